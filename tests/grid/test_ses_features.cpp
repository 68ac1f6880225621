// Tests of the exact SES distance on the host (src/grid/ses_features.cpp, ses_distance_cpu.cpp):
// arcs of simple sphere sets, analytic distances, and the binned evaluation against the
// independent brute force on crambin.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <utility>
#include <vector>

#include "fdmsurf/error.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "grid/grid_plan.hpp"
#include "grid/ses_distance_cpu.hpp"
#include "grid/ses_features.hpp"
#include "isosurface/marching_cubes_cpu.hpp"
#include "support/test_atoms.hpp"
#include "support/test_data.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::detail::arc_distance;
using fdmsurf::detail::build_ses_features;
using fdmsurf::detail::ses_distance;
using fdmsurf::detail::ses_distance_brute;
using fdmsurf::detail::SesArc;
using fdmsurf::detail::SesFeatures;

constexpr double kPi = std::numbers::pi;

using fdmsurf::test::data_path;

using fdmsurf_test::make_atoms;

// A point of arc `a` at angle theta.
std::array<double, 3> arc_point(const SesArc& a, double theta) {
    std::array<double, 3> p;
    for (int k = 0; k < 3; ++k)
        p[k] = a.m[k] + a.rho * (std::cos(theta) * a.e1[k] + std::sin(theta) * a.e2[k]);
    return p;
}

double dist(const std::array<double, 3>& p, const float* c) {
    return std::sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                     (p[2] - c[2]) * (p[2] - c[2]));
}

TEST(SesFeatures, TwoBallsMeetInOneWholeCircle) {
    // Inflated radii 3.0 and 3.0 at 3.6 Å: the circle halfway, radius sqrt(9 - 1.8^2) = 2.4.
    const SesFeatures f =
        build_ses_features(make_atoms({{0, 0, 0, 1.6f}, {3.6f, 0, 0, 1.6f}}), 1.4f);
    ASSERT_EQ(f.arcs.size(), 1u);
    EXPECT_EQ(f.circles, 1u);
    const SesArc& a = f.arcs[0];
    EXPECT_NEAR(a.m[0], 1.8, 1e-6);
    EXPECT_NEAR(a.rho, 2.4, 1e-6);
    EXPECT_NEAR(a.length, 2.0 * kPi, 1e-6);
    EXPECT_FLOAT_EQ(f.r_max, 3.0f);
    // From the circle's centre every point of it is rho away, and the faces' projections there
    // are buried by the other ball: d = rho.
    const double m[3] = {1.8, 0.0, 0.0};
    EXPECT_NEAR(ses_distance(f, m, 10.0), 2.4, 1e-6);
    // On the axis beyond the first centre the face of ball 1 is nearest: d = R - |p - c|.
    const double p[3] = {-1.0, 0.0, 0.0};
    EXPECT_NEAR(ses_distance(f, p, 10.0), 2.0, 1e-6);
    // Outside both balls: minus the distance to the nearer.
    const double q[3] = {-4.0, 0.0, 0.0};
    EXPECT_NEAR(ses_distance(f, q, 10.0), -1.0, 1e-6);
    // Clamped far inside... and far outside.
    EXPECT_NEAR(ses_distance(f, p, 1.5), 1.5, 1e-12);
    const double far[3] = {-20.0, 0.0, 0.0};
    EXPECT_NEAR(ses_distance(f, far, 2.5), -2.5, 1e-12);
}

