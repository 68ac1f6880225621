// Palettes, hydropathy and the built-in charge model.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>
#include <vector>

#include "fdmsurf/fdmsurf.hpp"
#include "properties/atom_tables.hpp"
#include "support/test_data.hpp"

using namespace fdmsurf;
using namespace fdmsurf::detail;

TEST(AtomTables, JmolElementColours) {
    EXPECT_EQ(element_color("C"), (Rgb{0x90, 0x90, 0x90}));
    EXPECT_EQ(element_color("o"), (Rgb{0xFF, 0x0D, 0x0D}));
    EXPECT_EQ(element_color("Fe"), (Rgb{0xE0, 0x66, 0x33}));
    EXPECT_EQ(element_color("XX"), (Rgb{0xFF, 0x14, 0x93}));
}

TEST(AtomTables, KyteDoolittleAndRamp) {
    EXPECT_FLOAT_EQ(kyte_doolittle("ILE"), 4.5f);
    EXPECT_FLOAT_EQ(kyte_doolittle("arg"), -4.5f);
    EXPECT_TRUE(std::isnan(kyte_doolittle("HOH")));
    EXPECT_EQ(diverging(0.0f, kHydrophilic, kHydrophobic), (Rgb{255, 255, 255}));
    EXPECT_EQ(diverging(1.0f, kHydrophilic, kHydrophobic), kHydrophobic);
    EXPECT_EQ(diverging(-2.0f, kHydrophilic, kHydrophobic), kHydrophilic);
}

TEST(AtomTables, BuiltInChargesOfCrambin) {
    // Crambin (1CRN): Arg 10, Arg 17, Glu 23, Asp 43, N-terminal Thr 1, C-terminal Asn 46
    // with OXT.
    const Atoms atoms = read_structure(fdmsurf::test::data_path("1crn.pdb")).atoms;
    const Charges c = atom_charges(atoms);
    EXPECT_FALSE(c.from_file);
    const double net = std::accumulate(c.q.begin(), c.q.end(), 0.0);
    EXPECT_NEAR(net, 2.0 + 1.0 - 2.0 - 1.0, 1e-5);  // Arg, N-terminus, Glu/Asp, C-terminus
    std::size_t charged = 0;
    for (float q : c.q) charged += q != 0.0f;
    EXPECT_EQ(charged, 3u + 3u + 2u + 2u + 1u + 2u);
}

