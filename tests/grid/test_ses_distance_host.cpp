// Tests of the exact SES field on the host (src/grid/ses_distance_host.cpp) against its CPU
// reference (ses_field_cpu, src/grid/ses_distance_cpu.cpp) and the device's pass.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>
#include <vector>

#include "fdmsurf/error.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "grid/grid_plan.hpp"
#include "grid/ses_distance_cpu.hpp"
#include "grid/ses_distance_host.hpp"
#include "grid/ses_features.hpp"
#include "support/gpu_fixture.hpp"
#include "support/test_atoms.hpp"
#include "support/test_data.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::SesMethod;
using fdmsurf::SurfaceOptions;
using fdmsurf::detail::build_ses_features;
using fdmsurf::detail::GridPlan;
using fdmsurf::detail::plan_grid;
using fdmsurf::detail::SesHostField;
using fdmsurf::test::data_path;

// The GPU test's tolerance (test_ses_distance_gpu.cpp): the host works in float like the shader
// for the depths and burial tests, in double for the arcs, with another summation order.
constexpr double kTolerance = 5e-5;

struct FieldDiff {
    std::size_t points = 0, band = 0, bad = 0;
    double max_diff = 0.0;
};

FieldDiff compare(const std::vector<float>& a, const std::vector<float>& b, const GridPlan& plan) {
    FieldDiff r;
    const auto& d = plan.info.dims;
    for (std::uint32_t z = 0; z < d[2]; ++z)
        for (std::uint32_t y = 0; y < d[1]; ++y)
            for (std::uint32_t x = 0; x < d[0]; ++x) {
                const std::size_t i = (std::size_t(z) * d[1] + y) * plan.pitch + x;
                const double diff = std::abs(double(a[i]) - b[i]);
                ++r.points;
                r.band += b[i] > plan.ses_d_min && b[i] < plan.ses_d_max;
                r.max_diff = std::max(r.max_diff, diff);
                r.bad += !(diff <= kTolerance);
            }
    return r;
}

FieldDiff host_against_reference(const Atoms& atoms, float spacing, unsigned threads = 0) {
    const SurfaceOptions options{.method = SesMethod::Edt, .spacing = spacing};
    const GridPlan plan = plan_grid(atoms, options);
    EXPECT_TRUE(plan.exact_ses);
    const auto features = build_ses_features(atoms, options.probe);
    const std::vector<float> cpu = fdmsurf::detail::ses_field_cpu(features, plan);
    const std::vector<float> host = SesHostField(features, threads).field(plan);
    EXPECT_EQ(host.size(), cpu.size());
    const FieldDiff r = compare(host, cpu, plan);
    std::printf("  %.2f Å: %zu points, %zu in the band, max |host - cpu| %.3g Å\n", spacing,
                r.points, r.band, r.max_diff);
    return r;
}

TEST(SesDistanceHost, MatchesCpuReferenceOnCrambin) {
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    const FieldDiff r = host_against_reference(atoms, 0.5f);
    EXPECT_EQ(r.bad, 0u) << "max |host - cpu| " << r.max_diff;
    EXPECT_GT(r.band, r.points / 10);  // the comparison covers the surface band
}

TEST(SesDistanceHost, MatchesCpuReferenceOnHemoglobinAtOneAngstrom) {
    const Atoms atoms = fdmsurf::read_structure(data_path("4hhb.xyzr")).atoms;
    const FieldDiff r = host_against_reference(atoms, 1.0f, 3);
    EXPECT_EQ(r.bad, 0u) << "max |host - cpu| " << r.max_diff;
    EXPECT_GT(r.band, r.points / 10);
}

TEST(SesDistanceHost, CoarseGridsReachOutsideTheBalls) {
    // At 3 Å the lower clamp r_s - 2h is -4.6 Å: points outside the balls keep -(their distance
    // to them) down to it, which the depths must reach beyond the balls.
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    const SurfaceOptions options{.method = SesMethod::Edt, .spacing = 3.0f};
    ASSERT_LT(plan_grid(atoms, options).ses_d_min, -4.0f);
    const FieldDiff r = host_against_reference(atoms, 3.0f);
    EXPECT_EQ(r.bad, 0u) << "max |host - cpu| " << r.max_diff;
}

TEST(SesDistanceHost, TiesAndCentresOnGridPoints) {
    // Equal balls symmetric about grid planes: every point of the bisector planes is as deep in
    // two balls (the tie path), and the centres are grid points (the projection's special case).
    const Atoms atoms = fdmsurf_test::make_atoms({{0.0f, 0.0f, 0.0f, 1.5f},
                                                  {3.0f, 0.0f, 0.0f, 1.5f},
                                                  {1.5f, 2.5f, 0.0f, 1.5f},
                                                  {1.5f, 1.0f, 2.5f, 1.5f}});
    const FieldDiff r = host_against_reference(atoms, 0.25f);
    EXPECT_EQ(r.bad, 0u) << "max |host - cpu| " << r.max_diff;
    EXPECT_GT(r.band, r.points / 20);
}

