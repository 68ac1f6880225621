// The exact SES (--method edt) end to end: analytic one- and two-sphere surfaces, crambin against
// NanoShaper's analytical SES, cavities, slabs and refinement onto the exact distance.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <numbers>
#include <string>
#include <vector>

#include "fdmsurf/compare.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "grid/grid_plan.hpp"
#include "grid/ses_distance_cpu.hpp"
#include "grid/ses_features.hpp"
#include "mesh/cavities.hpp"
#include "support/crambin_reference.hpp"
#include "support/gpu_fixture.hpp"
#include "support/mesh_checks.hpp"
#include "support/test_atoms.hpp"
#include "support/test_data.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::CompareResult;
using fdmsurf::MeshStats;
using fdmsurf::SesMethod;
using fdmsurf::SurfaceOptions;
using fdmsurf::SurfaceResult;

constexpr double kPi = std::numbers::pi;

using fdmsurf::test::data_path;

using fdmsurf_test::make_atoms;

// Area and volume of the SES of two balls (radii r1, r2, centres D apart on the z axis, probe
// p) when the probe rolling around their contact stays off the axis: a surface of revolution
// whose profile is an arc of circle 1, the probe's concave arc and an arc of circle 2. Area
// = ∫ 2π ρ ds and volume = ∫ π ρ² dz along the profile, by the midpoint rule on 2e5 steps per
// arc (the arcs are exact; the quadrature error is below 1e-9 relative).
struct Revolution {
    double area = 0.0, volume = 0.0;
};
Revolution two_ball_ses(double r1, double r2, double D, double p) {
    const double zp = ((r1 + p) * (r1 + p) - (r2 + p) * (r2 + p) + D * D) / (2.0 * D);
    const double rp = std::sqrt((r1 + p) * (r1 + p) - zp * zp);
    EXPECT_GT(rp, p) << "the probe would cross the axis";
    Revolution out;
    // Arc of centre (cz, 0)-plane point (cz, cr), radius r, angle a0 -> a1 (z grows along it).
    auto arc = [&](double cz, double cr, double r, double a0, double a1) {
        const int n = 200000;
        const double da = (a1 - a0) / n;
        for (int i = 0; i < n; ++i) {
            const double a = a0 + (i + 0.5) * da;
            const double z0 = cz + r * std::cos(a0 + i * da),
                         z1 = cz + r * std::cos(a0 + (i + 1) * da);
            const double rho = cr + r * std::sin(a);
            out.area += 2.0 * kPi * rho * r * std::abs(da);
            out.volume += kPi * rho * rho * (z1 - z0);
        }
    };
    // Contact points: on each sphere towards the probe centre.
    const double t1 = std::atan2(rp, zp);       // angle of the contact on sphere 1
    const double t2 = std::atan2(rp, zp - D);   // on sphere 2
    const double s1 = std::atan2(-rp, -zp);     // angle of contact 1 seen from the probe centre
    const double s2 = std::atan2(-rp, D - zp);  // of contact 2
    arc(0.0, 0.0, r1, kPi, t1);                 // sphere 1 from its far pole to the contact
    arc(zp, rp, p, s1 + 2.0 * kPi, s2 + 2.0 * kPi);  // the probe's arc, under its centre
    arc(D, 0.0, r2, t2, 0.0);                        // sphere 2 from the contact to its far pole
    return out;
}

class ExactSes : public CrambinReferenceTest {};

