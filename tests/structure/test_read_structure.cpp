// Tests of reading structures: real PDB/mmCIF/XYZR files, PQR, format detection and selection.
#include <gtest/gtest.h>
#include <zlib.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <map>
#include <sstream>

#include "fdmsurf/structure.hpp"
#include "structure/structure_test_util.hpp"

namespace fdmsurf {
namespace {

using test::data_path;
using test::pdb_atom;

ReadOptions keep_everything() {
    ReadOptions o;
    o.keep_waters = true;
    o.keep_hydrogens = true;
    o.keep_ligands = true;
    return o;
}

void expect_same_atoms(const Atoms& a, const Atoms& b, float tolerance) {
    ASSERT_EQ(a.size(), b.size());
    ASSERT_EQ(a.xyz.size(), 3 * a.size());
    for (std::size_t i = 0; i < a.xyz.size(); ++i)
        ASSERT_NEAR(a.xyz[i], b.xyz[i], tolerance) << "coordinate " << i;
}

// Atoms as (x, y, z, r) rounded to 1e-3 Å, sorted: for comparing files that list them in
// different orders.
std::vector<std::array<long, 4>> sorted_atoms(const Atoms& a) {
    std::vector<std::array<long, 4>> v;
    for (std::size_t i = 0; i < a.size(); ++i)
        v.push_back({std::lround(a.xyz[3 * i] * 1000.0f), std::lround(a.xyz[3 * i + 1] * 1000.0f),
                     std::lround(a.xyz[3 * i + 2] * 1000.0f), std::lround(a.radius[i] * 1000.0f)});
    std::sort(v.begin(), v.end());
    return v;
}

TEST(ReadStructure, PdbAndMmcifOfCrambinGiveSameAtomsWithBondiRadii) {
    Structure pdb = read_structure(data_path("1crn.pdb"));
    Structure cif = read_structure(data_path("1crn.cif"));
    EXPECT_EQ(pdb.info.format, StructureFormat::Pdb);
    EXPECT_EQ(cif.info.format, StructureFormat::Mmcif);
    ASSERT_EQ(pdb.atoms.size(), 327u);
    expect_same_atoms(pdb.atoms, cif.atoms, 1e-3f);
    EXPECT_EQ(pdb.atoms.element, cif.atoms.element);
    EXPECT_EQ(pdb.atoms.radius, cif.atoms.radius);
    const std::map<std::string, float> bondi = {
        {"C", 1.70f}, {"N", 1.55f}, {"O", 1.52f}, {"S", 1.80f}};
    for (std::size_t i = 0; i < pdb.atoms.size(); ++i) {
        ASSERT_TRUE(bondi.count(pdb.atoms.element[i])) << pdb.atoms.element[i];
        EXPECT_FLOAT_EQ(pdb.atoms.radius[i], bondi.at(pdb.atoms.element[i]));
    }
    EXPECT_EQ(pdb.info.atoms_in_file, 327u);
    EXPECT_EQ(pdb.info.models_in_file, 1u);
    EXPECT_TRUE(pdb.info.warnings.empty());
    // First atom of 1CRN: N of THR 1.
    EXPECT_FLOAT_EQ(pdb.atoms.xyz[0], 17.047f);
    EXPECT_EQ(pdb.atoms.element[0], "N");
}

TEST(ReadStructure, XyzrKeepsTheFileRadii) {
    Structure s = read_structure(data_path("1crn.xyzr"));
    EXPECT_EQ(s.info.format, StructureFormat::Xyzr);
    ASSERT_EQ(s.atoms.size(), 327u);
    std::istringstream file(test::read_text_file(data_path("1crn.xyzr")));
    double x, y, z, r;
    std::size_t i = 0;
    while (file >> x >> y >> z >> r) {
        ASSERT_LT(i, s.atoms.size());
        EXPECT_FLOAT_EQ(s.atoms.xyz[3 * i], static_cast<float>(x));
        EXPECT_FLOAT_EQ(s.atoms.xyz[3 * i + 2], static_cast<float>(z));
        EXPECT_FLOAT_EQ(s.atoms.radius[i], static_cast<float>(r));
        ++i;
    }
    EXPECT_EQ(i, 327u);
    // The reference holds 1crn.pdb's atoms (in another order) with the same radii.
    Structure pdb = read_structure(data_path("1crn.pdb"));
    EXPECT_EQ(sorted_atoms(s.atoms), sorted_atoms(pdb.atoms));
    EXPECT_EQ(s.atoms.element.size(), s.atoms.size());
    EXPECT_TRUE(s.atoms.element[0].empty());
}

TEST(ReadStructure, ModelSelectionPicksTheNthModel) {
    ReadOptions second;
    second.model = 2;
    Structure m1 = read_structure(data_path("1d3z.pdb.gz"));
    Structure m2 = read_structure(data_path("1d3z.pdb.gz"), second);
    EXPECT_EQ(m1.info.models_in_file, 10u);
    EXPECT_EQ(m1.info.atoms_in_file, 1231u);
    EXPECT_EQ(m1.info.hydrogens_skipped, 629u);
    ASSERT_EQ(m1.atoms.size(), 602u);
    ASSERT_EQ(m2.atoms.size(), 602u);
    float max_diff = 0.0f;
    for (std::size_t i = 0; i < m1.atoms.xyz.size(); ++i)
        max_diff = std::max(max_diff, std::abs(m1.atoms.xyz[i] - m2.atoms.xyz[i]));
    EXPECT_GT(max_diff, 0.5f);

    ReadOptions eleventh;
    eleventh.model = 11;
    test::expect_error([&] { read_structure(data_path("1d3z.pdb.gz"), eleventh); },
                       ErrorCode::InvalidArgument, {"1d3z.pdb.gz", "model 11", "10 models"});
    ReadOptions zeroth;
    zeroth.model = 0;
    test::expect_error([&] { read_structure(data_path("1d3z.pdb.gz"), zeroth); },
                       ErrorCode::InvalidArgument, {"model 0"});
}

TEST(ReadStructure, HydrogensWatersAndAltlocsAreCounted) {
    Structure s = read_structure(data_path("3al1.pdb"));
    EXPECT_EQ(s.info.atoms_in_file, 679u);
    EXPECT_EQ(s.info.altlocs_skipped, 188u);
    EXPECT_EQ(s.info.waters_skipped, 21u);
    EXPECT_EQ(s.info.hydrogens_skipped, 250u);
    EXPECT_EQ(s.info.ligands_skipped, 0u);
    EXPECT_EQ(s.atoms.size(), 679u - 188u - 21u - 250u);
    for (const std::string& e : s.atoms.element) EXPECT_NE(e, "H");

    Structure all = read_structure(data_path("3al1.pdb"), keep_everything());
    EXPECT_EQ(all.atoms.size(), 679u - 188u);
    EXPECT_EQ(all.info.altlocs_skipped, 188u);
    EXPECT_EQ(all.info.hydrogens_skipped + all.info.waters_skipped, 0u);

    // Ligands: MPD (22 atoms, hydrogens included) and two ethanolamines (ETA, 4 atoms each), first
    // alternate location only. The ACE caps open the peptide chains: polymer, not ligand.
    ReadOptions no_ligands = keep_everything();
    no_ligands.keep_ligands = false;
    Structure protein = read_structure(data_path("3al1.pdb"), no_ligands);
    EXPECT_EQ(protein.info.ligands_skipped, 30u);
}

TEST(ReadStructure, LigandsAreHetatmOutsidePolymersAndNotWater) {
    std::string text = pdb_atom("ATOM", 1, " N", ' ', "GLY", 'A', 1, 0, 0, 0, "N") +
                       pdb_atom("ATOM", 2, " CA", ' ', "GLY", 'A', 1, 1.4, 0, 0, "C") +
                       pdb_atom("ATOM", 3, " C", ' ', "GLY", 'A', 1, 2.0, 1.2, 0, "C") +
                       // selenomethionine inside the chain: HETATM, but part of the polymer
                       pdb_atom("HETATM", 4, " N", ' ', "MSE", 'A', 2, 3.3, 1.3, 0, "N") +
                       pdb_atom("HETATM", 5, " CA", ' ', "MSE", 'A', 2, 4.0, 2.5, 0, "C") +
                       pdb_atom("HETATM", 6, "SE", ' ', "MSE", 'A', 2, 5.0, 3.5, 0, "SE") +
                       "TER       7      MSE A   2\n" +
                       pdb_atom("HETATM", 8, "ZN", ' ', " ZN", 'A', 101, 9, 9, 9, "ZN") +
                       pdb_atom("HETATM", 9, " O", ' ', "HOH", 'A', 201, 12, 9, 9, "O") + "END\n";
    Structure s = read_structure_from_memory(text, "small.pdb");
    EXPECT_EQ(s.atoms.size(), 7u);
    EXPECT_EQ(s.info.waters_skipped, 1u);
    EXPECT_EQ(s.atoms.element[5], "SE");
    EXPECT_FLOAT_EQ(s.atoms.radius[5], 1.90f);
    EXPECT_EQ(s.atoms.element[6], "ZN");
    EXPECT_FLOAT_EQ(s.atoms.radius[6], 1.39f);

    ReadOptions no_ligands;
    no_ligands.keep_ligands = false;
    Structure protein = read_structure_from_memory(text, "small.pdb", no_ligands);
    EXPECT_EQ(protein.atoms.size(), 6u);
    EXPECT_EQ(protein.info.ligands_skipped, 1u);

    ReadOptions waters;
    waters.keep_waters = true;
    EXPECT_EQ(read_structure_from_memory(text, "small.pdb", waters).atoms.size(), 8u);
}

TEST(ReadStructure, FirstAlternateLocationSeenIsKept) {
    std::string text = pdb_atom("ATOM", 1, " CA", 'B', "SER", 'A', 1, 1, 0, 0, "C") +
                       pdb_atom("ATOM", 2, " CA", 'A', "SER", 'A', 1, 2, 0, 0, "C") +
                       pdb_atom("ATOM", 3, " CB", 'A', "SER", 'A', 1, 3, 0, 0, "C") +
                       pdb_atom("ATOM", 4, " CB", 'B', "SER", 'A', 1, 4, 0, 0, "C") +
                       pdb_atom("ATOM", 5, " OG", 'B', "SER", 'A', 1, 5, 0, 0, "O");
    Structure s = read_structure_from_memory(text, "alt.pdb");
    ASSERT_EQ(s.atoms.size(), 3u);
    EXPECT_FLOAT_EQ(s.atoms.xyz[0], 1.0f);
    EXPECT_FLOAT_EQ(s.atoms.xyz[3], 3.0f);
    EXPECT_FLOAT_EQ(s.atoms.xyz[6], 5.0f);
    EXPECT_EQ(s.info.altlocs_skipped, 2u);
}

TEST(ReadStructure, BlankElementColumnIsInferredFromTheAtomName) {
    // Records cut after the coordinates: no element column.
    std::string ca = pdb_atom("ATOM", 1, " CA", ' ', "ALA", 'A', 1, 1, 2, 3, "C").substr(0, 54);
    std::string calcium =
        pdb_atom("HETATM", 2, "CA", ' ', " CA", 'B', 1, 4, 5, 6, "CA").substr(0, 54);
    std::string hydrogen =
        pdb_atom("ATOM", 3, " HA", ' ', "ALA", 'A', 1, 1, 2, 4, "H").substr(0, 54);
    Structure s = read_structure_from_memory(ca + "\n" + calcium + "\n" + hydrogen, "noel.pdb",
                                             keep_everything());
    ASSERT_EQ(s.atoms.size(), 3u);
    EXPECT_EQ(s.atoms.element, (std::vector<std::string>{"C", "CA", "H"}));
    EXPECT_FLOAT_EQ(s.atoms.radius[0], 1.70f);
    EXPECT_FLOAT_EQ(s.atoms.radius[1], vdw_radius("Ca"));
    EXPECT_FLOAT_EQ(s.atoms.radius[2], 1.20f);
    EXPECT_TRUE(s.info.warnings.empty());
}

TEST(ReadStructure, UnknownElementsGetDefaultRadiusAndOneWarningEach) {
    std::string text = pdb_atom("HETATM", 1, "Q1", ' ', "UNL", 'A', 1, 0, 0, 0, "Q") +
                       pdb_atom("HETATM", 2, "Q2", ' ', "UNL", 'A', 1, 2, 0, 0, "Q") +
                       pdb_atom("HETATM", 3, "QX", ' ', "UNL", 'A', 1, 4, 0, 0, "QX") +
                       pdb_atom("HETATM", 4, " C1", ' ', "UNL", 'A', 1, 6, 0, 0, "C");
    Structure s = read_structure_from_memory(text, "unknown.pdb");
    ASSERT_EQ(s.atoms.size(), 4u);
    EXPECT_FLOAT_EQ(s.atoms.radius[0], kUnknownElementRadius);
    EXPECT_FLOAT_EQ(s.atoms.radius[2], kUnknownElementRadius);
    EXPECT_FLOAT_EQ(s.atoms.radius[3], 1.70f);
    EXPECT_EQ(s.atoms.element[0], "X");
    ASSERT_EQ(s.info.warnings.size(), 2u);
    EXPECT_NE(s.info.warnings[0].find("'Q' for 2 atoms"), std::string::npos) << s.info.warnings[0];
    EXPECT_NE(s.info.warnings[1].find("'QX' for 1 atom"), std::string::npos) << s.info.warnings[1];
}

TEST(ReadStructure, MmcifUnknownElementIsNamedInTheWarning) {
    std::string text = std::string(test::kCifAtomSiteHeader) +
                       "HETATM 1 Q  Q1 . UNL B . 1.0 2.0 3.0 1.0 10.0 5 1\n"
                       "HETATM 2 C  C1 . UNL B . 2.0 2.0 3.0 1.0 10.0 5 1\n";
    Structure s = read_structure_from_memory(text, "unknown.cif");
    ASSERT_EQ(s.atoms.size(), 2u);
    EXPECT_EQ(s.atoms.radius, (std::vector<float>{kUnknownElementRadius, 1.70f}));
    ASSERT_EQ(s.info.warnings.size(), 1u);
    EXPECT_NE(s.info.warnings[0].find("unknown element 'Q' for 1 atom;"), std::string::npos)
        << s.info.warnings[0];
}

TEST(ReadStructure, MmcifModelsAreCountedInFileOrder) {
    std::string text = std::string(test::kCifAtomSiteHeader) +
                       "ATOM 1 C CA . ALA A 1 1.0 2.0 3.0 1.0 10.0 1 3\n"
                       "ATOM 2 C CA . ALA A 1 1.5 2.0 3.0 1.0 10.0 1 7\n";
    ReadOptions second;
    second.model = 2;
    Structure s = read_structure_from_memory(text, "models.cif", second);
    EXPECT_EQ(s.info.models_in_file, 2u);
    ASSERT_EQ(s.atoms.size(), 1u);
    EXPECT_FLOAT_EQ(s.atoms.xyz[0], 1.5f);
}

TEST(ReadStructure, PqrReadsTheRadiusColumnWithOrWithoutChain) {
    const char* text =
        "REMARK   1 PQR file\n"
        "ATOM      1  N   MET A   1     -12.000   3.500  -0.25 -0.3000 1.8240\n"
        "ATOM      2  CA  MET     1     -11.000   3.500  -0.25  0.2100 1.9080\n"
        "ATOM      3  HA  MET     1 -10.5 4.0 0.5 0.1 1.1\n"
        "HETATM    4 ZN    ZN     2      1.000   2.000   3.000  2.0000 1.1000\n"
        "TER\nEND\n";
    Structure s = read_structure_from_memory(text, "small.pqr");
    EXPECT_EQ(s.info.format, StructureFormat::Pqr);
    ASSERT_EQ(s.atoms.size(), 4u);
    EXPECT_EQ(s.atoms.radius, (std::vector<float>{1.824f, 1.908f, 1.1f, 1.1f}));
    EXPECT_EQ(s.atoms.xyz[0], -12.0f);
    EXPECT_EQ(s.atoms.xyz[2], -0.25f);
    EXPECT_EQ(s.atoms.xyz[6], -10.5f);
    EXPECT_EQ(s.atoms.element, (std::vector<std::string>{"N", "C", "H", "ZN"}));
    EXPECT_EQ(s.info.atoms_in_file, 4u);
}

TEST(ReadStructure, XyzrSkipsCommentsAndBlankLinesAndExtraFields) {
    const char* text = "# x y z r\n\n1 2 3 1.5\n  4 5 6 1.7 1 CA\n\t# indented comment\n7 8 9 2";
    Structure s = read_structure_from_memory(text, "atoms.xyzr");
    ASSERT_EQ(s.atoms.size(), 3u);
    EXPECT_EQ(s.atoms.xyz, (std::vector<float>{1, 2, 3, 4, 5, 6, 7, 8, 9}));
    EXPECT_EQ(s.atoms.radius, (std::vector<float>{1.5f, 1.7f, 2.0f}));
}

TEST(ReadStructure, FormatFromContentWhenTheNameHasNoExtension) {
    std::string pdb = test::read_text_file(data_path("1crn.pdb"));
    std::string cif = test::read_text_file(data_path("1crn.cif"));
    EXPECT_EQ(read_structure_from_memory(pdb, "crambin").info.format, StructureFormat::Pdb);
    EXPECT_EQ(read_structure_from_memory(cif, "crambin").info.format, StructureFormat::Mmcif);
    // Bare ATOM records, no header.
    std::string atoms = pdb_atom("ATOM", 1, " CA", ' ', "ALA", 'A', 1, 1, 2, 3, "C");
    EXPECT_EQ(read_structure_from_memory(atoms, "stdin").atoms.size(), 1u);
}

TEST(ReadStructure, ExplicitFormatOverridesTheExtension) {
    ReadOptions xyzr;
    xyzr.format = StructureFormat::Xyzr;
    Structure s = read_structure_from_memory("1 2 3 1.5\n", "atoms.pdb", xyzr);
    EXPECT_EQ(s.info.format, StructureFormat::Xyzr);
    EXPECT_EQ(s.atoms.size(), 1u);
}

TEST(ReadStructure, CrlfLineEndingsAndMissingFinalNewlineAreRead) {
    std::string a = pdb_atom("ATOM", 1, " CA", ' ', "ALA", 'A', 1, 1, 2, 3, "C");
    std::string b = pdb_atom("ATOM", 2, " CB", ' ', "ALA", 'A', 1, 4, 5, 6, "C");
    std::string crlf = a.substr(0, a.size() - 1) + "\r\n" + b.substr(0, b.size() - 1) + "\r\n";
    EXPECT_EQ(read_structure_from_memory(crlf, "crlf.pdb").atoms.size(), 2u);
    // The last record ends right after z (column 54), with no newline.
    EXPECT_EQ(read_structure_from_memory(a + b.substr(0, 54), "short.pdb").atoms.size(), 2u);
    EXPECT_EQ(read_structure_from_memory("1 2 3 1.5\r\n4 5 6 1.5\r\n", "crlf.xyzr").atoms.size(),
              2u);
}

TEST(ReadStructure, GzipFileReadsLikeThePlainFile) {
    std::string plain = test::read_text_file(data_path("1crn.pdb"));
    test::TempFile gz("1crn_copy.pdb.gz", "");
    gzFile f = gzopen(gz.path().c_str(), "wb");
    ASSERT_NE(f, nullptr);
    ASSERT_EQ(gzwrite(f, plain.data(), static_cast<unsigned>(plain.size())),
              static_cast<int>(plain.size()));
    gzclose(f);
    Structure s = read_structure(gz.path());
    expect_same_atoms(s.atoms, read_structure(data_path("1crn.pdb")).atoms, 0.0f);
}

TEST(ReadStructure, FormatNamesAreStable) {
    EXPECT_STREQ(to_string(StructureFormat::Pdb), "pdb");
    EXPECT_STREQ(to_string(StructureFormat::Mmcif), "mmcif");
    EXPECT_STREQ(to_string(StructureFormat::Pqr), "pqr");
    EXPECT_STREQ(to_string(StructureFormat::Xyzr), "xyzr");
    EXPECT_STREQ(to_string(StructureFormat::Auto), "auto");
}

}  // namespace
}  // namespace fdmsurf
