// Tests of the van der Waals radius table: Bondi (1964) values, gemmi fallback, unknown symbols.
#include <gtest/gtest.h>

#include "fdmsurf/structure.hpp"

namespace fdmsurf {
namespace {

TEST(VdwRadius, BondiValuesForBiologicalElements) {
    EXPECT_FLOAT_EQ(vdw_radius("H"), 1.20f);
    EXPECT_FLOAT_EQ(vdw_radius("C"), 1.70f);
    EXPECT_FLOAT_EQ(vdw_radius("N"), 1.55f);
    EXPECT_FLOAT_EQ(vdw_radius("O"), 1.52f);
    EXPECT_FLOAT_EQ(vdw_radius("P"), 1.80f);
    EXPECT_FLOAT_EQ(vdw_radius("S"), 1.80f);
    EXPECT_FLOAT_EQ(vdw_radius("SE"), 1.90f);
    EXPECT_FLOAT_EQ(vdw_radius("ZN"), 1.39f);
    EXPECT_FLOAT_EQ(vdw_radius("MG"), 1.73f);
    EXPECT_FLOAT_EQ(vdw_radius("CL"), 1.75f);
    EXPECT_FLOAT_EQ(vdw_radius("I"), 1.98f);
}

TEST(VdwRadius, BondiWinsWhereGemmiDiffers) {
    // gemmi's table has 1.75 for platinum; Bondi gives 1.72.
    EXPECT_FLOAT_EQ(vdw_radius("PT"), 1.72f);
}

TEST(VdwRadius, DeuteriumIsHydrogenSized) { EXPECT_FLOAT_EQ(vdw_radius("D"), 1.20f); }

TEST(VdwRadius, CaseAndSpacesDoNotMatter) {
    EXPECT_FLOAT_EQ(vdw_radius("se"), 1.90f);
    EXPECT_FLOAT_EQ(vdw_radius("Se"), 1.90f);
    EXPECT_FLOAT_EQ(vdw_radius(" C"), 1.70f);
    EXPECT_FLOAT_EQ(vdw_radius("cl "), 1.75f);
}

TEST(VdwRadius, OtherKnownElementsFallBackToGemmi) {
    EXPECT_GT(vdw_radius("FE"), 0.0f);
    EXPECT_GT(vdw_radius("CA"), 0.0f);
    EXPECT_GT(vdw_radius("Mn"), 0.0f);
}

TEST(VdwRadius, UnknownSymbolsAreNegative) {
    EXPECT_LT(vdw_radius(""), 0.0f);
    EXPECT_LT(vdw_radius("X"), 0.0f);
    EXPECT_LT(vdw_radius("Q"), 0.0f);
    EXPECT_LT(vdw_radius("QQ"), 0.0f);
    EXPECT_LT(vdw_radius("CAX"), 0.0f);
    EXPECT_LT(vdw_radius("1"), 0.0f);
}

}  // namespace
}  // namespace fdmsurf