TEST_F(ExactSes, OneBallIsItsOwnSes) {
    // The probe rolls over one ball without touching anything else: the SES is the ball. At
    // 0.25 Å the chords lose (measured on lavapipe, vertices snapped onto the exact distance)
    // 0.45% of the area and 0.93% of the volume (marching cubes alone, whose vertices
    // interpolate the distance linearly and lie inside: 0.61% and 1.16%); refined once onto the
    // exact distance, 0.11% and 0.23%.
    const Atoms atoms = make_atoms({{0.3f, -0.2f, 0.1f, 1.8f}});
    const double area = 4.0 * kPi * 1.8 * 1.8, volume = 4.0 / 3.0 * kPi * 1.8 * 1.8 * 1.8;
    for (int refine : {0, 1}) {
        const SurfaceResult r = engine().make_surface(
            atoms, SurfaceOptions{.method = SesMethod::Edt, .spacing = 0.25f, .refine = refine});
        ASSERT_TRUE(IsClosedManifold(r.mesh));
        const MeshStats s = fdmsurf::compute_stats(r.mesh);
        std::printf("  one ball, refine %d: dA %+.3f%%, dV %+.3f%%\n", refine,
                    100.0 * (s.area / area - 1.0), 100.0 * (s.volume / volume - 1.0));
        EXPECT_NEAR(s.area, area, (refine == 0 ? 0.01 : 0.003) * area);
        EXPECT_NEAR(s.volume, volume, (refine == 0 ? 0.015 : 0.004) * volume);
        EXPECT_EQ(s.pieces, 1u);
    }
}

TEST_F(ExactSes, TwoBallsGetTheirToroidalPatch) {
    // Radii 1.7 and 1.5 Å, 3.6 Å apart, probe 1.4 Å: the probe touches both, and the SES has a
    // concave toroidal band between the two spherical caps. Measured at 0.25 Å: dA -0.36%,
    // dV -0.85% (marching cubes alone -0.51%, -1.06%); refined once: -0.09%, -0.21% (the chord
    // deficit of one ball, above: the band adds no error of its own).
    const double r1 = 1.7, r2 = 1.5, D = 3.6, p = 1.4;
    const Revolution exact = two_ball_ses(r1, r2, D, p);
    // The band fills the groove: more volume than the union of the balls (minus their lens).
    const double lens =
        kPi * (r1 + r2 - D) * (r1 + r2 - D) *
        (D * D + 2 * D * r2 - 3 * r2 * r2 + 2 * D * r1 + 6 * r1 * r2 - 3 * r1 * r1) / (12 * D);
    EXPECT_GT(exact.volume, 4.0 / 3.0 * kPi * (r1 * r1 * r1 + r2 * r2 * r2) - lens + 1.0);
    // The balls along a tilted axis, so that nothing lines up with the grid.
    const float ux = 0.48f, uy = 0.6f, uz = 0.64f;  // unit vector
    const Atoms atoms = make_atoms(
        {{0.1f, 0.2f, -0.3f, float(r1)},
         {0.1f + float(D) * ux, 0.2f + float(D) * uy, -0.3f + float(D) * uz, float(r2)}});
    for (int refine : {0, 1}) {
        const SurfaceResult r = engine().make_surface(
            atoms, SurfaceOptions{.method = SesMethod::Edt, .spacing = 0.25f, .refine = refine});
        ASSERT_TRUE(IsClosedManifold(r.mesh));
        const MeshStats s = fdmsurf::compute_stats(r.mesh);
        std::printf("  two balls (A %.3f, V %.3f), refine %d: dA %+.3f%%, dV %+.3f%%\n", exact.area,
                    exact.volume, refine, 100.0 * (s.area / exact.area - 1.0),
                    100.0 * (s.volume / exact.volume - 1.0));
        EXPECT_NEAR(s.area, exact.area, (refine == 0 ? 0.01 : 0.003) * exact.area);
        EXPECT_NEAR(s.volume, exact.volume, (refine == 0 ? 0.015 : 0.004) * exact.volume);
    }
}