TEST(SesFeatures, AThirdBallCutsTheCircleAtThreeSpherePoints) {
    const Atoms atoms = make_atoms({{0, 0, 0, 1.6f}, {3.6f, 0, 0, 1.6f}, {1.8f, 3.0f, 0.0f, 1.6f}});
    const SesFeatures f = build_ses_features(atoms, 1.4f);
    EXPECT_EQ(f.circles, 3u);
    ASSERT_EQ(f.arcs.size(), 3u);  // each circle loses one interval to the third ball
    for (const SesArc& a : f.arcs) {
        EXPECT_GT(a.length, 0.0f);
        EXPECT_LT(a.length, 2.0 * kPi);
        // Both ends lie on all three inflated spheres (radius 3.0).
        for (double theta : {double(a.start), double(a.start) + a.length}) {
            const auto e = arc_point(a, theta);
            for (std::size_t i = 0; i < 3; ++i)
                EXPECT_NEAR(dist(e, &atoms.xyz[3 * i]), 3.0, 1e-5) << "ball " << i;
        }
        // The middle of the arc is outside the ball that does not make the circle.
        const auto mid = arc_point(a, a.start + 0.5 * a.length);
        int outside = 0;
        for (std::size_t i = 0; i < 3; ++i) outside += dist(mid, &atoms.xyz[3 * i]) > 3.0 + 1e-6;
        EXPECT_EQ(outside, 1);
    }
    // The arc distance: on the arc 0, off it the nearer end.
    const SesArc& a = f.arcs[0];
    const auto on = arc_point(a, a.start + 0.3 * a.length);
    EXPECT_NEAR(arc_distance(a, on.data()), 0.0, 1e-5);
    const auto off = arc_point(a, a.start - 0.2);  // just before the start
    const auto end = arc_point(a, a.start);
    const double expect = std::hypot(off[0] - end[0], off[1] - end[1], off[2] - end[2]);
    EXPECT_NEAR(arc_distance(a, off.data()), expect, 1e-5);
}

TEST(SesFeatures, ABallInsideAnotherMakesNoCircle) {
    const SesFeatures f =
        build_ses_features(make_atoms({{0, 0, 0, 2.0f}, {0.3f, 0, 0, 1.0f}}), 1.4f);
    EXPECT_EQ(f.circles, 0u);
    EXPECT_TRUE(f.arcs.empty());
    // The inner ball's face is buried: inside, d is the outer ball's face distance.
    const double p[3] = {0.9, 0.0, 0.0};
    EXPECT_NEAR(ses_distance(f, p, 10.0), 3.4 - 0.9, 1e-6);
}

TEST(SesFeatures, BadInputIsRefused) {
    EXPECT_THROW(build_ses_features(Atoms{}, 1.4f), fdmsurf::Error);
    EXPECT_THROW(build_ses_features(make_atoms({{0, 0, 0, 1.6f}}), 0.0f), fdmsurf::Error);
    EXPECT_THROW(build_ses_features(make_atoms({{0, 0, 0, -1.0f}}), 1.4f), fdmsurf::Error);
    EXPECT_THROW(build_ses_features(make_atoms({{0, NAN, 0, 1.0f}}), 1.4f), fdmsurf::Error);
}

// Random points around random atoms, at their radius plus up to 1.6 probe radii: inside the
// inflated balls and near their surface (the distributions keep their state from call to call).
struct PointsNearAtoms {
    const Atoms& atoms;
    float probe;
    std::uniform_int_distribution<std::size_t> pick{0, atoms.size() - 1};
    std::normal_distribution<double> offset{0.0, 1.0};
    void operator()(std::mt19937& rng, double p[3]) {
        const std::size_t i = pick(rng);
        double dir[3] = {offset(rng), offset(rng), offset(rng)};
        const double len = std::sqrt(dir[0] * dir[0] + dir[1] * dir[1] + dir[2] * dir[2]);
        const double r =
            atoms.radius[i] + probe * std::uniform_real_distribution<double>(0.0, 1.6)(rng);
        for (int k = 0; k < 3; ++k) p[k] = atoms.xyz[3 * i + k] + r * dir[k] / len;
    }
};

