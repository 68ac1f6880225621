// Tests of src/grid/atom_bins.cpp: the bins and the boxes (density tiles) that atoms reach.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <string>
#include <vector>

#include "fdmsurf/structure.hpp"
#include "fdmsurf/surface.hpp"
#include "grid/atom_bins.hpp"
#include "grid/grid_plan.hpp"

namespace {

using fdmsurf::Atoms;
using fdmsurf::SurfaceKind;
using fdmsurf::SurfaceOptions;
using fdmsurf::detail::bin_atoms;
using fdmsurf::detail::GridPlan;
using fdmsurf::detail::plan_grid;
using fdmsurf::detail::reached_boxes;

// The least power distance over the points of box (bx, by, bz), brute force in double.
double box_min_power(const Atoms& atoms, const GridPlan& plan, const std::uint32_t group[3],
                     std::uint32_t bx, std::uint32_t by, std::uint32_t bz) {
    const auto& g = plan.info;
    double best = std::numeric_limits<double>::infinity();
    const std::uint32_t b[3] = {bx, by, bz};
    std::uint32_t lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = b[a] * group[a];
        hi[a] = std::min(lo[a] + group[a], g.dims[a]) - 1;
    }
    for (std::size_t i = 0; i < atoms.size(); ++i) {
        const double r = atoms.radius[i] + plan.density.radius_add;
        double d2 = 0.0;
        // The nearest grid point of the box to the atom, axis by axis.
        for (int a = 0; a < 3; ++a) {
            const double c = atoms.xyz[3 * i + a];
            double k = std::round((c - g.origin[a]) / g.spacing);
            k = std::clamp(k, double(lo[a]), double(hi[a]));
            const double d = g.origin[a] + double(g.spacing) * k - c;
            d2 += d * d;
        }
        best = std::min(best, d2 - r * r);
    }
    return best;
}

// The boxes of 4³ points holding a point with pi <= pi_cut (a non-zero density), and how many of
// them `reached` lacks.
struct Coverage {
    std::size_t needed = 0, missing = 0, boxes = 0;
};
Coverage coverage(const Atoms& atoms, const GridPlan& plan,
                  const std::vector<std::uint32_t>& reached) {
    const std::uint32_t group[3] = {4, 4, 4};
    std::uint32_t nb[3];
    for (int a = 0; a < 3; ++a) nb[a] = (plan.info.dims[a] + 3) / 4;
    Coverage c;
    c.boxes = std::size_t(nb[0]) * nb[1] * nb[2];
    for (std::uint32_t z = 0; z < nb[2]; ++z)
        for (std::uint32_t y = 0; y < nb[1]; ++y)
            for (std::uint32_t x = 0; x < nb[0]; ++x) {
                if (box_min_power(atoms, plan, group, x, y, z) > plan.density.pi_cut) continue;
                ++c.needed;
                const std::uint32_t id = (z * nb[1] + y) * nb[0] + x;
                c.missing += !std::binary_search(reached.begin(), reached.end(), id);
            }
    return c;
}

// Every box holding a point with pi <= pi_cut (a non-zero density) is listed; boxes far from
// both clusters of two crambins 40 Å apart are not.
TEST(AtomBins, ReachedBoxesCoverEveryNonZeroPoint) {
    Atoms atoms = fdmsurf::read_structure(std::string(FDMSURF_TEST_DATA_DIR) + "/1crn.pdb").atoms;
    const std::size_t n = atoms.size();
    for (std::size_t i = 0; i < n; ++i) {
        atoms.xyz.push_back(atoms.xyz[3 * i] + 40.0f);
        atoms.xyz.push_back(atoms.xyz[3 * i + 1]);
        atoms.xyz.push_back(atoms.xyz[3 * i + 2]);
        atoms.radius.push_back(atoms.radius[i]);
    }
    for (SurfaceKind kind : {SurfaceKind::Ses, SurfaceKind::Sas}) {
        const GridPlan plan = plan_grid(atoms, SurfaceOptions{.surface = kind, .spacing = 1.0f});
        const std::uint32_t group[3] = {4, 4, 4};
        const std::vector<std::uint32_t> reached =
            reached_boxes(bin_atoms(atoms, plan), plan, group);
        EXPECT_TRUE(std::is_sorted(reached.begin(), reached.end()));
        const Coverage c = coverage(atoms, plan, reached);
        const std::size_t needed = c.needed;
        EXPECT_EQ(c.missing, 0u) << to_string(kind);
        EXPECT_GT(needed, 0u);
        // Conservative, but not by much: the extra boxes are the ones the continuous box
        // distance lets in (a ring one box wide at most).
        EXPECT_LE(double(reached.size()), 1.5 * double(needed)) << to_string(kind);
        EXPECT_LT(double(reached.size()), 0.6 * double(c.boxes)) << to_string(kind);
    }
}

// A grid far coarser than the atoms (crambin on 64³ points 20 Å apart, 1,260 Å wide): bins of
// the atoms' size would number 500³ (gigabytes); they are never finer than the grid, and the
// boxes reached are still every box with a non-zero density.
TEST(AtomBins, NeverFinerThanTheGrid) {
    const Atoms atoms =
        fdmsurf::read_structure(std::string(FDMSURF_TEST_DATA_DIR) + "/1crn.pdb").atoms;
    const GridPlan plan = plan_grid(atoms, SurfaceOptions{.spacing = 20.0f, .min_grid = {64, 64, 64}});
    const auto bins = bin_atoms(atoms, plan);
    EXPECT_GE(bins.size, plan.info.spacing);
    EXPECT_LE(bins.bin_count(), std::size_t(plan.info.dims[0]) * plan.info.dims[1] * plan.info.dims[2]);
    const std::uint32_t group[3] = {4, 4, 4};
    const std::vector<std::uint32_t> reached = reached_boxes(bins, plan, group);
    const Coverage c = coverage(atoms, plan, reached);
    EXPECT_GT(c.needed, 0u);
    EXPECT_EQ(c.missing, 0u);
}

}  // namespace
