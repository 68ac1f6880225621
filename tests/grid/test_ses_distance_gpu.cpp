// Tests of the GPU exact SES field (src/grid/ses_distance_gpu.cpp, shaders/ses_distance.comp)
// against its CPU reference (src/grid/ses_distance_cpu.cpp) on real structures.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "grid/grid_plan.hpp"
#include "grid/ses_distance_cpu.hpp"
#include "grid/ses_distance_gpu.hpp"
#include "grid/ses_features.hpp"
#include "shader_interface.h"
#include "support/gpu_fixture.hpp"
#include "support/ses_field_diff.hpp"
#include "support/test_data.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::SesMethod;
using fdmsurf::SurfaceOptions;
using fdmsurf::detail::GridPlan;
using fdmsurf::detail::plan_grid;

using fdmsurf::test::data_path;

using fdmsurf_test::compare_ses_fields;
using FieldDiff = fdmsurf_test::SesFieldDiff;

class SesDistanceGpu : public GpuTest {
protected:
    void check_box_skipping(float spacing);
};

TEST_F(SesDistanceGpu, MatchesCpuReferenceOnCrambin) {
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    const auto features = fdmsurf::detail::build_ses_features(atoms, 1.4f);
    // Both bands: one spacing each side where the snap follows, two without it.
    for (const bool snap : {true, false}) {
        const SurfaceOptions options{.method = SesMethod::Edt, .spacing = 0.5f, .snap = snap};
        const GridPlan plan = plan_grid(atoms, options);
        ASSERT_TRUE(plan.exact_ses);
        const std::vector<float> cpu = fdmsurf::detail::ses_field_cpu(features, plan);
        const std::vector<float> gpu = impl().compute_ses_field(atoms, plan, options.probe);
        ASSERT_EQ(gpu.size(), cpu.size());
        const FieldDiff r = compare_ses_fields(gpu, cpu, plan);
        std::printf("  ses field (snap %d): %zu points, %zu in the band, max |gpu - cpu| %.3g Å\n",
                    int(snap), r.points, r.band, r.max_diff);
        EXPECT_EQ(r.bad, 0u) << "max |gpu - cpu| " << r.max_diff;
        EXPECT_GT(r.band, r.points / (snap ? 20 : 10));  // the surface band, not only clamps
    }
}

TEST_F(SesDistanceGpu, PerPointFallbackMatchesTheSharedLists) {
    // The fallback (boxes whose candidates overflow shared memory) forced everywhere.
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    const SurfaceOptions options{.method = SesMethod::Edt, .spacing = 1.0f};
    const GridPlan plan = plan_grid(atoms, options);
    const std::vector<float> shared = impl().compute_ses_field(atoms, plan, options.probe);
    const std::vector<float> global = impl().compute_ses_field(atoms, plan, options.probe, true);
    const auto features = fdmsurf::detail::build_ses_features(atoms, options.probe);
    const std::vector<float> cpu = fdmsurf::detail::ses_field_cpu(features, plan);
    const FieldDiff a = compare_ses_fields(global, cpu, plan), b = compare_ses_fields(shared, cpu, plan);
    EXPECT_EQ(a.bad, 0u) << "fallback: max |gpu - cpu| " << a.max_diff;
    EXPECT_EQ(b.bad, 0u) << "shared lists: max |gpu - cpu| " << b.max_diff;
}

TEST_F(SesDistanceGpu, CoarseGridsOverflowIntoTheFallbackAndStayExact) {
    // At 4 Å a workgroup's box (8 x 4 x 2 points) spans 28 x 12 x 4 Å and its candidates
    // (spheres within R + d_max = 3.2 + 13.4 Å) exceed kSesSphereCapacity in hemoglobin's core:
    // those boxes take the per-point path.
    const Atoms atoms = fdmsurf::read_structure(data_path("4hhb.xyzr")).atoms;
    const SurfaceOptions options{.method = SesMethod::Edt, .spacing = 4.0f};
    const GridPlan plan = plan_grid(atoms, options);
    const auto features = fdmsurf::detail::build_ses_features(atoms, options.probe);
    // The shader's gather, for the box holding the grid's centre point.
    const auto& dims = plan.info.dims;
    float lo[3], hi[3];
    const std::uint32_t group[3] = {
        fdmsurf::detail::shader::kSesGroupX, fdmsurf::detail::shader::kSesGroupY,
        fdmsurf::detail::shader::kSesGroupZ * fdmsurf::detail::ses_points_z(plan.info.spacing)};
    for (int a = 0; a < 3; ++a) {
        const std::uint32_t first = dims[a] / 2 / group[a] * group[a];
        const std::uint32_t last = std::min(first + group[a] - 1, dims[a] - 1);
        lo[a] = plan.info.origin[a] + plan.info.spacing * float(first);
        hi[a] = plan.info.origin[a] + plan.info.spacing * float(last);
    }
    std::size_t gathered = 0;
    for (std::size_t s = 0; s < features.sphere_count(); ++s) {
        float gap2 = 0.0f;
        for (int a = 0; a < 3; ++a) {
            const float c = features.spheres[4 * s + a];
            const float g = std::max({lo[a] - c, c - hi[a], 0.0f});
            gap2 += g * g;
        }
        const float r = features.spheres[4 * s + 3] + plan.ses_d_max;
        gathered += gap2 < r * r;
    }
    EXPECT_GT(gathered, fdmsurf::detail::shader::kSesSphereCapacity);
    const std::vector<float> cpu = fdmsurf::detail::ses_field_cpu(features, plan);
    const std::vector<float> gpu = impl().compute_ses_field(atoms, plan, options.probe);
    const FieldDiff r = compare_ses_fields(gpu, cpu, plan);
    EXPECT_EQ(r.bad, 0u) << "max |gpu - cpu| " << r.max_diff;
}