// The binned evaluation from arcs against the brute force over faces, circles and three-sphere
// points, at random points of crambin's surface band. Arcs are stored in float (1e-7 relative,
// ~1e-5 Å at these coordinates), hence the tolerance.
TEST(SesFeatures, BinnedDistanceMatchesBruteForceOnCrambin) {
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    const float probe = 1.4f;
    const SesFeatures f = build_ses_features(atoms, probe);
    EXPECT_GT(f.arcs.size(), atoms.size());
    const double d_max = probe + 1.5;
    std::mt19937 rng(1310);
    PointsNearAtoms near{atoms, probe};
    std::size_t compared = 0, band = 0, arcs_won = 0;
    double worst = 0.0;
    for (int n = 0; n < 3000; ++n) {
        // Around a random atom, about at its inflated radius: inside the balls, near their surface.
        double p[3];
        near(rng, p);
        const double fast = ses_distance(f, p, d_max);
        const double brute = ses_distance_brute(atoms, probe, p, d_max);
        worst = std::max(worst, std::abs(fast - brute));
        ++compared;
        band += fast > 0.0 && fast < d_max;
        // The SES's re-entrant part: where the nearest point is not the radial projection of any
        // single ball (checked crudely: no ball's face distance equals d).
        bool face = false;
        for (std::size_t k = 0; k < atoms.size() && !face; ++k) {
            const float* c = &atoms.xyz[3 * k];
            const double L =
                std::sqrt((p[0] - c[0]) * (p[0] - c[0]) + (p[1] - c[1]) * (p[1] - c[1]) +
                          (p[2] - c[2]) * (p[2] - c[2]));
            face = std::abs(std::abs(L - (atoms.radius[k] + probe)) - fast) < 1e-6;
        }
        arcs_won += fast > 0.0 && fast < d_max && !face;
        ASSERT_NEAR(fast, brute, 1e-4) << "point " << p[0] << " " << p[1] << " " << p[2];
    }
    std::printf("  ses distance: %zu points, %zu in the band, %zu re-entrant, max |diff| %.3g Å\n",
                compared, band, arcs_won, worst);
    // The sample covers the band and its re-entrant part (not only faces).
    EXPECT_GT(band, 1000u);
    EXPECT_GT(arcs_won, 200u);
}

TEST(SesFeatures, CoincidentAtomsAreOneBall) {
    // Duplicated atoms (the same centre and radius) make the same features as one: kept twice,
    // each would bury the other's face where rounding puts a projection a hair inside, and the
    // distance would jump there (a random set with coincident atoms grew 11% of spurious area).
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    Atoms doubled = atoms;
    for (std::size_t i = 0; i < atoms.size(); i += 7) {
        doubled.xyz.insert(doubled.xyz.end(), &atoms.xyz[3 * i], &atoms.xyz[3 * i] + 3);
        doubled.radius.push_back(atoms.radius[i]);
    }
    // Balls are the same when their float spheres are: a radius one ulp away whose r + probe
    // rounds to the same float is the same ball (the shaders could not tell them apart).
    std::size_t nudged = 0;
    for (std::size_t i = 3; i < atoms.size(); i += 7) {
        const float r = std::nextafter(atoms.radius[i], 10.0f);
        if (float(double(r) + 1.4f) != float(double(atoms.radius[i]) + 1.4f)) continue;
        doubled.xyz.insert(doubled.xyz.end(), &atoms.xyz[3 * i], &atoms.xyz[3 * i] + 3);
        doubled.radius.push_back(r);
        ++nudged;
    }
    EXPECT_GT(nudged, 3u);
    const SesFeatures a = build_ses_features(atoms, 1.4f);
    const SesFeatures b = build_ses_features(doubled, 1.4f);
    EXPECT_EQ(a.sphere_count(), b.sphere_count());
    EXPECT_EQ(a.spheres, b.spheres);
    EXPECT_EQ(a.arcs.size(), b.arcs.size());
    EXPECT_EQ(a.circles, b.circles);
    std::mt19937 rng(99);
    std::uniform_int_distribution<std::size_t> pick(0, atoms.size() - 1);
    std::normal_distribution<double> offset(0.0, 1.0);
    for (int n = 0; n < 2000; ++n) {
        const std::size_t i = pick(rng);
        double p[3];
        for (int k = 0; k < 3; ++k) p[k] = atoms.xyz[3 * i + k] + 2.5 * offset(rng);
        ASSERT_EQ(ses_distance(a, p, 3.0), ses_distance(b, p, 3.0));
    }
}

