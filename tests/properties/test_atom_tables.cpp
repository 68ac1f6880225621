// Palettes, hydropathy and the built-in charge model.
#include <gtest/gtest.h>

#include <cmath>
#include <numeric>

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
