// Tests of SurfaceOptions::refine through Engine::make_surface: crambin against NanoShaper's
// analytical SES, an analytic ball, slabs, the device path's counts, and bad levels.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <numbers>
#include <string>
#include <vector>

#include "fdmsurf/compare.hpp"
#include "fdmsurf/error.hpp"
#include "fdmsurf/mesh.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "fdmsurf/vulkan_interop.hpp"
#include "grid/grid_plan.hpp"
#include "support/crambin_reference.hpp"
#include "support/gpu_fixture.hpp"
#include "support/mesh_checks.hpp"
#include "support/test_data.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::CompareResult;
using fdmsurf::Error;
using fdmsurf::ErrorCode;
using fdmsurf::MeshStats;
using fdmsurf::SurfaceKind;
using fdmsurf::SurfaceOptions;
using fdmsurf::SurfaceResult;

using fdmsurf::test::data_path;

bool has_stage(const SurfaceResult& r, const std::string& name) {
    for (const auto& t : r.times)
        if (t.name == name) return true;
    return false;
}

class RefineSurface : public CrambinReferenceTest {};

// Triangles whose geometric normal points against the mean of their vertices' normals (which
// come from the field's gradient): folds.
std::size_t folded_triangles(const fdmsurf::Mesh& m) {
    std::size_t folded = 0;
    for (std::size_t t = 0; t < m.triangle_count(); ++t) {
        const std::uint32_t* c = &m.indices[3 * t];
        double p[3][3], n[3] = {0, 0, 0};
        for (int i = 0; i < 3; ++i)
            for (int k = 0; k < 3; ++k) {
                p[i][k] = m.positions[3 * c[i] + k];
                n[k] += m.normals[3 * c[i] + k];
            }
        const double u[3] = {p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]};
        const double w[3] = {p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]};
        const double g[3] = {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                             u[0] * w[1] - u[1] * w[0]};
        if (g[0] * n[0] + g[1] * n[1] + g[2] * n[2] < 0.0) ++folded;
    }
    return folded;
}

// Refinement moves the mesh towards the FDM surface, which is 0.15-0.2 Å from the SES, so it can
// only win where the mesh's own (chord) error counts: much at 1 Å, a little at 0.5 Å. Measured
// on lavapipe (docs/accuracy.md), weighted RMSD / area error against NanoShaper:
//   1.0 Å: refine 0 0.1977 Å / -6.48%, refine 1 0.1713 Å / -4.67%
//   0.5 Å: refine 0 0.1645 Å / -4.39%, refine 1 0.1589 Å / -3.73%
// The bounds ask for most of that gain, so a change that makes refinement worse fails. Folded
// triangles (measured: 1 of 6,628 -> 17 of 26,512 at 1 Å, 2 of 26,600 -> 8 of 106,400 at 0.5 Å;
// the full butterfly stencil folded 4.4%) may be the four children of each folded one plus 0.1%.
TEST_F(RefineSurface, CrambinGetsCloserToTheAnalyticalSes) {
    struct Case {
        float spacing;
        double max_rmsd_ratio;  // refine 1 over refine 0
        double min_area_gain;   // |dA| of refine 0 minus |dA| of refine 1, fraction
    };
    for (const Case c : {Case{1.0f, 0.90, 0.012}, Case{0.5f, 0.98, 0.004}}) {
        SCOPED_TRACE("spacing " + std::to_string(c.spacing));
        const SurfaceResult r0 = engine().make_surface(crambin(), {.spacing = c.spacing});
        const SurfaceResult r1 =
            engine().make_surface(crambin(), {.spacing = c.spacing, .refine = 1});
        EXPECT_TRUE(IsClosedManifold(r1.mesh));
        EXPECT_EQ(r1.mesh.triangle_count(), 4 * r0.mesh.triangle_count());
        EXPECT_EQ(fdmsurf::compute_stats(r1.mesh).pieces, fdmsurf::compute_stats(r0.mesh).pieces);
        EXPECT_TRUE(has_stage(r1, "refine"));
        EXPECT_FALSE(has_stage(r0, "refine"));
        EXPECT_TRUE(r1.warnings.empty()) << r1.warnings.front();
        const CompareResult c0 = against_reference(r0, c.spacing);
        const CompareResult c1 = against_reference(r1, c.spacing);
        std::printf(
            "  1crn %.1f Å: refine 0 RMSD %.4f dA %+.2f%% dV %+.2f%%; refine 1 RMSD %.4f "
            "dA %+.2f%% dV %+.2f%%\n",
            c.spacing, c0.rmsd_weighted, 100 * c0.area_rel_error, 100 * c0.volume_rel_error,
            c1.rmsd_weighted, 100 * c1.area_rel_error, 100 * c1.volume_rel_error);
        EXPECT_LT(c1.rmsd_weighted, c.max_rmsd_ratio * c0.rmsd_weighted);
        EXPECT_GT(std::abs(c0.area_rel_error) - std::abs(c1.area_rel_error), c.min_area_gain);
        EXPECT_LT(std::abs(c1.volume_rel_error), 0.01);
        const std::size_t f0 = folded_triangles(r0.mesh), f1 = folded_triangles(r1.mesh);
        std::printf("  folded triangles: %zu of %zu, refined %zu of %zu\n", f0,
                    r0.mesh.triangle_count(), f1, r1.mesh.triangle_count());
        EXPECT_LE(f1, 4 * f0 + r1.mesh.triangle_count() / 1000);
    }
}