TEST(SesFeatures, OnlyTiedFacesGiveTheSameDistanceAsEveryFace) {
    // ses_distance without every_face (the snap and refine stages, as the shader) skips the
    // faces of the balls not exactly as deep as the deepest: the same value and gradient, bit
    // for bit, on hemoglobin's re-entrant band (where those faces would be tried).
    const Atoms atoms = fdmsurf::read_structure(data_path("4hhb.xyzr")).atoms;
    const float probe = 1.4f;
    const SesFeatures f = build_ses_features(atoms, probe);
    const double d_max = probe + 1.0;
    std::mt19937 rng(4242);
    PointsNearAtoms near{atoms, probe};
    std::size_t band = 0;
    for (int n = 0; n < 20000; ++n) {
        double p[3];
        near(rng, p);
        double g_every[3], g_tied[3];
        const double every = ses_distance(f, p, d_max, g_every, true);
        const double tied = ses_distance(f, p, d_max, g_tied, false);
        band += every > 0.0 && every < d_max;
        ASSERT_EQ(every, tied) << "point " << p[0] << " " << p[1] << " " << p[2];
        for (int k = 0; k < 3; ++k) ASSERT_EQ(g_every[k], g_tied[k]);
    }
    EXPECT_GT(band, 5000u);
}

TEST(SesFeatures, ExactDepthTiesGiveTheSameDistanceAsEveryFace) {
    // Points exactly as deep in two balls take the tie path of ses_distance without every_face.
    // A ball inside another, touching it at (2, 0, 0), and points (x, 0, 0) between the centres:
    // both depths are 2 - x exactly, and both projections are (2, 0, 0) in exact arithmetic, on
    // both spheres: exposed (the burial test is strict). In doubles the big ball's projection
    // (2 / x) x rounds to 2 - 2^-52 for some x, inside the small ball: when the big ball is
    // the deepest there, only the tie path finds the small ball's exposed face (without it, d
    // would be d_max). Both orders of the atoms, so that either ball is the first found. Also
    // the mid-plane of two equal balls. Value and gradient as with every face tried.
    const float probe = 0.1f;
    Atoms pair;
    pair.xyz = {-1.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f};
    pair.radius = {1.9f, 1.9f};
    const SesFeatures fp = build_ses_features(pair, probe);
    const double d_max = 3.0;
    auto same = [&](const SesFeatures& f, const double p[3]) {
        double g_every[3], g_tied[3];
        const double every = ses_distance(f, p, d_max, g_every, true);
        const double tied = ses_distance(f, p, d_max, g_tied, false);
        EXPECT_EQ(every, tied) << p[0] << " " << p[1] << " " << p[2];
        for (int k = 0; k < 3; ++k) EXPECT_EQ(g_every[k], g_tied[k]);
        return tied;
    };
    std::size_t inside = 0;
    for (int i = -12; i <= 12; ++i) {
        for (int j = -12; j <= 12; ++j) {
            const double p[3] = {0.0, 0.25 * i, 0.25 * j};
            inside += same(fp, p) > 0.0;
        }
    }
    EXPECT_GT(inside, 60u);
    for (const bool big_first : {true, false}) {
        Atoms tangent;
        tangent.xyz = {0.0f, 0.0f, 0.0f, 1.0f, 0.0f, 0.0f};
        tangent.radius = {1.9f, 0.9f};  // inflated: 2 and 1 exactly in float
        if (!big_first) {
            tangent.xyz = {1.0f, 0.0f, 0.0f, 0.0f, 0.0f, 0.0f};
            tangent.radius = {0.9f, 1.9f};
        }
        const SesFeatures ft = build_ses_features(tangent, probe);
        std::size_t rounded = 0;
        for (int k = 1; k < 1000; ++k) {
            const double p[3] = {1.0 + k / 1000.0, 0.0, 0.0};
            rounded += (2.0 / p[0]) * p[0] != 2.0;
            EXPECT_DOUBLE_EQ(same(ft, p), 2.0 - p[0]) << "x = " << p[0];
        }
        EXPECT_GT(rounded, 50u) << "no point where the big ball's projection rounds inside";
    }
}

