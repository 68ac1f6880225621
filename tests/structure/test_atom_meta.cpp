// Tests of atom metadata: what each reader records, XYZRN input, chains, selections, subsets.
#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <string>
#include <vector>

#include "fdmsurf/structure.hpp"
#include "structure/structure_test_util.hpp"

namespace fdmsurf {
namespace {

using test::data_path;
using test::expect_error;
using test::expect_memory_error;
using test::pdb_atom;

std::size_t count(const std::vector<std::uint8_t>& mask) {
    return static_cast<std::size_t>(std::count(mask.begin(), mask.end(), std::uint8_t{1}));
}

std::size_t count_chain(const Atoms& atoms, const std::string& chain) {
    return static_cast<std::size_t>(std::count_if(
        atoms.meta.begin(), atoms.meta.end(), [&](const AtomMeta& m) { return m.chain == chain; }));
}

void expect_same_meta(const AtomMeta& a, const AtomMeta& b, std::size_t i) {
    SCOPED_TRACE("atom " + std::to_string(i));
    EXPECT_EQ(a.serial, b.serial);
    EXPECT_EQ(a.name, b.name);
    EXPECT_EQ(a.residue_name, b.residue_name);
    EXPECT_EQ(a.residue_number, b.residue_number);
    EXPECT_EQ(a.insertion_code, b.insertion_code);
    EXPECT_EQ(a.chain, b.chain);
    EXPECT_EQ(a.hetero, b.hetero);
    EXPECT_FLOAT_EQ(a.b_factor, b.b_factor);
    EXPECT_FLOAT_EQ(a.occupancy, b.occupancy);
    EXPECT_FLOAT_EQ(a.charge, b.charge);
    EXPECT_EQ(a.has_charge, b.has_charge);
}

// --- what the readers record ---

TEST(AtomMeta, PdbAndMmcifOfCrambinGiveTheSameMetadataForEveryAtom) {
    const Atoms pdb = read_structure(data_path("1crn.pdb")).atoms;
    const Atoms cif = read_structure(data_path("1crn.cif")).atoms;
    ASSERT_EQ(pdb.size(), 327u);
    ASSERT_EQ(pdb.meta.size(), 327u);
    ASSERT_EQ(cif.meta.size(), 327u);
    for (std::size_t i = 0; i < pdb.size(); ++i) expect_same_meta(pdb.meta[i], cif.meta[i], i);
    // ATOM      1  N   THR A   1      17.047  14.099   3.625  1.00 13.79           N
    const AtomMeta& first = pdb.meta.front();
    EXPECT_EQ(first.serial, 1);
    EXPECT_EQ(first.name, "N");
    EXPECT_EQ(first.residue_name, "THR");
    EXPECT_EQ(first.residue_number, 1);
    EXPECT_EQ(first.insertion_code, ' ');
    EXPECT_EQ(first.chain, "A");
    EXPECT_FALSE(first.hetero);
    EXPECT_FLOAT_EQ(first.b_factor, 13.79f);
    EXPECT_FLOAT_EQ(first.occupancy, 1.0f);
    EXPECT_FLOAT_EQ(first.charge, 0.0f);
    EXPECT_FALSE(first.has_charge);
    // ATOM    327  OXT ASN A  46      12.703   4.973  10.746  1.00  7.86           O
    const AtomMeta& last = pdb.meta.back();
    EXPECT_EQ(last.serial, 327);
    EXPECT_EQ(last.name, "OXT");
    EXPECT_EQ(last.residue_name, "ASN");
    EXPECT_EQ(last.residue_number, 46);
    EXPECT_FLOAT_EQ(last.b_factor, 7.86f);
    for (std::size_t i = 0; i < pdb.size(); ++i)
        ASSERT_EQ(pdb.meta[i].serial, static_cast<std::int32_t>(i + 1)) << "serials in order";
}

TEST(AtomMeta, PdbHetatmInsertionCodeOccupancyAndFormalCharge) {
    std::string zinc = pdb_atom("HETATM", 7, "ZN", ' ', " ZN", 'B', 301, 1, 2, 3, "ZN");
    zinc.replace(zinc.size() - 1, 1, "2+\n");  // columns 79-80
    std::string inserted = pdb_atom("ATOM", 5, " CA", ' ', "GLY", 'A', 52, 4, 5, 6, "C");
    inserted[26] = 'A';                 // insertion code, column 27
    inserted.replace(54, 6, "  0.50");  // occupancy, columns 55-60
    const Structure s = read_structure_from_memory(inserted + zinc, "small.pdb");
    ASSERT_EQ(s.atoms.meta.size(), 2u);
    const AtomMeta& ca = s.atoms.meta[0];
    EXPECT_EQ(ca.serial, 5);
    EXPECT_EQ(ca.residue_number, 52);
    EXPECT_EQ(ca.insertion_code, 'A');
    EXPECT_FLOAT_EQ(ca.occupancy, 0.5f);
    EXPECT_FLOAT_EQ(ca.b_factor, 10.0f);
    EXPECT_FALSE(ca.hetero);
    const AtomMeta& zn = s.atoms.meta[1];
    EXPECT_EQ(zn.name, "ZN");
    EXPECT_EQ(zn.residue_name, "ZN");
    EXPECT_EQ(zn.chain, "B");
    EXPECT_TRUE(zn.hetero);
    EXPECT_FLOAT_EQ(zn.charge, 2.0f);
    EXPECT_FALSE(zn.has_charge);  // a formal charge, not a partial one
}

TEST(AtomMeta, AltlocsWatersAndHydrogensLeftOutTakeTheirMetadataWithThem) {
    const std::string text = pdb_atom("ATOM", 1, " N", ' ', "ALA", 'A', 1, 0, 0, 0, "N") +
                             pdb_atom("ATOM", 2, " CA", 'A', "ALA", 'A', 1, 1, 0, 0, "C") +
                             pdb_atom("ATOM", 3, " CA", 'B', "ALA", 'A', 1, 1, 1, 0, "C") +
                             pdb_atom("ATOM", 4, " H", ' ', "ALA", 'A', 1, 0, 1, 0, "H") +
                             pdb_atom("HETATM", 5, " O", ' ', "HOH", 'A', 9, 5, 5, 5, "O");
    const Structure s = read_structure_from_memory(text, "alt.pdb");
    ASSERT_EQ(s.atoms.size(), 2u);
    ASSERT_EQ(s.atoms.meta.size(), 2u);
    EXPECT_EQ(s.atoms.meta[0].serial, 1);
    EXPECT_EQ(s.atoms.meta[1].serial, 2);
}

TEST(AtomMeta, AssemblyCopiesCarryTheCopiesChainNames) {
    ReadOptions o;
    o.assembly = 1;
    const Structure s = read_structure(data_path("3al1.pdb"), o);
    ASSERT_EQ(s.atoms.meta.size(), s.atoms.size());
    std::vector<std::string> chains;
    for (const AtomMeta& m : s.atoms.meta)
        if (std::find(chains.begin(), chains.end(), m.chain) == chains.end())
            chains.push_back(m.chain);
    // REMARK 350 applies one (identity) operator to chains A and B; gemmi names copies A1, B1.
    EXPECT_EQ(chains, (std::vector<std::string>{"A1", "B1"}));
    o.chains = {"B1"};
    const Structure b = read_structure(data_path("3al1.pdb"), o);
    EXPECT_EQ(b.atoms.size(), count_chain(s.atoms, "B1"));
    o.chains = {"A"};
    expect_error([&] { read_structure(data_path("3al1.pdb"), o); }, ErrorCode::InvalidArgument,
                 {"chain A is not in assembly 1 of model 1", "chains present: A1, B1"});
}

TEST(AtomMeta, PqrCarriesChargesResiduesAndChainsWhereTheLinesHaveThem) {
    const char* text =
        "REMARK   1 PQR file\n"
        "ATOM      1  N   MET A   1     -12.000   3.500  -0.25 -0.3000 1.8240\n"
        "ATOM      2  CA  MET     2     -11.000   3.500  -0.25  0.2100 1.9080\n"
        "ATOM      3  HA  MET B  52A    -10.5 4.0 0.5 0.1 0.0\n"
        "ATOM      4  CB  LYS C1000     -9.0 4.0 0.5 0.05 1.9\n"
        "HETATM    5 ZN    ZN    -3      1.000   2.000   3.000  2.0000 1.1000\n";
    const Structure s = read_structure_from_memory(text, "small.pqr");
    ASSERT_EQ(s.atoms.size(), 4u);  // HA has radius 0: left out, with its metadata
    ASSERT_EQ(s.atoms.meta.size(), 4u);
    const AtomMeta& n = s.atoms.meta[0];
    EXPECT_EQ(n.serial, 1);
    EXPECT_EQ(n.name, "N");
    EXPECT_EQ(n.residue_name, "MET");
    EXPECT_EQ(n.chain, "A");
    EXPECT_EQ(n.residue_number, 1);
    EXPECT_FLOAT_EQ(n.charge, -0.3f);
    EXPECT_TRUE(n.has_charge);
    EXPECT_FLOAT_EQ(n.b_factor, 0.0f);
    EXPECT_FLOAT_EQ(n.occupancy, 1.0f);
    EXPECT_FALSE(n.hetero);
    EXPECT_EQ(s.atoms.meta[1].chain, "");
    EXPECT_EQ(s.atoms.meta[1].residue_number, 2);
    EXPECT_FLOAT_EQ(s.atoms.meta[1].charge, 0.21f);
    // A one-letter chain glued to a four-digit residue number, as fixed columns write it.
    EXPECT_EQ(s.atoms.meta[2].chain, "C");
    EXPECT_EQ(s.atoms.meta[2].residue_number, 1000);
    EXPECT_EQ(s.atoms.meta[2].serial, 4);
    const AtomMeta& zn = s.atoms.meta[3];
    EXPECT_TRUE(zn.hetero);
    EXPECT_EQ(zn.residue_number, -3);
    EXPECT_FLOAT_EQ(zn.charge, 2.0f);

    const Structure icode =
        read_structure_from_memory("ATOM 7 CA GLY B 52A 1 2 3 0.1 1.9\n", "icode.pqr");
    EXPECT_EQ(icode.atoms.meta[0].residue_number, 52);
    EXPECT_EQ(icode.atoms.meta[0].insertion_code, 'A');
    EXPECT_EQ(icode.atoms.meta[0].chain, "B");
}

TEST(AtomMeta, PqrResidueNumberMustBeANumber) {
    expect_memory_error("ATOM 1 N MET A 1 1 2 3 0 1.5\nATOM 2 CA MET A x1 1 2 3 0 1.5\n", "bad.pqr",
                        ErrorCode::Format,
                        {"bad.pqr", "non-numeric residue number 'x1' at line 2"});
}

TEST(AtomMeta, XyzrHasNoMetadata) {
    const Structure s = read_structure(data_path("1crn.xyzr"));
    EXPECT_EQ(s.atoms.size(), 327u);
    EXPECT_TRUE(s.atoms.meta.empty());
}

// --- XYZRN ---

TEST(Xyzrn, NameIsTheLastFieldAndTheElementComesFromMsmsNames) {
    const char* text =
        "# x y z r n name\n"
        "1 2 3 1.55 1 A_23_x_LYS_NZ_Blue\n"
        "\n"
        "4 5 6 1.70 CA\n"                  // five fields: the fifth is the name
        "7 8 9 1.80\n"                     // no name
        "1 1 1 0 1 A_23_x_LYS_HZ1_Blue\n"  // radius 0: left out
        "2 2 2 1.39 1 B_301_x_ZN_ZN_Green\n"
        "3 3 3 1.70 1 _-4_B_ALA_CB_Green\n";  // blank chain, negative number, insertion code
    const Structure s = read_structure_from_memory(text, "small.xyzrn");
    EXPECT_EQ(s.info.format, StructureFormat::Xyzrn);
    ASSERT_EQ(s.atoms.size(), 5u);
    ASSERT_EQ(s.atoms.meta.size(), 5u);
    EXPECT_EQ(s.atoms.xyz, (std::vector<float>{1, 2, 3, 4, 5, 6, 7, 8, 9, 2, 2, 2, 3, 3, 3}));
    EXPECT_EQ(s.atoms.radius, (std::vector<float>{1.55f, 1.70f, 1.80f, 1.39f, 1.70f}));
    std::vector<std::string> fields, names, chains, residues;
    for (const AtomMeta& m : s.atoms.meta) {
        fields.push_back(m.xyzrn_name);
        names.push_back(m.name);
        chains.push_back(m.chain);
        residues.push_back(m.residue_name);
    }
    EXPECT_EQ(fields, (std::vector<std::string>{"A_23_x_LYS_NZ_Blue", "CA", "",
                                                "B_301_x_ZN_ZN_Green", "_-4_B_ALA_CB_Green"}));
    // MSMS-style names give chain, residue and atom name; others stay whole as the atom name.
    EXPECT_EQ(names, (std::vector<std::string>{"NZ", "CA", "", "ZN", "CB"}));
    EXPECT_EQ(chains, (std::vector<std::string>{"A", "", "", "B", ""}));
    EXPECT_EQ(residues, (std::vector<std::string>{"LYS", "", "", "ZN", "ALA"}));
    EXPECT_EQ(s.atoms.element, (std::vector<std::string>{"N", "", "", "ZN", "C"}));
    EXPECT_EQ(s.atoms.meta[0].residue_number, 23);
    EXPECT_EQ(s.atoms.meta[0].insertion_code, ' ');  // 'x': none
    EXPECT_EQ(s.atoms.meta[4].residue_number, -4);
    EXPECT_EQ(s.atoms.meta[4].insertion_code, 'B');
    // The serial is the sphere's number among the sphere lines (MSMS's atom number): the
    // radius-0 sphere keeps its number 4.
    std::vector<std::int32_t> serials;
    for (const AtomMeta& m : s.atoms.meta) serials.push_back(m.serial);
    EXPECT_EQ(serials, (std::vector<std::int32_t>{1, 2, 3, 5, 6}));
    EXPECT_EQ(s.info.warnings.size(), 1u);
}

TEST(Xyzrn, CrambinFileHasThePdbAtomsAndMsmsNames) {
    const Structure pdb = read_structure(data_path("1crn.pdb"));
    const Structure s = read_structure(data_path("1crn.xyzrn"));
    EXPECT_EQ(s.info.format, StructureFormat::Xyzrn);
    ASSERT_EQ(s.atoms.size(), 327u);
    EXPECT_EQ(s.atoms.xyz, pdb.atoms.xyz);
    EXPECT_EQ(s.atoms.radius, pdb.atoms.radius);
    EXPECT_EQ(s.atoms.element, pdb.atoms.element);
    EXPECT_EQ(s.atoms.meta.front().xyzrn_name, "A_1_x_THR_N_Blue");
    EXPECT_EQ(s.atoms.meta.back().xyzrn_name, "A_46_x_ASN_OXT_Red");
    // The names carry what the PDB file says of each atom.
    for (std::size_t i = 0; i < s.atoms.size(); ++i) {
        ASSERT_EQ(s.atoms.meta[i].name, pdb.atoms.meta[i].name) << i;
        ASSERT_EQ(s.atoms.meta[i].residue_name, pdb.atoms.meta[i].residue_name) << i;
        ASSERT_EQ(s.atoms.meta[i].residue_number, pdb.atoms.meta[i].residue_number) << i;
        ASSERT_EQ(s.atoms.meta[i].chain, pdb.atoms.meta[i].chain) << i;
    }
    // So selections work on it as on the PDB file.
    EXPECT_EQ(match_selection(s.atoms, "A/*/CA"), match_selection(pdb.atoms, "A/*/CA"));
}

TEST(Xyzrn, DetectedByContentWhenTheLastFieldIsNotANumber) {
    EXPECT_EQ(read_structure_from_memory("# atoms\n1 2 3 1.5 1 A_1_x_GLY_CA_Green\n", "atoms")
                  .info.format,
              StructureFormat::Xyzrn);
    EXPECT_EQ(read_structure_from_memory("1 2 3 1.5 CA\n", "atoms.txt").info.format,
              StructureFormat::Xyzrn);
    // Plain numbers stay unrecognised, as XYZR always was without its extension.
    expect_memory_error("1 2 3 1.5 1\n", "atoms.txt", ErrorCode::Format,
                        {"unknown format", ".xyzrn"});
    ReadOptions o;
    o.format = StructureFormat::Xyzrn;
    EXPECT_EQ(read_structure_from_memory("1 2 3 1.5\n", "atoms.xyzr", o).info.format,
              StructureFormat::Xyzrn);
}

TEST(Xyzrn, ShortOrBadLinesAreFormatErrorsWithTheirLine) {
    expect_memory_error("1 2 3 1.5 1 A\n4 5 6\n", "short.xyzrn", ErrorCode::Format,
                        {"short.xyzrn", "too few fields for an XYZRN atom at line 2", "(3;"});
    expect_memory_error("1 2 x 1.5 1 A\n", "text.xyzrn", ErrorCode::Format,
                        {"text.xyzrn", "non-numeric z coordinate 'x' at line 1"});
    expect_memory_error("1 2 3 -1 1 A\n", "neg.xyzrn", ErrorCode::Format,
                        {"radius -1 is not > 0 at line 1"});
    expect_memory_error("# only a comment\n", "none.xyzrn", ErrorCode::Format,
                        {"none.xyzrn", "no atoms"});
    expect_memory_error("1 2 3 0 1 A\n", "zero.xyzrn", ErrorCode::EmptySelection,
                        {"zero.xyzrn", "radius 0"});
}

// --- ReadOptions::chains ---

TEST(Chains, KeepOnlyTheNamedChainsOf3al1) {
    const Structure all = read_structure(data_path("3al1.pdb"));
    ReadOptions o;
    o.chains = {"A"};
    const Structure a = read_structure(data_path("3al1.pdb"), o);
    // Counted from the file with awk: chain A, no hydrogens, the first altloc of each atom.
    EXPECT_EQ(a.atoms.size(), 102u);
    EXPECT_EQ(count_chain(a.atoms, "A"), a.atoms.size());
    EXPECT_EQ(a.atoms.size(), count_chain(all.atoms, "A"));
    EXPECT_EQ(a.info.atoms_in_file, all.info.atoms_in_file);
    o.chains = {"B", "A"};
    const Structure ab = read_structure(data_path("3al1.pdb"), o);
    EXPECT_EQ(ab.atoms.size(), 204u);
    // File order is kept, whatever the order of the list.
    EXPECT_EQ(ab.atoms.meta.front().chain, "A");
    EXPECT_EQ(ab.atoms.meta.back().chain, "B");
    EXPECT_LT(ab.atoms.size(), all.atoms.size());  // the ligands without a chain id are gone
}

TEST(Chains, UnknownChainIsAnInvalidArgumentListingTheChainsPresent) {
    ReadOptions o;
    o.chains = {"Q"};
    expect_error([&] { read_structure(data_path("1crn.pdb"), o); }, ErrorCode::InvalidArgument,
                 {"1crn.pdb: chain Q is not in model 1; chains present: A"});
    expect_error([&] { read_structure(data_path("1crn.cif"), o); }, ErrorCode::InvalidArgument,
                 {"chain Q is not in model 1; chains present: A"});
    o.chains = {"A", "a", "C"};  // case-sensitive
    expect_error([&] { read_structure(data_path("3al1.pdb"), o); }, ErrorCode::InvalidArgument,
                 {"chains a, C are not in model 1", "chains present: A, B, (blank)"});
}

TEST(Chains, PqrNeedsChainIds) {
    const char* with = "ATOM 1 N MET A 1 1 2 3 -0.3 1.8\nATOM 2 N MET B 1 4 5 6 -0.3 1.8\n";
    ReadOptions o;
    o.chains = {"B"};
    const Structure b = read_structure_from_memory(with, "ab.pqr", o);
    ASSERT_EQ(b.atoms.size(), 1u);
    EXPECT_EQ(b.atoms.xyz[0], 4.0f);
    EXPECT_EQ(b.atoms.element, (std::vector<std::string>{"N"}));
    o.chains = {"Z"};
    expect_memory_error(with, "ab.pqr", ErrorCode::InvalidArgument,
                        {"ab.pqr: chain Z is not in the file; chains present: A, B"}, o);
    expect_memory_error("ATOM 1 N MET 1 1 2 3 -0.3 1.8\n", "nochain.pqr",
                        ErrorCode::InvalidArgument,
                        {"nochain.pqr", "chains Z requested", "no chain ids"}, o);
}

TEST(Chains, XyzrCannotBeFilteredByChainOrSelectionXyzrnWithMsmsNamesCan) {
    ReadOptions chains;
    chains.chains = {"A"};
    expect_error([&] { read_structure(data_path("1crn.xyzr"), chains); },
                 ErrorCode::InvalidArgument, {"1crn.xyzr: chains needs", "xyzr input"});
    ReadOptions select;
    select.select = "A/*/CA";
    EXPECT_EQ(read_structure(data_path("1crn.xyzrn"), select).atoms.size(), 46u);
    EXPECT_EQ(read_structure(data_path("1crn.xyzrn"), chains).atoms.size(), 327u);
    chains.chains = {"B"};
    expect_error([&] { read_structure(data_path("1crn.xyzrn"), chains); },
                 ErrorCode::InvalidArgument, {"chain B is not in", "chains present: A"});
}

// --- selections ---

TEST(Selection, CountsOnCrambinMatchHandCountedNumbers) {
    const Atoms atoms = read_structure(data_path("1crn.pdb")).atoms;
    // Counted in 1crn.pdb with awk (46 residues, 6 cysteines, residues 10-20, B > 15 Å²).
    EXPECT_EQ(count(match_selection(atoms, "A/*/CA")), 46u);
    EXPECT_EQ(count(match_selection(atoms, "CA[C]")), 46u);
    EXPECT_EQ(count(match_selection(atoms, "/1/*/*/CA")), 46u);
    EXPECT_EQ(count(match_selection(atoms, "[S]")), 6u);
    EXPECT_EQ(count(match_selection(atoms, "(CYS)")), 36u);
    EXPECT_EQ(count(match_selection(atoms, "A/10-20")), 87u);
    EXPECT_EQ(count(match_selection(atoms, ";b>15")), 5u);
    EXPECT_EQ(count(match_selection(atoms, "/1/A")), 327u);
    EXPECT_EQ(count(match_selection(atoms, "")), 327u);
    EXPECT_EQ(count(match_selection(atoms, "/2")), 0u);  // the atoms are model 1
    EXPECT_EQ(count(match_selection(atoms, "B")), 0u);
    EXPECT_EQ(count(match_selection(atoms, ";polymer")), 327u);
    EXPECT_EQ(count(match_selection(atoms, ";solvent")), 0u);
    EXPECT_EQ(count(match_selection(atoms, "!A")), 0u);
    const std::vector<std::uint8_t> ca = match_selection(atoms, "A/*/CA");
    ASSERT_EQ(ca.size(), atoms.size());
    EXPECT_EQ(ca[0], 0);  // N of THR 1
    EXPECT_EQ(ca[1], 1);  // CA of THR 1
}

TEST(Selection, ExamplesOfTheDocsSelectWhatTheySay) {
    const Atoms atoms = read_structure(data_path("1crn.pdb")).atoms;
    const std::vector<std::pair<const char*, std::size_t>> examples = {
        {"A", 327},          {"A,B", 327},    {"A/10-10", 11},    {"A/10A-10A", 0},
        {"A/(CYS,MET)", 36}, {"[!C,N,O]", 6}, {"A/(CYS)/[S]", 6}, {"*/*/N,CA,C,O", 184},
        {"A/1-10;b>10", 12}, {";q<0.5", 0},   {";!solvent", 327}};
    // gemmi 0.5.7 reads a residue number without '-' as "from there on": 268 atoms from 10.
    EXPECT_EQ(count(match_selection(atoms, "A/10")), 268u);
    for (const auto& [expr, n] : examples)
        EXPECT_EQ(count(match_selection(atoms, expr)), n) << expr;
    // Counted with awk: residue 10 is ARG (11 atoms), 12 atoms of residues 1-10 have B > 10 Å²;
    // the backbone has 4 atoms in each of 46 residues.
    EXPECT_EQ(atoms.meta[count(match_selection(atoms, "A/1-9"))].residue_name, "ARG");
}

TEST(Selection, SelectOptionKeepsWhatMatchSelectionMatches) {
    const Atoms all = read_structure(data_path("1crn.cif")).atoms;
    for (const char* expr : {"A/10-20", "A/*/CA", "A/(CYS)/[S]", ";b>15"}) {
        SCOPED_TRACE(expr);
        ReadOptions o;
        o.select = expr;
        const Structure s = read_structure(data_path("1crn.cif"), o);
        const Atoms expected = subset(all, match_selection(all, expr));
        EXPECT_EQ(s.atoms.xyz, expected.xyz);
        EXPECT_EQ(s.atoms.radius, expected.radius);
        EXPECT_EQ(s.atoms.element, expected.element);
        ASSERT_EQ(s.atoms.meta.size(), expected.meta.size());
        for (std::size_t i = 0; i < s.atoms.size(); ++i)
            expect_same_meta(s.atoms.meta[i], expected.meta[i], i);
    }
}

TEST(Selection, SelectAppliesAfterTheOtherRulesAndTheChains) {
    ReadOptions o;
    o.select = "(HOH)";
    o.keep_waters = true;
    const Structure waters = read_structure(data_path("3al1.pdb"), o);
    EXPECT_EQ(waters.atoms.size(), 21u);  // 21 waters (30 records, altlocs), chain id blank
    o.keep_waters = false;
    expect_error([&] { read_structure(data_path("3al1.pdb"), o); }, ErrorCode::EmptySelection,
                 {"3al1.pdb: no atoms left after selection", "water atoms (keep_waters, the CLI's --waters)",
                  "not matching select '(HOH)'"});
    o.select = "A,B/*/CA";
    o.chains = {"B"};
    const Structure b = read_structure(data_path("3al1.pdb"), o);
    EXPECT_EQ(b.atoms.size(), 12u);  // 12 residues with a CA in chain B (not ACE)
    EXPECT_EQ(count_chain(b.atoms, "B"), b.atoms.size());
}

TEST(Selection, ModelNumberIsTheModelRead) {
    ReadOptions o;
    o.model = 2;
    o.select = "/2";
    const Structure two = read_structure(data_path("1d3z.pdb.gz"), o);
    EXPECT_EQ(two.info.model, 2);
    EXPECT_EQ(two.atoms.size(), 602u);
    o.select = "/1";
    expect_error([&] { read_structure(data_path("1d3z.pdb.gz"), o); }, ErrorCode::EmptySelection,
                 {"602 atoms not matching select '/1'"});
}

TEST(Selection, PqrIsSelectedOnItsMetadata) {
    const char* text =
        "ATOM 1 N MET A 1 1 2 3 -0.3 1.8\n"
        "ATOM 2 CA MET A 1 2 2 3 0.2 1.9\n"
        "ATOM 3 CA GLY A 2 3 2 3 0.2 1.9\n"
        "HETATM 4 O HOH W 9 8 8 8 -0.8 1.5\n";
    ReadOptions o;
    o.select = "*/*/CA";
    EXPECT_EQ(read_structure_from_memory(text, "s.pqr", o).atoms.size(), 2u);
    o.select = "(HOH)";
    EXPECT_EQ(read_structure_from_memory(text, "s.pqr", o).atoms.meta[0].serial, 4);
    o.select = ";solvent";
    EXPECT_EQ(read_structure_from_memory(text, "s.pqr", o).atoms.size(), 1u);
    o.select = "(ALA)";
    expect_memory_error(text, "s.pqr", ErrorCode::EmptySelection,
                        {"s.pqr: no atoms left after selection", "4 atoms not matching select"}, o);
}

TEST(Selection, BadSyntaxIsAnInvalidArgumentWithGemmisMessageAndAHint) {
    ReadOptions o;
    o.select = "CA[Qq]";
    expect_error([&] { read_structure(data_path("1crn.pdb"), o); }, ErrorCode::InvalidArgument,
                 {"1crn.pdb: bad selection 'CA[Qq]'", "Invalid selection syntax",
                  "gemmi selection syntax", "A/10-50"});
    const Atoms atoms = read_structure(data_path("1crn.pdb")).atoms;
    expect_error([&] { match_selection(atoms, "A/1-2/CA;x=1"); }, ErrorCode::InvalidArgument,
                 {"selection: bad selection 'A/1-2/CA;x=1'", "Invalid selection syntax"});
    // Syntax is checked before the text is parsed.
    expect_memory_error("not a structure", "x.pdb", ErrorCode::InvalidArgument,
                        {"x.pdb: bad selection"}, o);
}

TEST(Selection, OddExpressionsNeverCrash) {
    const Atoms atoms = read_structure(data_path("1crn.pdb")).atoms;
    for (const char* expr :
         {"/",   "//",    "///",        "////", "/*",  "(",      ")",          "()",
          "[",   "[]",    "]",          ":",    ";",   ";;",     "-",          "1-",
          "-5",  ".",     "*.",         "(ALA", "A/(", "A/1-2/", "A/1-2/CA[",  "A/1-2/CA[C",
          "[C,", "!",     "!!",         ";b",   ";b>", ";b>x",   ";q<0.5;b>1", "/x",
          "/1x", "A//CA", "*/*/*[*]:*", " ",    "A B", "\t"}) {
        SCOPED_TRACE(expr);
        try {
            EXPECT_EQ(match_selection(atoms, expr).size(), atoms.size());
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << e.what();
        }
    }
}

TEST(Selection, AtomsWithoutMetadataAreRefused) {
    const Atoms xyzr = read_structure(data_path("1crn.xyzr")).atoms;
    expect_error([&] { match_selection(xyzr, "A"); }, ErrorCode::InvalidArgument,
                 {"needs atom metadata", "327 atoms"});
    EXPECT_TRUE(match_selection(Atoms{}, "A").empty());
}

// --- subset ---

TEST(Subset, CopiesTheKeptAtomsWithElementsAndMetadata) {
    const Atoms atoms = read_structure(data_path("1crn.pdb")).atoms;
    std::vector<std::uint8_t> keep(atoms.size(), 0);
    keep[1] = keep[5] = 1;
    const Atoms two = subset(atoms, keep);
    ASSERT_EQ(two.size(), 2u);
    std::vector<float> xyz(atoms.xyz.begin() + 3, atoms.xyz.begin() + 6);
    xyz.insert(xyz.end(), atoms.xyz.begin() + 15, atoms.xyz.begin() + 18);
    EXPECT_EQ(two.xyz, xyz);
    EXPECT_EQ(two.radius[1], atoms.radius[5]);
    EXPECT_EQ(two.element, (std::vector<std::string>{atoms.element[1], atoms.element[5]}));
    ASSERT_EQ(two.meta.size(), 2u);
    EXPECT_EQ(two.meta[1].serial, 6);
    // Without metadata (XYZR) the subset has none either.
    const Atoms xyzr = read_structure(data_path("1crn.xyzr")).atoms;
    const Atoms part = subset(xyzr, keep);
    EXPECT_EQ(part.size(), 2u);
    EXPECT_TRUE(part.meta.empty());
    EXPECT_EQ(part.element.size(), 2u);
    expect_error([&] { subset(atoms, std::vector<std::uint8_t>(3, 1)); },
                 ErrorCode::InvalidArgument, {"3 keep flags for 327 atoms"});
}

}  // namespace
}  // namespace fdmsurf