// Against NanoShaper's analytical SES of the same atoms and radii (tests/data), at 0.5 Å.
// Measured on lavapipe, vertices snapped onto the exact distance (the default since issue 13):
// weighted RMSD 0.0239 Å, dA -0.54%, dV -0.14% (refine 0); 0.0083 Å, -0.00%, -0.00% (refine 1).
// Marching cubes alone (snap off): 0.0272 Å, -0.95%, -0.19%. Issue 4 asked for 1% and 0.05 Å,
// issue 13 for ±0.7% without refine and an RMSD no worse; the FDM method reaches 0.16 Å.
TEST_F(ExactSes, SnappingOntoTheExactDistanceRecoversTheChordDeficit) {
    const SurfaceResult off = engine().make_surface(
        crambin(), SurfaceOptions{.method = SesMethod::Edt, .spacing = 0.5f, .snap = false});
    const SurfaceResult on =
        engine().make_surface(crambin(), SurfaceOptions{.method = SesMethod::Edt, .spacing = 0.5f});
    const CompareResult a = against_reference(off, 0.5), b = against_reference(on, 0.5);
    std::printf("  1crn edt: marching cubes RMSD %.4f Å, dA %+.2f%%; snapped %.4f Å, %+.2f%%\n",
                a.rmsd_weighted, 100.0 * a.area_rel_error, b.rmsd_weighted,
                100.0 * b.area_rel_error);
    // Same connectivity, vertices moved.
    EXPECT_EQ(on.mesh.indices, off.mesh.indices);
    EXPECT_LE(b.rmsd_weighted, a.rmsd_weighted);
    EXPECT_LE(std::abs(b.area_rel_error), 0.007);
    EXPECT_LT(std::abs(b.area_rel_error), std::abs(a.area_rel_error));
    // Every vertex within 1e-3 of a spacing of the exact level set.
    const fdmsurf::detail::SesFeatures features =
        fdmsurf::detail::build_ses_features(crambin(), 1.4f);
    double worst = 0.0;
    for (std::size_t v = 0; v < on.mesh.vertex_count(); ++v) {
        const double p[3] = {on.mesh.positions[3 * v], on.mesh.positions[3 * v + 1],
                             on.mesh.positions[3 * v + 2]};
        worst = std::max(worst,
                         std::abs(fdmsurf::detail::ses_distance(features, p, 2.4, nullptr) - 1.4));
    }
    std::printf("  snapped vertices at most %.2e Å from the exact SES\n", worst);
    EXPECT_LE(worst, 1e-3 * 0.5 + 1e-5);
}

TEST_F(ExactSes, CrambinMatchesTheAnalyticalSes) {
    for (int refine : {0, 1}) {
        const SurfaceResult r = engine().make_surface(
            crambin(), SurfaceOptions{.method = SesMethod::Edt, .spacing = 0.5f, .refine = refine});
        ASSERT_TRUE(IsClosedManifold(r.mesh));
        const CompareResult c = against_reference(r, 0.5);
        std::printf("  1crn edt refine %d: RMSD %.4f Å, dA %+.2f%%, dV %+.2f%%, Hausdorff %.3f Å\n",
                    refine, c.rmsd_weighted, 100.0 * c.area_rel_error, 100.0 * c.volume_rel_error,
                    c.hausdorff);
        EXPECT_LE(c.rmsd_weighted, refine == 0 ? 0.0272 : 0.015);
        EXPECT_LE(std::abs(c.area_rel_error), refine == 0 ? 0.007 : 0.003);
        EXPECT_LE(std::abs(c.volume_rel_error), refine == 0 ? 0.005 : 0.003);
        EXPECT_EQ(c.share_beyond_spacing, 0.0);
        EXPECT_LE(c.hausdorff, 0.25);
        // The outer surface and crambin's one internal cavity, as in the reference.
        EXPECT_EQ(fdmsurf::compute_stats(r.mesh).pieces, 2u);
        EXPECT_EQ(r.cavities_removed, 0u);
    }
}

TEST_F(ExactSes, NoCavitiesKeepsTheOuterSurfaceOnly) {
    const SurfaceResult r = engine().make_surface(
        crambin(), SurfaceOptions{.method = SesMethod::Edt,
                                  .spacing = 0.5f,
                                  .min_cavity_volume = std::numeric_limits<float>::infinity()});
    EXPECT_EQ(fdmsurf::compute_stats(r.mesh).pieces, 1u);
    EXPECT_EQ(r.cavities_removed, 1u);
}