// Marching cubes on the exact SES field of `plan` (the whole grid, on the CPU reference).
fdmsurf::Mesh ses_field_mesh(const std::vector<float>& field,
                             const fdmsurf::detail::GridPlan& plan) {
    const auto& d = plan.info.dims;
    fdmsurf::detail::McParams mc;
    for (int a = 0; a < 3; ++a) mc.origin[a] = plan.info.origin[a];
    mc.spacing = plan.info.spacing;
    mc.iso = plan.iso;
    mc.z_end = d[2] - 1;
    const fdmsurf::detail::FieldView view{field.data(), d[0], d[1], d[2], plan.pitch};
    return fdmsurf::detail::marching_cubes_cpu(view, mc);
}

TEST(SesField, LowerClampLeavesTheMeshUnchanged) {
    // Without the snap the field is clamped to [r_s - 2h, r_s + 2h] (it was +-(r_s + 2h)):
    // marching cubes reads the values at the ends of a crossed edge (within h of the level, d
    // being 1-Lipschitz) and their neighbours for the normals (within 2h), so the mesh of
    // crambin at 0.5 A is the same, positions, normals and indices, with either lower clamp.
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    const fdmsurf::SurfaceOptions options{
        .method = fdmsurf::SesMethod::Edt, .spacing = 0.5f, .snap = false};
    const fdmsurf::detail::GridPlan plan = fdmsurf::detail::plan_grid(atoms, options);
    ASSERT_TRUE(plan.exact_ses);
    ASSERT_FLOAT_EQ(plan.ses_d_min, options.probe - 2.0f * plan.info.spacing);
    fdmsurf::detail::GridPlan wide = plan;
    wide.ses_d_min = -plan.ses_d_max;
    const SesFeatures f = build_ses_features(atoms, options.probe);
    const std::vector<float> tight = fdmsurf::detail::ses_field_cpu(f, plan);
    const std::vector<float> old = fdmsurf::detail::ses_field_cpu(f, wide);
    std::size_t clamped = 0;
    for (std::size_t i = 0; i < tight.size(); ++i) clamped += tight[i] != old[i];
    EXPECT_GT(clamped, tight.size() / 10) << "the two clamps differ at few points";
    const fdmsurf::Mesh a = ses_field_mesh(tight, plan), b = ses_field_mesh(old, plan);
    EXPECT_GT(a.triangle_count(), 10000u);
    EXPECT_EQ(a.positions, b.positions);
    EXPECT_EQ(a.normals, b.normals);
    EXPECT_EQ(a.indices, b.indices);
}

