// Biological assemblies (ReadOptions::assembly) and every model of a file (read_models).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "fdmsurf/error.hpp"
#include "fdmsurf/structure.hpp"
#include "structure/structure_test_util.hpp"

namespace fdmsurf {
namespace {

using test::data_path;

// Chain A: two protein atoms (subchain A) and a water (subchain B). Assembly 1 applies the
// identity and a 20 Å shift along y to both subchains; assembly 2 the identity to A only.
std::string assembly_cif(bool with_assemblies = true) {
    std::string text = std::string(test::kCifAtomSiteHeader) +
                       "ATOM 1 C CA . ALA A 1 0.0 0.0 0.0 1.0 10.0 1 1\n"
                       "ATOM 2 N N . ALA A 1 1.5 0.0 0.0 1.0 10.0 1 1\n"
                       "HETATM 3 O O . HOH B . 5.0 0.0 0.0 1.0 10.0 101 1\n"
                       "#\n";
    if (!with_assemblies) return text;
    return text +
           "loop_\n"
           "_pdbx_struct_assembly.id\n_pdbx_struct_assembly.details\n"
           "_pdbx_struct_assembly.method_details\n_pdbx_struct_assembly.oligomeric_details\n"
           "_pdbx_struct_assembly.oligomeric_count\n"
           "1 author_defined_assembly ? dimeric 2\n"
           "2 software_defined_assembly PISA monomeric 1\n"
           "#\n"
           "loop_\n"
           "_pdbx_struct_assembly_gen.assembly_id\n_pdbx_struct_assembly_gen.oper_expression\n"
           "_pdbx_struct_assembly_gen.asym_id_list\n"
           "1 1,2 A,B\n"
           "2 1 A\n"
           "#\n"
           "loop_\n"
           "_pdbx_struct_oper_list.id\n_pdbx_struct_oper_list.type\n"
           "_pdbx_struct_oper_list.matrix[1][1]\n_pdbx_struct_oper_list.matrix[1][2]\n"
           "_pdbx_struct_oper_list.matrix[1][3]\n_pdbx_struct_oper_list.vector[1]\n"
           "_pdbx_struct_oper_list.matrix[2][1]\n_pdbx_struct_oper_list.matrix[2][2]\n"
           "_pdbx_struct_oper_list.matrix[2][3]\n_pdbx_struct_oper_list.vector[2]\n"
           "_pdbx_struct_oper_list.matrix[3][1]\n_pdbx_struct_oper_list.matrix[3][2]\n"
           "_pdbx_struct_oper_list.matrix[3][3]\n_pdbx_struct_oper_list.vector[3]\n"
           "1 'identity operation' 1 0 0 0 0 1 0 0 0 0 1 0\n"
           "2 'point symmetry operation' 1 0 0 0 0 1 0 20 0 0 1 0\n"
           "#\n";
}

// Two chains; REMARK 350 biomolecule 1 copies chain A by a 2-fold about z (x, y -> -x, -y).
std::string assembly_pdb() {
    return "REMARK 350 BIOMOLECULE: 1                                                       \n"
           "REMARK 350 AUTHOR DETERMINED BIOLOGICAL UNIT: DIMERIC                          \n"
           "REMARK 350 APPLY THE FOLLOWING TO CHAINS: A                                    \n"
           "REMARK 350   BIOMT1   1  1.000000  0.000000  0.000000        0.00000            \n"
           "REMARK 350   BIOMT2   1  0.000000  1.000000  0.000000        0.00000            \n"
           "REMARK 350   BIOMT3   1  0.000000  0.000000  1.000000        0.00000            \n"
           "REMARK 350   BIOMT1   2 -1.000000  0.000000  0.000000        0.00000            \n"
           "REMARK 350   BIOMT2   2  0.000000 -1.000000  0.000000        0.00000            \n"
           "REMARK 350   BIOMT3   2  0.000000  0.000000  1.000000        0.00000            \n" +
           test::pdb_atom("ATOM", 1, " CA ", ' ', "ALA", 'A', 1, 10.0, 0.0, 0.0, "C") +
           test::pdb_atom("ATOM", 2, " H  ", ' ', "ALA", 'A', 1, 11.0, 0.0, 0.0, "H") +
           test::pdb_atom("ATOM", 3, " CA ", ' ', "GLY", 'B', 1, 0.0, 30.0, 0.0, "C") + "END\n";
}

std::vector<float> ys(const Atoms& atoms) {
    std::vector<float> y;
    for (std::size_t i = 0; i < atoms.size(); ++i) y.push_back(atoms.xyz[3 * i + 1]);
    std::sort(y.begin(), y.end());
    return y;
}

TEST(Assembly, MmcifOperatorsCopyTheSubchainsBeforeSelection) {
    ReadOptions options;
    options.assembly = 1;
    const Structure s = read_structure_from_memory(assembly_cif(), "asm.cif", options);
    // 2 operators x 3 atoms; the water copies are then left out like the original.
    EXPECT_EQ(s.info.atoms_in_file, 6u);
    EXPECT_EQ(s.info.waters_skipped, 2u);
    ASSERT_EQ(s.atoms.size(), 4u);
    EXPECT_EQ(ys(s.atoms), (std::vector<float>{0.0f, 0.0f, 20.0f, 20.0f}));
    EXPECT_EQ(s.info.assembly, 1);
    EXPECT_EQ(s.info.assembly_name, "1");
    EXPECT_EQ(s.info.assemblies_in_file, 2u);
    EXPECT_EQ(s.info.assembly_operators, 2u);
    // Without auth_asym_id the chains are the label_asym_ids, A and B: 2 chains x 2 operators.
    EXPECT_EQ(s.info.assembly_chains, 4u);
    EXPECT_TRUE(s.info.warnings.empty());

    options.keep_waters = true;
    EXPECT_EQ(read_structure_from_memory(assembly_cif(), "asm.cif", options).atoms.size(), 6u);

    options.assembly = 2;  // the identity on subchain A alone: the water is not in it
    const Structure two = read_structure_from_memory(assembly_cif(), "asm.cif", options);
    EXPECT_EQ(two.info.atoms_in_file, 2u);
    EXPECT_EQ(two.atoms.size(), 2u);
    EXPECT_EQ(two.info.assembly_name, "2");

    // The default is the model as deposited.
    const Structure asu = read_structure_from_memory(assembly_cif(), "asm.cif");
    EXPECT_EQ(asu.atoms.size(), 2u);
    EXPECT_EQ(asu.info.assembly, 0);
    EXPECT_EQ(asu.info.assemblies_in_file, 2u);
    EXPECT_EQ(asu.info.assembly_chains, 0u);
}

TEST(Assembly, PdbRemark350AppliesToTheChainsItNames) {
    ReadOptions options;
    options.assembly = 1;
    const Structure s = read_structure_from_memory(assembly_pdb(), "asm.pdb", options);
    EXPECT_EQ(s.info.atoms_in_file, 4u);  // chain A twice; chain B is not in the assembly
    EXPECT_EQ(s.info.hydrogens_skipped, 2u);
    ASSERT_EQ(s.atoms.size(), 2u);
    std::vector<float> x = {s.atoms.xyz[0], s.atoms.xyz[3]};
    std::sort(x.begin(), x.end());
    EXPECT_FLOAT_EQ(x[0], -10.0f);
    EXPECT_FLOAT_EQ(x[1], 10.0f);
    EXPECT_EQ(s.info.assembly_chains, 2u);
    EXPECT_EQ(s.info.assembly_operators, 2u);
}

TEST(Assembly, OutOfRangeOrMissingAssembliesAreInvalidArguments) {
    ReadOptions options;
    options.assembly = 3;
    test::expect_memory_error(assembly_cif(), "asm.cif", ErrorCode::InvalidArgument,
                              {"asm.cif", "assembly 3", "2 assemblies", "ids 1, 2"}, options);
    options.assembly = 1;
    test::expect_memory_error(assembly_cif(false), "none.cif", ErrorCode::InvalidArgument,
                              {"none.cif", "assembly 1", "no assemblies", "_pdbx_struct_assembly"},
                              options);
    test::expect_error([&] { read_structure(data_path("1d3z.pdb.gz"), options); },
                       ErrorCode::InvalidArgument, {"1d3z.pdb.gz", "no assemblies", "REMARK 350"});
    test::expect_memory_error("0 0 0 1.7\n", "one.xyzr", ErrorCode::InvalidArgument,
                              {"one.xyzr", "assembly 1", "no assemblies"}, options);
    options.assembly = -1;
    test::expect_memory_error(assembly_cif(), "asm.cif", ErrorCode::InvalidArgument,
                              {"asm.cif", "assembly -1"}, options);
}

TEST(Assembly, ChainsTheModelLacksAreWarnings) {
    std::string text = assembly_cif();
    text.replace(text.find("1 1,2 A,B"), 9, "1 1,2 A,B,Z");
    ReadOptions options;
    options.assembly = 1;
    const Structure s = read_structure_from_memory(text, "z.cif", options);
    EXPECT_EQ(s.atoms.size(), 4u);
    ASSERT_EQ(s.info.warnings.size(), 2u);  // once per operator
    EXPECT_EQ(s.info.warnings[0], "z.cif: assembly 1: no subchain Z");
}

TEST(Assembly, ProductsOfOperatorsAreRefused) {
    std::string text = assembly_cif();
    text.replace(text.find("1 1,2 A,B"), 9, "1 '(1)(1,2)' A,B");
    ReadOptions options;
    options.assembly = 1;
    test::expect_memory_error(text, "product.cif", ErrorCode::Format,
                              {"product.cif", "assembly 1", "(1)(1,2)", "product"}, options);
    options.assembly = 2;  // the other assembly is fine
    EXPECT_EQ(read_structure_from_memory(text, "product.cif", options).atoms.size(), 2u);
}

TEST(Assembly, EmptySelectionNamesTheAssembly) {
    ReadOptions options;
    options.assembly = 1;
    options.keep_hydrogens = false;
    std::string text = assembly_pdb();
    // Only hydrogens in chain A: the assembly's two copies are both removed.
    text.erase(text.find("ATOM      1"),
               test::pdb_atom("ATOM", 1, " CA ", ' ', "ALA", 'A', 1, 10.0, 0.0, 0.0, "C").size());
    test::expect_memory_error(text, "h.pdb", ErrorCode::EmptySelection,
                              {"h.pdb", "assembly 1 of model 1 has 2 atoms", "2 hydrogens"},
                              options);
}

// 4YVS, EV71 capsid: 15 chains in the file, 12 operators: a 180-mer of 317,160 atoms.
TEST(Assembly, CapsidOf4yvsHasTheFullAtomCount) {
    const std::string path = std::string(FDMSURF_TEST_DATA_DIR) + "/4yvs.cif.gz";
    ReadOptions options;
    options.assembly = 1;
    const Structure s = read_structure(path, options);
    EXPECT_EQ(s.info.atoms_in_file, 317160u);
    EXPECT_EQ(s.atoms.size(), 317160u);
    EXPECT_EQ(s.info.assembly_chains, 180u);
    EXPECT_EQ(s.info.assembly_operators, 12u);
    EXPECT_EQ(s.info.assemblies_in_file, 1u);
    EXPECT_TRUE(s.info.warnings.empty());
    // A capsid: atoms on a shell about 300 Å across.
    float lo = 1e9f, hi = -1e9f;
    for (std::size_t i = 0; i < s.atoms.size(); ++i) {
        lo = std::min(lo, s.atoms.xyz[3 * i]);
        hi = std::max(hi, s.atoms.xyz[3 * i]);
    }
    EXPECT_GT(hi - lo, 250.0f);
    EXPECT_LT(hi - lo, 350.0f);
}

TEST(ReadModels, EveryModelOfAnNmrEnsemble) {
    ReadOptions all;
    all.model = kAllModels;
    const std::vector<Structure> models = read_models(data_path("1d3z.pdb.gz"), all);
    ASSERT_EQ(models.size(), 10u);
    for (std::size_t i = 0; i < models.size(); ++i) {
        EXPECT_EQ(models[i].info.model, static_cast<int>(i + 1));
        EXPECT_EQ(models[i].info.models_in_file, 10u);
        EXPECT_EQ(models[i].atoms.size(), 602u);
        EXPECT_EQ(models[i].info.hydrogens_skipped, 629u);
    }
    ReadOptions third;
    third.model = 3;
    const Structure m3 = read_structure(data_path("1d3z.pdb.gz"), third);
    EXPECT_EQ(models[2].atoms.xyz, m3.atoms.xyz);
    EXPECT_NE(models[1].atoms.xyz, m3.atoms.xyz);

    // One model asked for: a vector of one.
    const std::vector<Structure> one = read_models(data_path("1d3z.pdb.gz"), third);
    ASSERT_EQ(one.size(), 1u);
    EXPECT_EQ(one[0].info.model, 3);
    EXPECT_EQ(one[0].atoms.xyz, m3.atoms.xyz);
}

TEST(ReadModels, SingleModelFormatsGiveOneStructure) {
    ReadOptions all;
    all.model = kAllModels;
    EXPECT_EQ(read_models(data_path("1crn.xyzr"), all).size(), 1u);
    const std::vector<Structure> crambin = read_models(data_path("1crn.cif"), all);
    ASSERT_EQ(crambin.size(), 1u);
    EXPECT_EQ(crambin[0].info.model, 1);
    EXPECT_EQ(crambin[0].atoms.size(), 327u);
    const std::vector<Structure> mem = read_models_from_memory("0 0 0 1.7\n", "a.xyzr", all);
    ASSERT_EQ(mem.size(), 1u);
    EXPECT_EQ(mem[0].info.model, 1);
}

TEST(ReadModels, AssemblyOfEveryModel) {
    std::string text = std::string(test::kCifAtomSiteHeader) +
                       "ATOM 1 C CA . ALA A 1 0.0 0.0 0.0 1.0 10.0 1 1\n"
                       "ATOM 2 C CA . ALA A 1 3.0 0.0 0.0 1.0 10.0 1 2\n";
    std::string tail = assembly_cif();
    text += tail.substr(tail.find("#\nloop_\n_pdbx_struct_assembly.id"));
    ReadOptions options;
    options.model = kAllModels;
    options.assembly = 1;
    const std::vector<Structure> models = read_models_from_memory(text, "nmr.cif", options);
    ASSERT_EQ(models.size(), 2u);
    for (const Structure& s : models) {
        ASSERT_EQ(s.atoms.size(), 2u);
        EXPECT_EQ(ys(s.atoms), (std::vector<float>{0.0f, 20.0f}));
    }
    EXPECT_FLOAT_EQ(models[1].atoms.xyz[0], 3.0f);
}

TEST(ReadModels, ReadStructureRefusesAllModels) {
    ReadOptions all;
    all.model = kAllModels;
    test::expect_error([&] { read_structure(data_path("1d3z.pdb.gz"), all); },
                       ErrorCode::InvalidArgument, {"1d3z.pdb.gz", "model 0", "read_models"});
    ReadOptions bad;
    bad.model = -2;
    test::expect_error([&] { read_models(data_path("1d3z.pdb.gz"), bad); },
                       ErrorCode::InvalidArgument, {"model -2"});
    bad.model = 11;
    test::expect_error([&] { read_models(data_path("1d3z.pdb.gz"), bad); },
                       ErrorCode::InvalidArgument, {"model 11", "10 models"});
}

}  // namespace
}  // namespace fdmsurf
