// The exact SES's arcs cut by the balls each ball's power cell keeps (build_ses_features)
// against its plain reference that cuts every circle by every neighbour
// (build_ses_features_plain): the same features bit for bit, on real structures and on
// degenerate sets where planes coincide or touch the cell.
#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "fdmsurf/structure.hpp"
#include "grid/ses_features.hpp"
#include "support/test_atoms.hpp"
#include "support/test_data.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::detail::build_ses_features;
using fdmsurf::detail::build_ses_features_plain;
using fdmsurf::detail::kSesCellFrom;
using fdmsurf::detail::SesFeatures;
using fdmsurf::test::data_path;
using fdmsurf_test::make_atoms;

template <class T>
bool same_bytes(const std::vector<T>& a, const std::vector<T>& b) {
    return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0);
}

// The features of `atoms` with every atom's cell (cell_from 0) or by default, against the plain
// cut, compared field by field; the plain ones are returned.
SesFeatures expect_same_features(const Atoms& atoms, float probe, const std::string& what,
                                 std::size_t cell_from = 0) {
    const SesFeatures cell = build_ses_features(atoms, probe, cell_from);
    const SesFeatures plain = build_ses_features_plain(atoms, probe);
    EXPECT_EQ(cell.circles, plain.circles) << what;
    EXPECT_EQ(cell.buried_circles, plain.buried_circles) << what;
    EXPECT_EQ(cell.arcs.size(), plain.arcs.size()) << what;
    EXPECT_TRUE(same_bytes(cell.arcs, plain.arcs)) << what;
    EXPECT_TRUE(same_bytes(cell.arc_start, plain.arc_start)) << what;
    EXPECT_TRUE(same_bytes(cell.spheres, plain.spheres)) << what;
    EXPECT_TRUE(same_bytes(cell.neighbours, plain.neighbours)) << what;
    EXPECT_EQ(std::memcmp(&cell.rho_max, &plain.rho_max, sizeof(float)), 0) << what;
    EXPECT_EQ(std::memcmp(&cell.r_max, &plain.r_max, sizeof(float)), 0) << what;
    std::printf("  %s: %zu circles (%zu buried), %zu arcs\n", what.c_str(), plain.circles,
                plain.buried_circles, plain.arcs.size());
    return plain;
}

TEST(SesFeaturesCell, SameArcsAsThePlainCutOnProteins) {
    for (const char* name : {"1crn.xyzr", "4hhb.xyzr", "4yvs.cif.gz"}) {
        const Atoms atoms = fdmsurf::read_structure(data_path(name)).atoms;
        for (const float probe : {1.4f, 0.5f, 3.0f}) {
            const std::string what = std::string(name) + " probe " + std::to_string(probe);
            expect_same_features(atoms, probe, what + ", by default", kSesCellFrom);
            const SesFeatures f = expect_same_features(atoms, probe, what);
            // Not a set whose circles all vanish or all stay whole: the cell has work to do.
            EXPECT_GT(f.buried_circles, f.circles / 4) << name;
            EXPECT_GT(f.arcs.size(), atoms.size() / 4) << name;
        }
    }
}

// Ball i (R 3.75) and balls j (R 4.25, 2 Å away) and m (R 6.25, 5 Å away) on one axis: both
// radical planes are x = 0 exactly (3-4-5 and 15-8-17 triangles scaled), so the three spheres
// share one circle, which more balls round it cut into arcs. The cell clips the plane of j, then
// finds m's touching it (or the other way round) and keeps both.
TEST(SesFeaturesCell, CoincidentPlanesGiveTheSameArcs) {
    const float probe = 1.5f;
    Atoms atoms = make_atoms({{0, 0, 0, 2.25f}, {2, 0, 0, 2.75f}, {5, 0, 0, 4.75f}});
    for (int k = 0; k < 5; ++k) {
        const double a = 2.0 * 3.141592653589793 * k / 5.0;
        atoms.xyz.insert(atoms.xyz.end(), {0.5f, float(4.5 * std::cos(a)), float(4.5 * std::sin(a))});
        atoms.radius.push_back(1.0f);
    }
    const SesFeatures f = expect_same_features(atoms, probe, "coincident planes");
    EXPECT_GT(f.arcs.size(), 5u);
    // The same with the ring's balls on the shared circle's plane itself.
    for (std::size_t k = 3; k < atoms.size(); ++k) atoms.xyz[3 * k] = 0.0f;
    expect_same_features(atoms, probe, "coincident planes, ring on the plane");
}

// Cubic lattices of equal balls: each ball's cell is the cube of its six axis neighbours, and
// the bisecting planes of the twelve diagonal neighbours touch it along its edges (inside the
// ball: R 3 against edges 2.83 to 3.46 Å from the centre), where four spheres meet at each point.
// The same with one in three centres moved by one float step (planes a hair off the edges), and
// with larger balls whose body-diagonal neighbours' planes touch the cube's corners.
TEST(SesFeaturesCell, PlanesTouchingTheCellGiveTheSameArcs) {
    for (const float radius : {1.6f, 2.2f})
        for (const bool nudge : {false, true}) {
            Atoms lattice;
            for (int x = 0; x < 6; ++x)
                for (int y = 0; y < 6; ++y)
                    for (int z = 0; z < 6; ++z) {
                        float p[3] = {4.0f * x, 4.0f * y, 4.0f * z};
                        if (nudge && (x + 2 * y + z) % 3 == 0) p[0] = std::nextafter(p[0], -1.0f);
                        lattice.xyz.insert(lattice.xyz.end(), {p[0], p[1], p[2]});
                        lattice.radius.push_back(radius);
                    }
            const SesFeatures f = expect_same_features(
                lattice, 1.4f,
                "lattice r " + std::to_string(radius) + (nudge ? " nudged" : ""));
            EXPECT_GT(f.arcs.size(), 0u);
        }
}

// A ball inside another, touching its sphere from inside (its cap all but empty, left to the
// plain cut), and one 0.125 Å short of touching; the same balls growing into the other's sphere.
TEST(SesFeaturesCell, BallsTouchingFromInsideGiveTheSameArcs) {
    // Ball 0 of R 3.5, ball 1 of R 1.625 at 1.875 Å: 1.875 + 1.625 = 3.5, exact in binary.
    for (const float x : {1.875f, 1.75f, 2.0f}) {
        const Atoms atoms = make_atoms({{0, 0, 0, 2.0f}, {x, 0, 0, 0.125f}, {0, 3, 0, 1.0f},
                                        {0, -3, 0, 1.0f}, {0, 0, 3, 1.0f}, {2.5f, 2.5f, 2.5f, 1.0f},
                                        {3, 0, 0, 1.0f}});
        const SesFeatures f =
            expect_same_features(atoms, 1.5f, "ball touching from inside, at " + std::to_string(x));
        EXPECT_GT(f.arcs.size(), 0u);
    }
}

}  // namespace
