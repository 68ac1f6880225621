// Test helper: two exact SES fields in a plan's layout compared point by point, with the
// tolerance the GPU and host tests share (tests/grid/test_ses_distance_{gpu,host}.cpp).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "grid/grid_plan.hpp"

namespace fdmsurf_test {

// The shader works in float. Coordinates are ~30 Å from the origin (float ulp ~2e-6 Å), |p - c|
// and the arc distance (sqrt of sums of squares of terms up to ~6 Å) lose a few ulps each, and
// the float atan and sin of the arc angle are good to ~1e-6 rad over a radius of at most
// ~3.3 Å: |gpu - cpu| <= 5e-5 Å. A burial decided differently in float and double (a
// projection within ~1e-5 Å of another sphere) changes d by less than that too: where a face
// point is barely buried, the nearest arc point is next to it. The host's field (float depths
// and burials, float arcs in its rows, another summation order) stays within it as well.
inline constexpr double kSesFieldTolerance = 5e-5;

struct SesFieldDiff {
    std::size_t points = 0, band = 0, bad = 0;  // band: reference strictly inside the clamp
    double max_diff = 0.0;
};

// `tested` against `reference`, both plan.pitch floats per row: bad counts the points more
// than kSesFieldTolerance apart.
inline SesFieldDiff compare_ses_fields(const std::vector<float>& tested,
                                       const std::vector<float>& reference,
                                       const fdmsurf::detail::GridPlan& plan) {
    SesFieldDiff r;
    const auto& d = plan.info.dims;
    for (std::uint32_t z = 0; z < d[2]; ++z)
        for (std::uint32_t y = 0; y < d[1]; ++y)
            for (std::uint32_t x = 0; x < d[0]; ++x) {
                const std::size_t i = (std::size_t(z) * d[1] + y) * plan.pitch + x;
                const double diff = std::abs(double(tested[i]) - reference[i]);
                ++r.points;
                r.band += reference[i] > plan.ses_d_min && reference[i] < plan.ses_d_max;
                r.max_diff = std::max(r.max_diff, diff);
                r.bad += !(diff <= kSesFieldTolerance);
            }
    return r;
}

}  // namespace fdmsurf_test