TEST(SesField, WhereTheSnapFollowsOneSpacingGivesTheSameCrossings) {
    // With the snap (and no refinement) the field is exact within one spacing of the level: the
    // crossings read no farther, so marching cubes puts the same vertices in the same triangles
    // as on the two-spacing field (crambin at 0.5 and 1 A); only the normals, whose central
    // differences read clamped neighbours, differ, and the snap replaces those.
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    const SesFeatures f = build_ses_features(atoms, 1.4f);
    for (const float spacing : {0.5f, 1.0f}) {
        const fdmsurf::SurfaceOptions snapped{.method = fdmsurf::SesMethod::Edt,
                                              .spacing = spacing};
        fdmsurf::SurfaceOptions raw = snapped, refined = snapped;
        raw.snap = false;
        refined.refine = 1;
        EXPECT_EQ(fdmsurf::detail::ses_band_steps(snapped), 1.0f);
        EXPECT_EQ(fdmsurf::detail::ses_band_steps(raw), 2.0f);
        EXPECT_EQ(fdmsurf::detail::ses_band_steps(refined), 2.0f);
        const fdmsurf::detail::GridPlan narrow = fdmsurf::detail::plan_grid(atoms, snapped);
        const fdmsurf::detail::GridPlan wide = fdmsurf::detail::plan_grid(atoms, raw);
        ASSERT_FLOAT_EQ(narrow.ses_d_max, 1.4f + spacing);
        ASSERT_FLOAT_EQ(narrow.ses_d_min, 1.4f - spacing);
        ASSERT_FLOAT_EQ(wide.ses_d_max, 1.4f + 2.0f * spacing);
        ASSERT_EQ(narrow.info.dims, wide.info.dims);
        const fdmsurf::Mesh a = ses_field_mesh(fdmsurf::detail::ses_field_cpu(f, narrow), narrow);
        const fdmsurf::Mesh b = ses_field_mesh(fdmsurf::detail::ses_field_cpu(f, wide), wide);
        EXPECT_GT(a.triangle_count(), spacing < 0.75f ? 10000u : 2000u);
        EXPECT_EQ(a.positions, b.positions);
        EXPECT_EQ(a.indices, b.indices);
        EXPECT_NE(a.normals, b.normals) << "no normal read a clamped neighbour";
    }
}

TEST(SesFeatures, GradientIsTheUnitDirectionFromTheNearestPoint) {
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    const SesFeatures f = build_ses_features(atoms, 1.4f);
    std::mt19937 rng(7);
    std::uniform_int_distribution<std::size_t> pick(0, atoms.size() - 1);
    std::size_t checked = 0;
    for (int n = 0; n < 300; ++n) {
        const std::size_t i = pick(rng);
        const double p[3] = {atoms.xyz[3 * i] + 2.5, atoms.xyz[3 * i + 1] + 0.7,
                             atoms.xyz[3 * i + 2] - 0.4};
        double g[3];
        const double d = ses_distance(f, p, 3.0, g);
        if (!(std::abs(d) < 2.9)) continue;
        // Central differences of d (smooth away from the medial axis: most points).
        const double e = 1e-4;
        double num[3];
        for (int k = 0; k < 3; ++k) {
            double a[3] = {p[0], p[1], p[2]}, b[3] = {p[0], p[1], p[2]};
            a[k] += e, b[k] -= e;
            num[k] = (ses_distance(f, a, 3.0) - ses_distance(f, b, 3.0)) / (2 * e);
        }
        const double diff = std::hypot(num[0] - g[0], num[1] - g[1], num[2] - g[2]);
        EXPECT_NEAR(std::hypot(g[0], g[1], g[2]), 1.0, 1e-9);
        checked += diff < 1e-3;
    }
    EXPECT_GT(checked, 200u);
}