TEST_F(RefineSurface, VdwBallIsRefinedOntoTheSphere) {
    // Vertices go onto the ball exactly (projection onto the power distance), so what is left is
    // the chord deficit of the finer triangles: about four times smaller per level. Measured
    // without the snap stage (on by default since issue 13), whose chord splits would already
    // take the unrefined mesh to a fixed tolerance and hide the rate refinement gives.
    const double r = 1.8, kPi = std::numbers::pi;
    Atoms atoms;
    atoms.xyz = {0.3f, -0.7f, 1.1f};
    atoms.radius = {float(r)};
    atoms.element = {"S"};
    double previous = 1.0;
    for (int levels = 0; levels <= 2; ++levels) {
        const SurfaceResult res = engine().make_surface(
            atoms, {.surface = SurfaceKind::Vdw, .spacing = 0.5f, .refine = levels, .snap = false});
        EXPECT_TRUE(IsClosedManifold(res.mesh));
        const MeshStats s = fdmsurf::compute_stats(res.mesh);
        const double d_area = (s.area - 4 * kPi * r * r) / (4 * kPi * r * r);
        double worst = 0.0;
        for (std::size_t v = 0; v < res.mesh.vertex_count(); ++v) {
            const float* p = &res.mesh.positions[3 * v];
            worst = std::max(worst, std::abs(std::hypot(p[0] - 0.3, p[1] + 0.7, p[2] - 1.1) - r));
        }
        std::printf(
            "  vdw ball r 1.8, h 0.5, refine %d: %zu triangles, dA %+.3f%%, vertices off "
            "the sphere at most %.1e Å\n",
            levels, res.mesh.triangle_count(), 100 * d_area, worst);
        EXPECT_LT(worst, 1e-4);
        EXPECT_LT(std::abs(d_area), 0.4 * previous);
        previous = std::abs(d_area);
    }
}

TEST_F(RefineSurface, SlabsRefineLikeTheSingleGrid) {
    // Forced slabs: the field is assembled on the host and refinement projects onto it.
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.pdb")).atoms;
    const SurfaceOptions options{.spacing = 0.5f, .refine = 1};
    const auto plan = fdmsurf::detail::plan_grid(atoms, options);
    const std::uint64_t limit = std::min<std::uint64_t>(
        8u << 20, (plan.field_floats() * sizeof(float) * 2 / 3) & ~std::uint64_t(0xFFFF));
    fdmsurf::Engine small(fdmsurf::EngineOptions{.validation = true, .max_buffer_range = limit});
    const SurfaceResult sliced = small.make_surface(atoms, options);
    EXPECT_TRUE(small.take_validation_messages().empty());
    const SurfaceResult whole = engine().make_surface(atoms, options);
    EXPECT_GT(sliced.grid.slabs, 1u);
    EXPECT_TRUE(IsClosedManifold(sliced.mesh));
    EXPECT_TRUE(has_stage(sliced, "refine"));
    EXPECT_TRUE(sliced.warnings.empty());
    const MeshStats s = fdmsurf::compute_stats(sliced.mesh), w = fdmsurf::compute_stats(whole.mesh);
    EXPECT_NEAR(s.area, w.area, 0.01 * w.area);
    EXPECT_NEAR(s.volume, w.volume, 0.01 * w.volume);
}

TEST_F(RefineSurface, DeviceSurfaceCarriesTheRefinedMesh) {
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.pdb")).atoms;
    const SurfaceOptions options{.spacing = 1.0f, .min_cavity_volume = 0.0f, .refine = 1};
    // VkFFT's filter for both (a mesh left on the device keeps it; a CPU device's host filter,
    // a slightly different low-pass at 1 Å, would move a few vertices).
    fdmsurf::Engine e(fdmsurf::EngineOptions{.gaussian_filter = fdmsurf::StagePlace::Device});
    const SurfaceResult host = e.make_surface(atoms, options);
    const fdmsurf::DeviceSurfaceResult dev = e.make_device_surface(atoms, options);
    EXPECT_EQ(dev.mesh.vertex_count(), host.mesh.vertex_count());
    EXPECT_EQ(dev.mesh.triangle_count(), host.mesh.triangle_count());
    bool refined = false;
    for (const auto& t : dev.times) refined = refined || t.name == "refine";
    EXPECT_TRUE(refined);
}

TEST_F(RefineSurface, BadLevelsAreRefusedBeforeAnyWork) {
    Atoms atoms;
    atoms.xyz = {0.0f, 0.0f, 0.0f};
    atoms.radius = {1.5f};
    atoms.element = {"C"};
    for (int levels : {-1, 5, 100}) {
        try {
            engine().make_surface(atoms, {.refine = levels});
            ADD_FAILURE() << "no error for refine " << levels;
        } catch (const Error& e) {
            EXPECT_EQ(e.code(), ErrorCode::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find("refine must be between 0 and 4"),
                      std::string::npos)
                << e.what();
        }
    }
}

}  // namespace
