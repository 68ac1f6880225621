// Lenient structure input (issue 33): files that gemmi, Biopython, MDAnalysis or PyMOL open are
// read, each with a warning that says what was assumed; bad input stays an error naming the line.
// The files are in tests/data/lenient/, small, each showing one feature.
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "fdmsurf/structure.hpp"
#include "structure/structure_test_util.hpp"

namespace fdmsurf {
namespace {

using test::data_path;
using test::expect_memory_error;
using test::read_text_file;

std::string lenient(const std::string& file) { return data_path("lenient/" + file); }

// The one warning that holds every one of `parts`.
void expect_warning(const StructureInfo& info, std::initializer_list<std::string_view> parts) {
    for (const std::string& w : info.warnings) {
        bool all = true;
        for (std::string_view p : parts) all = all && w.find(p) != std::string::npos;
        if (all) return;
    }
    std::string seen;
    for (const std::string& w : info.warnings) seen += "\n  " + w;
    ADD_FAILURE() << "no warning with all parts; warnings:" << seen;
}

ReadOptions keep_all() {
    ReadOptions o;
    o.keep_waters = o.keep_hydrogens = o.keep_ligands = true;
    return o;
}

TEST(StructureLenient, MmcifWithLabelItemsOnly) {
    Structure s = read_structure(lenient("label-only.cif"), keep_all());
    ASSERT_EQ(s.atoms.size(), 8u);
    expect_warning(s.info, {"label-only.cif", "no auth_seq_id", "label_seq_id", "from 3"});
    EXPECT_EQ(s.atoms.meta[0].chain, "A");
    EXPECT_EQ(s.atoms.meta[4].residue_number, 2);
    // The two waters ('.' for label_seq_id) are two residues, numbered after the polymer's.
    EXPECT_EQ(s.atoms.meta[6].chain, "B");
    EXPECT_EQ(s.atoms.meta[6].residue_number, 3);
    EXPECT_EQ(s.atoms.meta[7].residue_number, 4);
    EXPECT_FLOAT_EQ(s.atoms.xyz[3 * 7], 22.0f);
    // Waters are still told apart by the selection rules.
    Structure d = read_structure(lenient("label-only.cif"));
    EXPECT_EQ(d.atoms.size(), 6u);
    EXPECT_EQ(d.info.waters_skipped, 2u);
}

TEST(StructureLenient, MinimalMmcifGetsSerialsOccupancyAndB) {
    Structure s = read_structure(lenient("minimal.cif"));
    ASSERT_EQ(s.atoms.size(), 4u);
    expect_warning(s.info, {"no id", "row numbers"});
    expect_warning(s.info, {"no occupancy", "1 assumed"});
    expect_warning(s.info, {"no B_iso_or_equiv", "0 assumed"});
    expect_warning(s.info, {"no label_alt_id"});
    EXPECT_EQ(s.atoms.meta[3].serial, 4);
    EXPECT_FLOAT_EQ(s.atoms.meta[3].occupancy, 1.0f);
    EXPECT_FLOAT_EQ(s.atoms.meta[3].b_factor, 0.0f);
    EXPECT_EQ(s.atoms.element[1], "C");
    EXPECT_FLOAT_EQ(s.atoms.xyz[9], 15.268f);
}

TEST(StructureLenient, MmcifWithoutDataHeaderIsOneBlock) {
    std::string text = read_text_file(lenient("minimal.cif"));
    text.erase(0, text.find("loop_"));  // Biopython's test files keep tables without a header
    Structure s = read_structure_from_memory(text, "headless.cif");
    EXPECT_EQ(s.atoms.size(), 4u);
    expect_warning(s.info, {"headless.cif: no data_ header before the first item at line 1",
                            "one data block"});
}

TEST(StructureLenient, MmcifWithoutCoordinatesStaysAnError) {
    expect_memory_error(
        "data_x\nloop_\n_atom_site.type_symbol\n_atom_site.label_atom_id\n"
        "_atom_site.label_comp_id\n_atom_site.Cartn_x\n_atom_site.Cartn_y\nC CA GLY 1.0 2.0\n",
        "x.cif", ErrorCode::Format, {"x.cif: _atom_site lacks column(s) Cartn_z"});
}

TEST(StructureLenient, RepeatedModelNumbersInFileOrder) {
    ReadOptions all;
    all.model = kAllModels;
    std::vector<Structure> models = read_models(lenient("models-repeated.pdb"), all);
    ASSERT_EQ(models.size(), 2u);
    EXPECT_EQ(models[0].atoms.size(), 2u);
    EXPECT_EQ(models[1].atoms.size(), 3u);
    EXPECT_FLOAT_EQ(models[1].atoms.xyz[0], 18.047f);
    expect_warning(models[1].info, {"MODEL 1 at line 6 repeats a model number", "file order"});
}

TEST(StructureLenient, ModelWithoutEndmdlInFileOrder) {
    ReadOptions second;
    second.model = 2;
    Structure s = read_structure(lenient("model-no-endmdl.pdb"), second);
    EXPECT_EQ(s.info.models_in_file, 2u);
    ASSERT_EQ(s.atoms.size(), 3u);
    EXPECT_FLOAT_EQ(s.atoms.xyz[0], 18.047f);
    expect_warning(s.info, {"MODEL at line 5 follows a model without ENDMDL"});
}

TEST(StructureLenient, OldFormatTextInChargeColumnsIgnored) {
    Structure s = read_structure(lenient("old-charge.pdb"));
    ASSERT_EQ(s.atoms.size(), 3u);
    expect_warning(s.info,
                   {"old-charge.pdb: unreadable charge '1A' (columns 79-80) at line 3 (and 2 more)"});
    EXPECT_EQ(s.atoms.element[0], "N");
    EXPECT_EQ(s.atoms.meta[0].charge, 0.0f);
}

TEST(StructureLenient, OverflowedPdbFieldsReadFieldByField) {
    Structure s = read_structure(lenient("overflow.pdb"));
    ASSERT_EQ(s.atoms.size(), 6u);
    expect_warning(s.info, {"4 ATOM/HETATM record(s) with fields past their columns",
                            "the first at line 6"});
    const std::vector<float> expected = {17.047f,   14.099f,  3.625f, 16.967f,  12.784f, 4.338f,
                                         15.685f,   12.755f,  5.133f, 15.115f,  11.555f, 5.265f,
                                         -1000.125f, -1000.25f, 5.594f, 10000.5f, 10001.75f, 5.594f};
    for (std::size_t i = 0; i < expected.size(); ++i)
        EXPECT_NEAR(s.atoms.xyz[i], expected[i], 0.006f) << i;
    EXPECT_EQ(s.atoms.meta[2].serial, 100000);
    EXPECT_EQ(s.atoms.meta[2].residue_number, 9999);
    EXPECT_EQ(s.atoms.meta[3].residue_number, 10000);
    EXPECT_EQ(s.atoms.meta[3].name, "N");
    EXPECT_EQ(s.atoms.meta[3].residue_name, "GLY");
    EXPECT_EQ(s.atoms.element[5], "C");
}

TEST(StructureLenient, FiveDigitResidueOverInsertionCode) {
    // VMD keeps the columns and writes the fifth digit where the insertion code goes.
    std::string line =
        "ATOM      1  CA  GLY A10000     15.115  11.555   5.265  1.00 10.00           C\n";
    Structure s = read_structure_from_memory(line, "x.pdb");
    EXPECT_EQ(s.atoms.meta[0].residue_number, 10000);
    EXPECT_EQ(s.atoms.meta[0].insertion_code, ' ');
    EXPECT_FLOAT_EQ(s.atoms.xyz[0], 15.115f);
}

TEST(StructureLenient, OverflowThatDoesNotFitTheShapeIsRefused) {
    // A residue field that is no number, and coordinates of other decimals: no split is certain.
    expect_memory_error(
        "ATOM      1  CA  GLY A1x000      15.115  11.555   5.265  1.00 10.00           C\n",
        "x.pdb", ErrorCode::Format, {"x.pdb: non-numeric", "(columns", "at line 1"});
    expect_memory_error(
        "ATOM      1  CA  GLY A   1     -1000.12-1000.25   5.594  1.00 10.00           C\n",
        "x.pdb", ErrorCode::Format, {"y coordinate", "(columns 39-46) at line 1"});
    expect_memory_error(
        "ATOM      1  CA  GLY A   1      15.1x5  11.555   5.265  1.00 10.00           C\n",
        "x.pdb", ErrorCode::Format, {"non-numeric x coordinate '  15.1x5' (columns 31-38) at line 1"});
}

TEST(StructureLenient, FreeFormatRecordsReadByTheirFields) {
    Structure s = read_structure(lenient("free-format.pdb"));
    ASSERT_EQ(s.atoms.size(), 4u);
    expect_warning(s.info, {"4 ATOM/HETATM record(s) in free format", "the first at line 3"});
    const std::vector<float> expected = {17.047f, 14.099f, 3.625f, 16.967f, 12.784f, 4.338f,
                                         15.685f, 12.755f, 5.133f, -3.0f,   0.0f,    0.0f};
    for (std::size_t i = 0; i < expected.size(); ++i)
        EXPECT_NEAR(s.atoms.xyz[i], expected[i], 1e-4f) << i;
    EXPECT_EQ(s.atoms.meta[1].name, "CA");
    EXPECT_EQ(s.atoms.element[1], "C");  // CA in column 14: carbon, as in a standard file
    EXPECT_EQ(s.atoms.meta[1].chain, "A");
    EXPECT_EQ(s.atoms.meta[2].chain, "");  // no chain field
    EXPECT_EQ(s.atoms.meta[2].residue_number, 1);
    EXPECT_FLOAT_EQ(s.atoms.meta[2].b_factor, 2.0f);
    EXPECT_EQ(s.atoms.meta[3].residue_name, "ION");
    EXPECT_EQ(s.atoms.meta[3].residue_number, 2);
    // Fields of no such shape stay an error naming the line and columns.
    expect_memory_error(
        "ATOM      1  CA  GLY A   1       1.000   2.000   three  1.00  0.00           C\n",
        "x.pdb", ErrorCode::Format, {"x.pdb: non-numeric z coordinate", "(columns 47-54) at line 1"});
}

TEST(StructureLenient, ElementsFromNamesThatStartInColumn13) {
    Structure s = read_structure(lenient("amber-names.pdb"));
    expect_warning(s.info, {"4 atoms named from column 13 without an element symbol",
                            "e.g. CA in ALA (not Ca)"});
    expect_warning(s.info, {"3 atoms without an element symbol", "e.g. CH3 in ACE"});
    // HH31 and HG2 are hydrogens, left out as such; the calcium ion stays calcium.
    EXPECT_EQ(s.info.hydrogens_skipped, 3u);
    ASSERT_EQ(s.atoms.size(), 8u);
    const std::vector<std::string> elements = {"C", "C", "N", "C", "C", "C", "CA", "C"};
    EXPECT_EQ(s.atoms.element, elements);
    EXPECT_FLOAT_EQ(s.atoms.radius[3], vdw_radius("C"));
}

// Names that repeat with the same altloc letter are other atoms, not alternates (APBS's alkanes
// write the residue name a column left, so that its first letter reads as the altloc).
TEST(StructureLenient, RepeatedNamesOfOneAltlocAreAtoms) {
    std::string text =
        "ATOM      1  C  ALK      1       1.437  -1.308   0.657 0.000 1.908\n"
        "ATOM      2  C  ALK      1       0.739   0.054   0.519 0.000 1.908\n"
        "ATOM      3  C  ALK      1      -0.716  -0.170   0.083 0.000 1.908\n";
    Structure s = read_structure_from_memory(text, "alk.pdb");
    EXPECT_EQ(s.atoms.size(), 3u);
    EXPECT_EQ(s.info.altlocs_skipped, 0u);
    text[16 + 2 * 68] = 'B';  // a true alternate of the first atom: left out
    Structure t = read_structure_from_memory(text, "alk.pdb");
    EXPECT_EQ(t.atoms.size(), 2u);
    EXPECT_EQ(t.info.altlocs_skipped, 1u);
}

TEST(StructureLenient, PqrInFixedColumnsWithoutChain) {
    Structure s = read_structure(lenient("columns.pqr"));
    ASSERT_EQ(s.atoms.size(), 4u);
    expect_warning(s.info, {"4 record(s) read in PDB's fixed columns", "line 3"});
    EXPECT_FLOAT_EQ(s.atoms.xyz[0], 1999.323f);
    EXPECT_FLOAT_EQ(s.atoms.xyz[1], 2998.770f);
    EXPECT_FLOAT_EQ(s.atoms.xyz[2], -900.490f);
    EXPECT_FLOAT_EQ(s.atoms.radius[3], 1.6612f);
    EXPECT_FLOAT_EQ(s.atoms.meta[3].charge, -0.5679f);
    EXPECT_EQ(s.atoms.meta[3].chain, "");
    EXPECT_EQ(s.atoms.meta[3].residue_number, 1);
    EXPECT_EQ(s.atoms.element[1], "C");
}

TEST(StructureLenient, PqrWithAllRadiiZeroUsesElementRadii) {
    Structure s = read_structure(lenient("zero-radii.pqr"));
    ASSERT_EQ(s.atoms.size(), 5u);
    expect_warning(s.info, {"all 5 atoms have radius 0", "element radii",
                            "kept as soon as one atom has a radius above 0"});
    EXPECT_FLOAT_EQ(s.atoms.radius[0], vdw_radius("N"));
    EXPECT_FLOAT_EQ(s.atoms.radius[4], vdw_radius("S"));
    EXPECT_EQ(s.info.zero_radius_skipped, 0u);
    // One atom with a radius: the file's radii, the others left out as before.
    std::string text = read_text_file(lenient("zero-radii.pqr"));
    text.replace(text.find("0.5973 0.0000"), 13, "0.5973 1.9080");
    Structure t = read_structure_from_memory(text, "one.pqr");
    EXPECT_EQ(t.atoms.size(), 1u);
    EXPECT_EQ(t.info.zero_radius_skipped, 4u);
}

TEST(StructureLenient, AllWaterNamesTheCliOption) {
    std::string text = test::pdb_atom("HETATM", 1, "O", ' ', "HOH", 'A', 1, 1, 2, 3, "O") +
                       test::pdb_atom("HETATM", 2, "O", ' ', "HOH", 'A', 2, 4, 2, 3, "O");
    expect_memory_error(text, "w.pdb", ErrorCode::EmptySelection,
                        {"w.pdb: no atoms left after selection", "2 water atoms",
                         "--waters"});
}

}  // namespace
}  // namespace fdmsurf
