// Points (atom centres) in cubic cells over their bounding box, for neighbour searches on the
// host (per-atom areas, vertex kinds). The GPU passes bin atoms on their own (shader layouts).
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

namespace fdmsurf::detail {

struct CellList {
    double origin[3] = {0, 0, 0};
    double size = 1.0;                  // Å; at least the size asked for
    std::int64_t dims[3] = {1, 1, 1};
    std::vector<std::uint32_t> start;   // per cell, into `items`; one more than the cells
    std::vector<std::uint32_t> items;   // point indices, cell by cell, in index order

    // The cell coordinate of `x` along axis `a`, clamped into the grid.
    std::int64_t axis(double x, int a) const {
        return std::clamp<std::int64_t>(std::int64_t(std::floor((x - origin[a]) / size)), 0,
                                        dims[a] - 1);
    }
    std::int64_t index(std::int64_t i, std::int64_t j, std::int64_t k) const {
        return (k * dims[1] + j) * dims[0] + i;
    }
    // Calls f(point index) for every point in the 27 cells around the cell of p: every point
    // within `size` of p, and some farther ones.
    template <class F>
    void for_each_near(const double p[3], F&& f) const {
        const std::int64_t c[3] = {axis(p[0], 0), axis(p[1], 1), axis(p[2], 2)};
        for (std::int64_t z = std::max<std::int64_t>(c[2] - 1, 0);
             z <= std::min(c[2] + 1, dims[2] - 1); ++z)
            for (std::int64_t y = std::max<std::int64_t>(c[1] - 1, 0);
                 y <= std::min(c[1] + 1, dims[1] - 1); ++y)
                for (std::int64_t x = std::max<std::int64_t>(c[0] - 1, 0);
                     x <= std::min(c[0] + 1, dims[0] - 1); ++x) {
                    const std::int64_t cell = index(x, y, z);
                    for (std::uint32_t s = start[cell]; s < start[cell + 1]; ++s) f(items[s]);
                }
    }
    // The same points as for_each_near, in the same order, as runs of `items`: f(first, end)
    // for each of the up to 9 rows of three cells along x (consecutive cells are consecutive in
    // `items`).
    template <class F>
    void for_each_run_near(const double p[3], F&& f) const {
        const std::int64_t c[3] = {axis(p[0], 0), axis(p[1], 1), axis(p[2], 2)};
        const std::int64_t x0 = std::max<std::int64_t>(c[0] - 1, 0),
                           x1 = std::min(c[0] + 1, dims[0] - 1);
        for (std::int64_t z = std::max<std::int64_t>(c[2] - 1, 0);
             z <= std::min(c[2] + 1, dims[2] - 1); ++z)
            for (std::int64_t y = std::max<std::int64_t>(c[1] - 1, 0);
                 y <= std::min(c[1] + 1, dims[1] - 1); ++y)
                f(start[std::size_t(index(x0, y, z))], start[std::size_t(index(x1, y, z)) + 1]);
    }
};

// Bins the points xyz (3 floats each) in cells of side `size` (> 0, Å); far-apart points widen
// the cells so that there are at most about 256³ of them.
CellList make_cell_list(const std::vector<float>& xyz, double size);

}  // namespace fdmsurf::detail
