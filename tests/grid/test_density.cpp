// Tests of the GPU density pass (src/grid/density_gpu.cpp, shaders/density.comp) against the
// brute-force double-precision reference of src/grid/density_cpu.cpp (Giard & Macq 2010, §2).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>
#include <string>
#include <vector>

#include "engine/engine_impl.hpp"
#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "grid/atom_bins.hpp"
#include "grid/density_cpu.hpp"
#include "grid/grid_plan.hpp"
#include "shader_interface.h"
#include "support/density_checks.hpp"
#include "support/gpu_fixture.hpp"
#include "support/test_data.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::SurfaceKind;
using fdmsurf::SurfaceOptions;
using fdmsurf::detail::density_at;
using fdmsurf::detail::density_cpu;
using fdmsurf::detail::GridPlan;
using fdmsurf::detail::plan_grid;

// Crambin, and a copy of it moved by `shift` Å along x: two clusters with empty space between.
Atoms two_crambins(float shift) {
    Atoms atoms = fdmsurf::read_structure(std::string(FDMSURF_TEST_DATA_DIR) + "/1crn.pdb").atoms;
    const std::size_t n = atoms.size();
    for (std::size_t i = 0; i < n; ++i) {
        atoms.xyz.push_back(atoms.xyz[3 * i] + shift);
        atoms.xyz.push_back(atoms.xyz[3 * i + 1]);
        atoms.xyz.push_back(atoms.xyz[3 * i + 2]);
        atoms.radius.push_back(atoms.radius[i]);
    }
    return atoms;
}

using fdmsurf::test::data_path;
using fdmsurf::test::DensityComparison;
using fdmsurf::test::report_density;

class Density : public GpuTest {
protected:
    // Every grid point of the GPU field against density_cpu (the row padding is not compared).
    void compare_whole_grid(const Atoms& atoms, const SurfaceOptions& options) {
        const GridPlan plan = plan_grid(atoms, options);
        const std::vector<float> gpu = impl().compute_field(atoms, plan, false);
        const std::vector<float> cpu = density_cpu(atoms, plan);
        ASSERT_EQ(gpu.size(), plan.field_floats());
        ASSERT_EQ(cpu.size(), plan.field_floats());
        const auto& d = plan.info.dims;
        DensityComparison c;
        double max_value = 0.0;
        for (std::uint32_t z = 0; z < d[2]; ++z)
            for (std::uint32_t y = 0; y < d[1]; ++y)
                for (std::uint32_t x = 0; x < d[0]; ++x) {
                    const std::size_t i = (std::size_t(z) * d[1] + y) * plan.pitch + x;
                    c.add(gpu[i], cpu[i], plan, x, y, z);
                    max_value = std::max(max_value, double(cpu[i]));
                }
        // Sanity: the field is not trivially empty (the density exceeds T inside atoms).
        EXPECT_GT(max_value, plan.density.level_t);
        report_density(c);
    }
};

TEST_F(Density, MatchesCpuReferenceOnCrambinSes) {
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.pdb")).atoms;
    compare_whole_grid(atoms, SurfaceOptions{.surface = SurfaceKind::Ses, .spacing = 0.5f});
}

TEST_F(Density, MatchesCpuReferenceOnCrambinSas) {
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.pdb")).atoms;
    compare_whole_grid(atoms, SurfaceOptions{.surface = SurfaceKind::Sas, .spacing = 0.5f});
}