TEST(SesDistanceHost, RandomAtomsMatchTheReference) {
    // Random balls packed closer than in proteins, radii 1-2.2 Å, one pair coincident and one
    // ball inside another: many buried faces, short arcs, three-ball points.
    std::mt19937 rng(17);
    std::uniform_real_distribution<float> pos(0.0f, 9.0f), rad(1.0f, 2.2f);
    Atoms atoms;
    for (int i = 0; i < 60; ++i) {
        atoms.xyz.insert(atoms.xyz.end(), {pos(rng), pos(rng), pos(rng)});
        atoms.radius.push_back(rad(rng));
    }
    atoms.xyz.insert(atoms.xyz.end(), {atoms.xyz[0], atoms.xyz[1], atoms.xyz[2]});
    atoms.radius.push_back(atoms.radius[0]);
    atoms.xyz.insert(atoms.xyz.end(), {atoms.xyz[3] + 0.1f, atoms.xyz[4], atoms.xyz[5]});
    atoms.radius.push_back(0.5f);
    for (float spacing : {0.3f, 0.7f}) {
        const FieldDiff r = host_against_reference(atoms, spacing);
        EXPECT_EQ(r.bad, 0u) << spacing << " Å: max |host - cpu| " << r.max_diff;
    }
}

TEST(SesDistanceHost, PlaneRangesAndThreadCountsGiveTheSameValues) {
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    const SurfaceOptions options{.method = SesMethod::Edt, .spacing = 0.6f};
    const GridPlan plan = plan_grid(atoms, options);
    const auto features = build_ses_features(atoms, options.probe);
    const std::vector<float> one = SesHostField(features, 1).field(plan);
    const std::vector<float> many = SesHostField(features, 7).field(plan);
    EXPECT_EQ(one, many);
    // Planes [5, 23) alone, in rows of nx + 3 floats: the whole field's planes, bit for bit.
    const auto& d = plan.info.dims;
    const std::size_t pitch = d[0] + 3;
    std::vector<float> part(std::size_t(18) * d[1] * pitch, -99.0f);
    SesHostField(features, 2).evaluate(plan, 5, 23, part.data(), pitch);
    std::size_t differ = 0, padding = 0;
    for (std::uint32_t z = 5; z < 23; ++z)
        for (std::uint32_t y = 0; y < d[1]; ++y) {
            const float* row = &part[(std::size_t(z - 5) * d[1] + y) * pitch];
            for (std::uint32_t x = 0; x < d[0]; ++x)
                differ += row[x] != one[(std::size_t(z) * d[1] + y) * plan.pitch + x];
            for (std::size_t x = d[0]; x < pitch; ++x) padding += row[x] != -99.0f;
        }
    EXPECT_EQ(differ, 0u);
    EXPECT_EQ(padding, 0u);  // rows are written within nx
}

TEST(SesDistanceHost, RejectsBadRanges) {
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.xyzr")).atoms;
    const SurfaceOptions options{.method = SesMethod::Edt, .spacing = 1.0f};
    const GridPlan plan = plan_grid(atoms, options);
    const auto features = build_ses_features(atoms, options.probe);
    const SesHostField field(features);
    std::vector<float> out(plan.field_floats());
    const auto& d = plan.info.dims;
    for (auto [a, b, pitch] : {std::tuple{3u, 3u, std::size_t(plan.pitch)},
                               std::tuple{0u, d[2] + 1, std::size_t(plan.pitch)},
                               std::tuple{0u, d[2], std::size_t(d[0] - 1)}}) {
        try {
            field.evaluate(plan, a, b, out.data(), pitch);
            ADD_FAILURE() << "no error for planes [" << a << ", " << b << ") pitch " << pitch;
        } catch (const fdmsurf::Error& e) {
            EXPECT_EQ(e.code(), fdmsurf::ErrorCode::InvalidArgument);
            EXPECT_NE(std::string(e.what()).find("host SES field"), std::string::npos) << e.what();
        }
    }
    GridPlan fdm = plan;
    fdm.exact_ses = false;
    EXPECT_THROW(field.evaluate(fdm, 0, d[2], out.data(), plan.pitch), fdmsurf::Error);
}

// The device's pass and the host's on hemoglobin at the default spacing: both within the
// tolerance of the reference, so within twice it of each other (the reference would take
// minutes on this grid).
class SesDistanceHostGpu : public GpuTest {};

TEST_F(SesDistanceHostGpu, MatchesTheDevicesPassOnHemoglobin) {
    const Atoms atoms = fdmsurf::read_structure(data_path("4hhb.xyzr")).atoms;
    const SurfaceOptions options{.method = SesMethod::Edt, .spacing = 0.5f};
    const GridPlan plan = plan_grid(atoms, options);
    const auto features = build_ses_features(atoms, options.probe);
    const std::vector<float> gpu = impl().compute_ses_field(atoms, plan, options.probe);
    const std::vector<float> host = SesHostField(features).field(plan);
    ASSERT_EQ(gpu.size(), host.size());
    FieldDiff r = compare(host, gpu, plan);
    std::printf("  %zu points, %zu in the band, max |host - gpu| %.3g Å\n", r.points, r.band,
                r.max_diff);
    EXPECT_LE(r.max_diff, 2 * kTolerance);
    EXPECT_GT(r.band, r.points / 10);
}

}  // namespace
