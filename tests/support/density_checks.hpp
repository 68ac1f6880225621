// The density tests' comparison of a field with density_cpu's values (tests/grid): the
// tolerance that float arithmetic allows, and the points where rounding puts pi on either side
// of the cut.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <string>

#include "grid/grid_plan.hpp"

namespace fdmsurf::test {

using fdmsurf::detail::GridPlan;

// Tolerance. The GPU works in float: the grid point origin + h * i, the atom centre and r² are
// rounded to float (about 6e-8 relative, so ~2e-6 Å at 30 Å from the origin) and |p - c|² - r²
// is summed in float; with |p - c| up to ~8 Å inside the Gaussian support that is an error of
// up to ~5e-5 Å² in the power distance pi, i.e. a relative error of ~5e-6 in exp(-pi / σ²)
// at σ = 3 Å, plus a few ulps from the float exp. Hence
//     |gpu - cpu| <= 1e-5 * |cpu| + 1e-6 * T.
// Where pi sits at the cut pi_cut (density density_cut * T) the same rounding can put a point on
// either side of the cut: a tie, one side 0 and the other within 1e-4 relative of the cut value.
// Ties are counted separately and must stay rare (at most 1e-4 of the points compared).
inline constexpr double kDensityRelTol = 1e-5;
inline constexpr double kDensityAbsTol = 1e-6;  // times T
inline constexpr double kDensityTieBand = 1e-4;

struct DensityComparison {
    std::size_t points = 0;
    std::size_t bad = 0;   // outside the tolerance (and not a tie)
    std::size_t ties = 0;  // one side cut to 0, the other at the cut value
    double max_abs = 0.0;  // largest |gpu - cpu| over non-tie points
    double max_rel = 0.0;  // largest |gpu - cpu| / max(|cpu|, 1e-3 T) over non-tie points
    std::string first_bad;

    void add(double gpu, double cpu, const GridPlan& plan, std::uint32_t x, std::uint32_t y,
             std::uint32_t z) {
        ++points;
        const double t = plan.density.level_t;
        const double cut_value = t * std::exp(-double(plan.density.pi_cut) /
                                              (double(plan.density.sigma) * plan.density.sigma));
        auto at_cut = [&](double v) { return std::abs(v - cut_value) <= kDensityTieBand * cut_value; };
        if ((gpu == 0.0 && at_cut(cpu)) || (cpu == 0.0 && at_cut(gpu))) {
            ++ties;
            return;
        }
        const double diff = std::abs(gpu - cpu);
        max_abs = std::max(max_abs, diff);
        max_rel = std::max(max_rel, diff / std::max(std::abs(cpu), 1e-3 * t));
        if (!(diff <= kDensityRelTol * std::abs(cpu) + kDensityAbsTol * t)) {
            if (bad++ == 0)
                first_bad = "point (" + std::to_string(x) + ", " + std::to_string(y) + ", " +
                            std::to_string(z) + "): gpu " + std::to_string(gpu) + ", cpu " +
                            std::to_string(cpu);
        }
    }
};

inline void report_density(const DensityComparison& c) {
    ::testing::Test::RecordProperty("points", std::to_string(c.points));
    ::testing::Test::RecordProperty("max_abs_diff", std::to_string(c.max_abs));
    ::testing::Test::RecordProperty("ties", std::to_string(c.ties));
    std::printf(
        "  density: %zu points, max |gpu - cpu| = %.3g, max relative = %.3g, %zu cut ties\n",
        c.points, c.max_abs, c.max_rel, c.ties);
    EXPECT_EQ(c.bad, 0u) << c.bad << " points out of tolerance; first: " << c.first_bad;
    EXPECT_LE(double(c.ties), 1e-4 * double(c.points));
}

}  // namespace fdmsurf::test