// Each sphere's neighbour row is every other ball it intersects (|c_s - c_t| < R_s + R_t in
// double, R = r + probe), in ascending sphere order: against all pairs, on crambin moved far
// from the origin (the bins' bounds are floats there) and on a lattice of balls 6 Å apart
// whose inflated radii are 3 Å, on the bins' bounds: touching exactly (no intersection), or
// one float step nearer (an intersection).
TEST(SesFeatures, NeighbourRowsAreEveryIntersectingBall) {
    const Atoms crambin = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    Atoms far = crambin;
    for (std::size_t i = 0; i < far.size(); ++i) {
        far.xyz[3 * i] += 3000.0f;
        far.xyz[3 * i + 1] -= 2000.0f;
        far.xyz[3 * i + 2] += 1000.0f;
    }
    Atoms lattice;
    for (int x = 0; x < 7; ++x)
        for (int y = 0; y < 7; ++y)
            for (int z = 0; z < 7; ++z) {
                float p[3] = {6.0f * x, 6.0f * y, 6.0f * z};
                if ((x + 2 * y + z) % 3 == 0) p[0] = std::nextafter(p[0], -1.0f);
                lattice.xyz.insert(lattice.xyz.end(), {p[0], p[1], p[2]});
                lattice.radius.push_back(1.6f);  // 1.6f + 1.4f is 3 exactly
            }
    for (const Atoms* atoms : std::array<const Atoms*, 3>{&crambin, &far, &lattice}) {
        const float probe = 1.4f;
        const SesFeatures f = build_ses_features(*atoms, probe);
        const std::size_t n = f.sphere_count();
        ASSERT_EQ(n, atoms->size());
        // Each sphere's atom by its centre (all distinct here), for its inflated radius.
        std::map<std::array<float, 3>, std::size_t> atom_at;
        for (std::size_t i = 0; i < n; ++i)
            atom_at[{atoms->xyz[3 * i], atoms->xyz[3 * i + 1], atoms->xyz[3 * i + 2]}] = i;
        std::vector<double> R(n);
        for (std::size_t s = 0; s < n; ++s) {
            const auto it =
                atom_at.find({f.spheres[4 * s], f.spheres[4 * s + 1], f.spheres[4 * s + 2]});
            ASSERT_NE(it, atom_at.end());
            R[s] = double(atoms->radius[it->second]) + probe;
        }
        std::size_t pairs = 0;
        for (std::size_t s = 0; s < n; ++s) {
            std::vector<std::uint32_t> expect;
            for (std::size_t t = 0; t < n; ++t) {
                if (t == s) continue;
                double dd = 0.0;
                for (int k = 0; k < 3; ++k) {
                    const double d = double(f.spheres[4 * t + k]) - double(f.spheres[4 * s + k]);
                    dd += d * d;
                }
                const double reach = R[s] + R[t];
                if (dd < reach * reach) expect.push_back(static_cast<std::uint32_t>(t));
            }
            const std::vector<std::uint32_t> row(f.neighbours.begin() + f.neighbour_start[s],
                                                 f.neighbours.begin() + f.neighbour_start[s + 1]);
            ASSERT_EQ(row, expect) << "sphere " << s;
            pairs += row.size();
        }
        EXPECT_GT(pairs, 0u);
    }
}

}  // namespace

