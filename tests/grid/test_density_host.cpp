// Tests of the host's density pass (src/grid/density_host.cpp) against the brute-force
// reference (src/grid/density_cpu.cpp) and against the device's pass (shaders/density.comp),
// whose least powers it must reproduce bit for bit.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "engine/engine_impl.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "grid/atom_bins.hpp"
#include "grid/density_cpu.hpp"
#include "grid/density_host.hpp"
#include "grid/grid_plan.hpp"
#include "support/density_checks.hpp"
#include "support/gpu_fixture.hpp"
#include "support/test_data.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::SurfaceKind;
using fdmsurf::SurfaceOptions;
using fdmsurf::detail::bin_atoms;
using fdmsurf::detail::density_cpu;
using fdmsurf::detail::density_host;
using fdmsurf::detail::GridPlan;
using fdmsurf::detail::plan_grid;
using fdmsurf::test::data_path;
using fdmsurf::test::DensityComparison;
using fdmsurf::test::report_density;

Atoms read_atoms(const std::string& name) { return fdmsurf::read_structure(data_path(name)).atoms; }

// The host's field in the device buffer's layout (plan.pitch floats per row; the padding is
// set to a marker that must survive: the pass writes only the grid's points).
std::vector<float> host_field(const Atoms& atoms, const GridPlan& plan, unsigned threads = 0) {
    std::vector<float> field(plan.field_floats(), -7.0f);
    density_host(bin_atoms(atoms, plan), plan, field.data(), plan.pitch, threads);
    return field;
}

void compare_with_reference(const Atoms& atoms, const SurfaceOptions& options) {
    const GridPlan plan = plan_grid(atoms, options);
    const std::vector<float> host = host_field(atoms, plan);
    const std::vector<float> cpu = density_cpu(atoms, plan);
    const auto& d = plan.info.dims;
    DensityComparison c;
    std::size_t nonzero = 0;
    for (std::uint32_t z = 0; z < d[2]; ++z)
        for (std::uint32_t y = 0; y < d[1]; ++y) {
            const std::size_t row = (std::size_t(z) * d[1] + y) * plan.pitch;
            for (std::uint32_t x = 0; x < d[0]; ++x) {
                c.add(host[row + x], cpu[row + x], plan, x, y, z);
                nonzero += host[row + x] > 0.0f;
            }
            for (std::uint32_t x = d[0]; x < plan.pitch; ++x)
                ASSERT_EQ(host[row + x], -7.0f) << "padding of row " << y << ", plane " << z;
        }
    EXPECT_GT(nonzero, 5000u);  // not trivially empty
    report_density(c);
}

TEST(DensityHost, MatchesCpuReferenceOnCrambinSesAndSas) {
    const Atoms atoms = read_atoms("1crn.pdb");
    compare_with_reference(atoms, SurfaceOptions{.surface = SurfaceKind::Ses, .spacing = 0.5f});
    compare_with_reference(atoms, SurfaceOptions{.surface = SurfaceKind::Sas, .spacing = 0.7f});
    // A coarse grid: boxes of 8 x 4 x 4 points wider than the atoms' bins.
    compare_with_reference(atoms, SurfaceOptions{.surface = SurfaceKind::Ses, .spacing = 1.3f});
}

// Two crambins 60 Å apart: most boxes are out of every atom's reach and only zeroed.
TEST(DensityHost, MatchesCpuReferenceWithLargeEmptyRegions) {
    Atoms atoms = read_atoms("1crn.pdb");
    const std::size_t n = atoms.size();
    for (std::size_t i = 0; i < n; ++i) {
        atoms.xyz.insert(atoms.xyz.end(), {atoms.xyz[3 * i] + 60.0f, atoms.xyz[3 * i + 1],
                                           atoms.xyz[3 * i + 2]});
        atoms.radius.push_back(atoms.radius[i]);
    }
    compare_with_reference(atoms, SurfaceOptions{.surface = SurfaceKind::Ses, .spacing = 0.7f});
}

// One thread and all threads write the same field (each layer of boxes belongs to one thread).
TEST(DensityHost, SameFieldOnAnyNumberOfThreads) {
    const Atoms atoms = read_atoms("4hhb.xyzr");
    const GridPlan plan = plan_grid(atoms, SurfaceOptions{.spacing = 0.6f});
    EXPECT_EQ(host_field(atoms, plan, 1), host_field(atoms, plan, 3));
}

class DensityHostVsDevice : public GpuTest {};

// The device's pass and the host's take the least power over the same atoms with the same float
// expression: the same powers, so the same points cut to 0 (no ties), and values that differ
// only by the exponential's rounding (a few ulps).
TEST_F(DensityHostVsDevice, SameLeastPowersOnHemoglobin) {
    const Atoms atoms = read_atoms("4hhb.xyzr");
    for (const auto& options : {SurfaceOptions{.spacing = 0.5f},
                                SurfaceOptions{.surface = SurfaceKind::Sas, .spacing = 1.0f}}) {
        const GridPlan plan = plan_grid(atoms, options);
        const std::vector<float> device = impl().compute_field(atoms, plan, false);
        const std::vector<float> host = host_field(atoms, plan);
        const auto& d = plan.info.dims;
        std::size_t nonzero = 0, zero_mismatch = 0;
        double max_rel = 0.0;
        for (std::uint32_t z = 0; z < d[2]; ++z)
            for (std::uint32_t y = 0; y < d[1]; ++y)
                for (std::uint32_t x = 0; x < d[0]; ++x) {
                    const std::size_t i = (std::size_t(z) * d[1] + y) * plan.pitch + x;
                    if ((device[i] == 0.0f) != (host[i] == 0.0f)) {
                        ++zero_mismatch;
                        continue;
                    }
                    if (device[i] == 0.0f) continue;
                    ++nonzero;
                    max_rel = std::max(max_rel,
                                       std::abs(double(host[i]) - device[i]) / double(device[i]));
                }
        std::printf("  spacing %.2f: %zu non-zero points, max relative difference %.3g\n",
                    double(options.spacing), nonzero, max_rel);
        EXPECT_GT(nonzero, plan.points() / 20);
        EXPECT_EQ(zero_mismatch, 0u);
        EXPECT_LE(max_rel, 1e-6);  // the exponentials' rounding, not the powers'
    }
}

}  // namespace