TEST_F(Density, MatchesCpuReferenceOnHemoglobinRandomPoints) {
    const Atoms atoms = fdmsurf::read_structure(data_path("4hhb.xyzr")).atoms;
    ASSERT_EQ(atoms.size(), 4384u);
    const GridPlan plan = plan_grid(atoms, SurfaceOptions{.spacing = 0.5f});
    const std::vector<float> gpu = impl().compute_field(atoms, plan, false);
    ASSERT_EQ(gpu.size(), plan.field_floats());
    const auto& d = plan.info.dims;
    std::mt19937 rng(20100611);  // fixed seed
    std::uniform_int_distribution<std::uint32_t> ux(0, d[0] - 1), uy(0, d[1] - 1), uz(0, d[2] - 1);
    DensityComparison c;
    std::size_t nonzero = 0;
    for (int n = 0; n < 20000; ++n) {
        const std::uint32_t x = ux(rng), y = uy(rng), z = uz(rng);
        const double cpu = density_at(atoms, plan, x, y, z);
        nonzero += cpu > 0.0;
        c.add(gpu[(std::size_t(z) * d[1] + y) * plan.pitch + x], cpu, plan, x, y, z);
    }
    // About a quarter of the samples fall inside the Gaussian support (4948 with this seed).
    EXPECT_GT(nonzero, 4000u);
    report_density(c);
}

// Two crambins 60 Å apart: most tiles lie between or around them, out of every atom's reach,
// and are never visited (zero-filled); the field must still be the reference everywhere.
TEST_F(Density, MatchesCpuReferenceWithLargeEmptyRegions) {
    const Atoms atoms = two_crambins(60.0f);
    const SurfaceOptions options{.surface = SurfaceKind::Ses, .spacing = 0.7f};
    const GridPlan plan = plan_grid(atoms, options);
    const std::uint32_t group[3] = {fdmsurf::detail::shader::kDensityGroupX,
                                    fdmsurf::detail::shader::kDensityGroupY,
                                    fdmsurf::detail::shader::kDensityGroupZ};
    const auto reached =
        fdmsurf::detail::reached_boxes(fdmsurf::detail::bin_atoms(atoms, plan), plan, group);
    std::size_t boxes = 1;
    for (int a = 0; a < 3; ++a) boxes *= (plan.info.dims[a] + group[a] - 1) / group[a];
    EXPECT_LT(double(reached.size()), 0.5 * double(boxes));  // the skip is exercised
    compare_whole_grid(atoms, options);
}

// With at most 2 candidates stored per tile, nearly every tile overflows and its points take
// the per-point shell search: still the reference, and the first grid must not leak into the next.
TEST_F(Density, MatchesCpuReferenceWhenCandidatesOverflow) {
    impl().density.set_capacity_limit(2);
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.pdb")).atoms;
    compare_whole_grid(atoms, SurfaceOptions{.surface = SurfaceKind::Ses, .spacing = 0.5f});
    compare_whole_grid(atoms, SurfaceOptions{.surface = SurfaceKind::Sas, .spacing = 0.7f});
    impl().density.set_capacity_limit(0xffffffffu);
}

// A pool of 4,000 atom indices holds the lists of the first few hundred tiles to claim it; the
// others find it full and take the per-point search, in the same dispatch: both paths must have
// run, and give the reference. The pool's top must not be left over from one grid to the next.
TEST_F(Density, MatchesCpuReferenceWhenThePoolRunsOut) {
    struct Restore {
        ~Restore() { impl().density.set_pool_limit(~std::uint64_t{0}); }
    } restore;
    impl().density.set_pool_limit(4000);
    const Atoms atoms = fdmsurf::read_structure(data_path("1crn.pdb")).atoms;
    for (const float spacing : {0.5f, 0.6f}) {
        compare_whole_grid(atoms, SurfaceOptions{.surface = SurfaceKind::Ses, .spacing = spacing});
        if (const auto outcome = impl().density.list_outcome()) {
            EXPECT_GT(outcome->listed, 100u) << "spacing " << spacing;
            EXPECT_GT(outcome->overflowed, 100u) << "spacing " << spacing;
        }
    }
    // Without the limit every tile of crambin gets its list.
    impl().density.set_pool_limit(~std::uint64_t{0});
    compare_whole_grid(atoms, SurfaceOptions{.surface = SurfaceKind::Ses, .spacing = 0.5f});
    if (const auto outcome = impl().density.list_outcome()) {
        EXPECT_GT(outcome->listed, 1000u);
        EXPECT_EQ(outcome->overflowed, 0u);
    }
}

}  // namespace