TEST_F(ExactSes, SlabsGiveTheSameSurface) {
    // The field is exact per point, so slabs need no overlap and change nothing.
    const SurfaceOptions options{.method = SesMethod::Edt, .spacing = 0.5f};
    const auto plan = fdmsurf::detail::plan_grid(crambin(), options);
    const std::uint64_t limit = (plan.field_floats() * sizeof(float) / 3) & ~std::uint64_t(0xFFFF);
    fdmsurf::Engine small(fdmsurf::EngineOptions{.validation = true, .max_buffer_range = limit});
    const SurfaceResult sliced = small.make_surface(crambin(), options);
    EXPECT_TRUE(small.take_validation_messages().empty());
    const SurfaceResult whole = engine().make_surface(crambin(), options);
    EXPECT_GT(sliced.grid.slabs, 2u);
    ASSERT_TRUE(IsClosedManifold(sliced.mesh));
    const MeshStats s = fdmsurf::compute_stats(sliced.mesh), w = fdmsurf::compute_stats(whole.mesh);
    EXPECT_EQ(s.triangles, w.triangles);
    EXPECT_NEAR(s.area, w.area, 1e-6 * w.area);
    EXPECT_NEAR(s.volume, w.volume, 1e-6 * w.volume);
}

TEST_F(ExactSes, NeedsAProbe) {
    try {
        engine().make_surface(crambin(), SurfaceOptions{.method = SesMethod::Edt, .probe = 0.0f});
        FAIL() << "no error";
    } catch (const fdmsurf::Error& e) {
        EXPECT_EQ(e.code(), fdmsurf::ErrorCode::InvalidArgument);
        EXPECT_NE(std::string(e.what()).find("probe"), std::string::npos) << e.what();
    }
}

}  // namespace

namespace {

// Centroids of the cavities (pieces of negative volume) of a mesh, their vertices averaged.
std::vector<std::array<double, 3>> cavity_centroids(fdmsurf::Mesh mesh) {
    std::vector<std::array<double, 3>> out;
    fdmsurf::detail::remove_cavities_if(mesh, [&](const fdmsurf::detail::MeshPiece& c) {
        std::array<double, 3> sum{0, 0, 0};
        for (const auto& t : c.triangles)
            for (const auto& v : t)
                for (int a = 0; a < 3; ++a) sum[a] += v[a] / (3.0 * c.triangles.size());
        out.push_back(sum);
        return false;
    });
    return out;
}

// Issue 4: the FDM surface must have no interior piece that the SES lacks. On hemoglobin at
// 0.5 Å the filtered density has 30 voids; 27 hold no probe and are not SES cavities, two of
// them of 14 Å³, more than a probe's volume (the former rule, "less than a probe's volume",
// kept those). The default removes every void no probe fits in; the three left must be among
// the exact SES's 24 (NanoShaper's reference has the same 24; FDM smoothing closes the others).
TEST_F(ExactSes, FdmCavitiesAreCavitiesOfTheExactSes) {
    const Atoms atoms = fdmsurf::read_structure(data_path("4hhb.xyzr")).atoms;
    const SurfaceResult fdm = engine().make_surface(atoms, SurfaceOptions{.spacing = 0.5f});
    const SurfaceResult edt =
        engine().make_surface(atoms, SurfaceOptions{.method = SesMethod::Edt, .spacing = 0.5f});
    const auto mine = cavity_centroids(fdm.mesh), exact = cavity_centroids(edt.mesh);
    EXPECT_EQ(exact.size(), 24u);
    EXPECT_EQ(mine.size(), 3u);
    EXPECT_EQ(fdm.cavities_removed, 27u);
    for (const auto& c : mine) {
        double nearest = 1e9;
        for (const auto& e : exact)
            nearest = std::min(nearest, std::hypot(c[0] - e[0], c[1] - e[1], c[2] - e[2]));
        EXPECT_LT(nearest, 1.0) << "an FDM cavity at " << c[0] << ", " << c[1] << ", " << c[2]
                                << " is " << nearest << " Å from every SES cavity";
    }
}

}  // namespace