// The exposed arcs against a plain reference on hemoglobin (4,384 atoms): every pair of
// intersecting balls i < j, the interval of angles each other ball buries (acos and atan2 on the
// circle, no pseudo-angles, no cover bins, no balls tried first), their union. The circles, the
// ones buried whole, and the exposed length: the builder's early verdicts and its vectorised
// cuts (circle_cuts, as wide as the machine's vectors) change none of them.
TEST(SesFeatures, ArcsMatchAPlainReferenceOnHemoglobin) {
    const Atoms atoms = fdmsurf::read_structure(data_path("4hhb.xyzr")).atoms;
    const double probe = 1.4;
    const SesFeatures f = build_ses_features(atoms, float(probe));
    const std::size_t n = atoms.size();
    auto centre = [&](std::size_t i, int a) { return double(atoms.xyz[3 * i + a]); };
    auto R = [&](std::size_t i) { return double(atoms.radius[i]) + probe; };
    std::vector<std::vector<std::uint32_t>> near(n);
    for (std::size_t i = 0; i < n; ++i)
        for (std::size_t j = 0; j < n; ++j) {
            double d2 = 0.0;
            for (int a = 0; a < 3; ++a) d2 += std::pow(centre(i, a) - centre(j, a), 2);
            if (j != i && d2 < std::pow(R(i) + R(j), 2)) near[i].push_back(std::uint32_t(j));
        }
    std::size_t circles = 0, buried = 0;
    double exposed_length = 0.0;
    for (std::size_t i = 0; i < n; ++i)
        for (const std::uint32_t j : near[i]) {
            if (j <= i) continue;
            double u[3], d2 = 0.0;
            for (int a = 0; a < 3; ++a) u[a] = centre(j, a) - centre(i, a), d2 += u[a] * u[a];
            const double d = std::sqrt(d2);
            if (d <= std::abs(R(i) - R(j))) continue;
            for (double& x : u) x /= d;
            const double a_i = (d2 + R(i) * R(i) - R(j) * R(j)) / (2.0 * d);
            const double rho = std::sqrt(R(i) * R(i) - a_i * a_i);
            double m[3], e1[3], e2[3];
            for (int a = 0; a < 3; ++a) m[a] = centre(i, a) + a_i * u[a];
            const double t[3] = {std::abs(u[0]) < 0.6 ? 1.0 : 0.0, std::abs(u[0]) < 0.6 ? 0.0 : 1.0,
                                 0.0};
            e1[0] = u[1] * t[2] - u[2] * t[1], e1[1] = u[2] * t[0] - u[0] * t[2],
            e1[2] = u[0] * t[1] - u[1] * t[0];
            const double l = std::sqrt(e1[0] * e1[0] + e1[1] * e1[1] + e1[2] * e1[2]);
            for (double& x : e1) x /= l;
            e2[0] = u[1] * e1[2] - u[2] * e1[1], e2[1] = u[2] * e1[0] - u[0] * e1[2],
            e2[2] = u[0] * e1[1] - u[1] * e1[0];
            ++circles;
            // Buried angles [from, to] (to may pass 2 pi), from every other ball near i.
            std::vector<std::pair<double, double>> cuts;
            bool whole = false;
            for (const std::uint32_t k : near[i]) {
                if (k == j) continue;
                double w[3], A = 0.0, B = 0.0, w2 = 0.0;
                for (int a = 0; a < 3; ++a) w[a] = m[a] - centre(k, a);
                for (int a = 0; a < 3; ++a) A += w[a] * e1[a], B += w[a] * e2[a], w2 += w[a] * w[a];
                const double M = std::hypot(A, B);
                const double E = R(k) * R(k) - w2 - rho * rho;
                if (E <= -2.0 * rho * M) continue;  // misses the circle
                if (E >= 2.0 * rho * M) {
                    whole = true;
                    break;
                }
                // Inside where M cos(theta - psi) < E / (2 rho), psi the angle of (A, B): within
                // acos(-E / (2 rho M)) of phi = psi + pi.
                const double open = std::acos(-E / (2.0 * rho * M));
                const double phi = std::atan2(-B, -A);
                const double from = phi - open;
                cuts.push_back({from - 2.0 * kPi * std::floor(from / (2.0 * kPi)), 2.0 * open});
            }
            if (whole) {
                ++buried;
                continue;
            }
            std::vector<std::pair<double, double>> spans;  // [a, b] within [0, 4 pi)
            for (auto [from, len] : cuts) spans.push_back({from, from + len});
            std::sort(spans.begin(), spans.end());
            // The union over one turn, wrapped: spans reaching past 2 pi cover [0, end - 2 pi].
            double covered = 0.0, cursor = 0.0, wrap = 0.0;
            for (auto [a, b] : spans) wrap = std::max(wrap, b - 2.0 * kPi);
            cursor = wrap;
            for (auto [a, b] : spans) {
                const double lo = std::max(a, cursor), hi = std::min(b, 2.0 * kPi);
                if (hi > lo) covered += hi - lo;
                cursor = std::max(cursor, std::min(b, 2.0 * kPi));
            }
            covered += wrap;
            const double exposed = std::max(0.0, 2.0 * kPi - covered);
            if (exposed < 1e-9) ++buried;
            exposed_length += rho * exposed;
        }
    double arcs_length = 0.0;
    for (const SesArc& a : f.arcs) arcs_length += double(a.rho) * a.length;
    std::printf("  circles %zu (reference %zu), buried whole %zu (%zu), exposed %.3f Å (%.3f)\n",
                f.circles, circles, f.buried_circles, buried, arcs_length, exposed_length);
    EXPECT_EQ(f.circles, circles);
    // Circles whose last gap is about as small as rounding may go either way.
    EXPECT_NEAR(double(f.buried_circles), double(buried), 2.0);
    EXPECT_NEAR(arcs_length, exposed_length, 1e-5 * exposed_length);
    EXPECT_GT(f.arcs.size(), n);
}