TEST(AtomTables, TheNTerminusIsTheFirstAminoAcidsNUnlessCapped) {
    // Chain A starts with selenomethionine (HETATM MSE): its N carries the +1, not Thr 2's.
    // Chain B's Glu 1 is capped by an acetyl group (ACE 0, its C 1.33 Å from Glu's N): none.
    const Structure s = read_structure_from_memory(
        "HETATM    1  N   MSE A   1       0.000   0.000   0.000  1.00 10.00           N\n"
        "HETATM    2  CA  MSE A   1       1.460   0.000   0.000  1.00 10.00           C\n"
        "HETATM    3  C   MSE A   1       2.000   1.400   0.000  1.00 10.00           C\n"
        "HETATM    4  SE  MSE A   1       1.500  -1.500   1.500  1.00 10.00          SE\n"
        "ATOM      5  N   THR A   2       3.300   1.500   0.000  1.00 10.00           N\n"
        "ATOM      6  CA  THR A   2       4.000   2.700   0.000  1.00 10.00           C\n"
        "ATOM      7  C   THR A   2       5.500   2.500   0.000  1.00 10.00           C\n"
        "HETATM    8  C   ACE B   0      10.000   0.000   0.000  1.00 10.00           C\n"
        "HETATM    9  O   ACE B   0      10.000   1.200   0.000  1.00 10.00           O\n"
        "HETATM   10  CH3 ACE B   0       8.600  -0.500   0.000  1.00 10.00           C\n"
        "ATOM     11  N   GLU B   1      11.200  -0.600   0.000  1.00 10.00           N\n"
        "ATOM     12  CA  GLU B   1      12.500   0.000   0.000  1.00 10.00           C\n"
        "ATOM     13  C   GLU B   1      13.500  -1.000   0.000  1.00 10.00           C\n",
        "termini.pdb");
    ASSERT_EQ(s.atoms.size(), 13u);
    const Charges c = atom_charges(s.atoms);
    std::vector<float> expected(13, 0.0f);
    expected[0] = 1.0f;  // MSE 1 N
    EXPECT_EQ(c.q, expected);
    // The same chain B without its cap: Glu 1's N is the terminus.
    const Structure uncapped = read_structure_from_memory(
        "ATOM     11  N   GLU B   1      11.200  -0.600   0.000  1.00 10.00           N\n"
        "ATOM     12  CA  GLU B   1      12.500   0.000   0.000  1.00 10.00           C\n"
        "ATOM     13  C   GLU B   1      13.500  -1.000   0.000  1.00 10.00           C\n",
        "glu.pdb");
    EXPECT_EQ(atom_charges(uncapped.atoms).q, (std::vector<float>{1.0f, 0.0f, 0.0f}));
    // The cap listed after the chain (trailing HETATM), and a myristoyl bonded through C1: no
    // charge either. Pyroglutamate's N closes its own ring: none.
    const Structure trailing = read_structure_from_memory(
        "ATOM     11  N   GLU B   1      11.200  -0.600   0.000  1.00 10.00           N\n"
        "ATOM     12  CA  GLU B   1      12.500   0.000   0.000  1.00 10.00           C\n"
        "ATOM     13  C   GLU B   1      13.500  -1.000   0.000  1.00 10.00           C\n"
        "HETATM   14  C1  MYR B   0      10.000   0.000   0.000  1.00 10.00           C\n"
        "HETATM   15  O1  MYR B   0      10.000   1.200   0.000  1.00 10.00           O\n",
        "myristoyl.pdb");
    EXPECT_EQ(atom_charges(trailing.atoms).q, std::vector<float>(5, 0.0f));
    const Structure pyroglutamate = read_structure_from_memory(
        "HETATM    1  N   PCA C   1       0.000   0.000   0.000  1.00 10.00           N\n"
        "HETATM    2  CA  PCA C   1       1.460   0.000   0.000  1.00 10.00           C\n"
        "HETATM    3  C   PCA C   1       2.000   1.400   0.000  1.00 10.00           C\n"
        "HETATM    4  CD  PCA C   1      -0.700  -1.100   0.000  1.00 10.00           C\n",
        "pca.pdb");
    EXPECT_EQ(atom_charges(pyroglutamate.atoms).q, std::vector<float>(4, 0.0f));
}

TEST(AtomTables, AcetylCappedPeptidesHaveNoNTerminalCharge) {
    // 3AL1: two chains, each Ac-Glu 101 ...; every N is neutral, so the net charge is the side
    // chains' and C-termini's alone.
    const Atoms atoms = read_structure(fdmsurf::test::data_path("3al1.pdb")).atoms;
    const Charges c = atom_charges(atoms);
    const std::vector<AtomLabel> labels = atom_labels(atoms);
    std::size_t aces = 0;
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        aces += labels[i].residue_name == "ACE";
        if (labels[i].atom_name == "N") {
            EXPECT_EQ(c.q[i], 0.0f) << labels[i].residue_key;
        }
    }
    EXPECT_GT(aces, 0u);  // the caps are read
}

TEST(AtomTables, PqrChargesWin) {
    const Structure s = read_structure_from_memory(
        "ATOM      1  N   LYS A   1       0.000   0.000   0.000 -0.3000 1.8000\n"
        "ATOM      2  NZ  LYS A   1       3.000   0.000   0.000  0.7000 1.8000\n",
        "two.pqr");
    const Charges c = atom_charges(s.atoms);
    EXPECT_TRUE(c.from_file);
    EXPECT_FLOAT_EQ(c.q[0], -0.3f);
    EXPECT_FLOAT_EQ(c.q[1], 0.7f);
}

TEST(AtomTables, MsmsNamesGiveResidues) {
    const Atoms atoms = read_structure_from_memory("0 0 0 1.5 1 A_23_x_LYS_NZ_Blue\n"
                                                   "1 0 0 1.5 1 B_7_x_ASP_OD1_Red\n"
                                                   "2 0 0 1.5 1 C_8_x_IOD_I_Red\n",
                                                   "three.xyzrn")
                            .atoms;
    const Charges c = atom_charges(atoms);
    EXPECT_FLOAT_EQ(c.q[0], 1.0f);
    EXPECT_FLOAT_EQ(c.q[1], -0.5f);
    EXPECT_FLOAT_EQ(c.q[2], -1.0f);  // iodide
    const std::vector<AtomLabel> l = atom_labels(atoms);
    EXPECT_EQ(l[0].residue_name, "LYS");
    EXPECT_EQ(l[1].chain, "B");
}