// ses_boxes.comp against its CPU reference (all spheres, not the bins), on hemoglobin: the same
// class for every box but those whose centre is within float rounding of the threshold; every
// point of a box classed outside has, in the CPU reference field, exactly d_min; and the field
// with those boxes skipped is the field with every box evaluated, bit for bit.
void SesDistanceGpu::check_box_skipping(float spacing) {
    const Atoms atoms = fdmsurf::read_structure(data_path("4hhb.xyzr")).atoms;
    const SurfaceOptions options{.method = SesMethod::Edt, .spacing = spacing};
    const GridPlan plan = plan_grid(atoms, options);
    const auto features = fdmsurf::detail::build_ses_features(atoms, options.probe);
    const std::uint32_t points_z = fdmsurf::detail::ses_points_z(plan.info.spacing);
    std::vector<std::uint32_t> gpu_classes;
    const std::vector<float> skipped =
        impl().compute_ses_field(atoms, plan, options.probe, false, true, &gpu_classes);
    const std::vector<float> every =
        impl().compute_ses_field(atoms, plan, options.probe, false, false);
    const std::vector<std::uint32_t> cpu_classes =
        fdmsurf::detail::ses_box_classes_cpu(features, plan, points_z);
    ASSERT_EQ(gpu_classes.size(), cpu_classes.size());
    namespace sh = fdmsurf::detail::shader;
    std::size_t outside = 0, differ = 0;
    for (std::size_t b = 0; b < cpu_classes.size(); ++b) {
        ASSERT_TRUE(gpu_classes[b] == sh::kSesBoxBand || gpu_classes[b] == sh::kSesBoxOutside);
        outside += gpu_classes[b] == sh::kSesBoxOutside;
        differ += gpu_classes[b] != cpu_classes[b];
    }
    std::printf("  %zu boxes, %.1f%% outside; %zu classed otherwise by the CPU reference\n",
                cpu_classes.size(), 100.0 * double(outside) / double(cpu_classes.size()), differ);
    EXPECT_LE(differ, cpu_classes.size() / 1000);
    // Many boxes are skipped (hemoglobin: 55% at 0.5 Å, 47% at 1 Å): the test covers skipping.
    EXPECT_GT(outside, cpu_classes.size() / 3);

    // Conservative: the CPU reference field at every point of every skipped box.
    const auto& d = plan.info.dims;
    const auto boxes = fdmsurf::detail::ses_boxes(plan);
    const std::uint32_t span[3] = {sh::kSesGroupX, sh::kSesGroupY, sh::kSesGroupZ * points_z};
    std::size_t checked = 0, wrong = 0;
    for (std::uint32_t z = 0; z < d[2]; ++z)
        for (std::uint32_t y = 0; y < d[1]; ++y)
            for (std::uint32_t x = 0; x < d[0]; ++x) {
                const std::size_t b =
                    (std::size_t(z / span[2]) * boxes[1] + y / span[1]) * boxes[0] + x / span[0];
                if (gpu_classes[b] != sh::kSesBoxOutside) continue;
                const double p[3] = {double(plan.info.origin[0] + plan.info.spacing * float(x)),
                                     double(plan.info.origin[1] + plan.info.spacing * float(y)),
                                     double(plan.info.origin[2] + plan.info.spacing * float(z))};
                const float value = std::max(
                    float(fdmsurf::detail::ses_distance(features, p, plan.ses_d_max)),
                    plan.ses_d_min);
                ++checked;
                wrong += value != plan.ses_d_min;
                const std::size_t i = (std::size_t(z) * d[1] + y) * plan.pitch + x;
                wrong += skipped[i] != plan.ses_d_min;
            }
    EXPECT_GT(checked, plan.points() / 3);
    EXPECT_EQ(wrong, 0u);
    ASSERT_EQ(skipped.size(), every.size());
    std::size_t mismatched = 0;
    for (std::size_t i = 0; i < skipped.size(); ++i) mismatched += skipped[i] != every[i];
    EXPECT_EQ(mismatched, 0u);
}

// The default spacing, and 1 Å, where points_z is 1 rather than 2: a box spans twice the
// length in x and y, half in z, and more of the boxes cross the surface.
TEST_F(SesDistanceGpu, BoxesOutsideTheBallsAreSkippedExactly) { check_box_skipping(0.5f); }
TEST_F(SesDistanceGpu, BoxesOutsideTheBallsAreSkippedExactlyAtOneAngstrom) {
    check_box_skipping(1.0f);
}

}  // namespace
