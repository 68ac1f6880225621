// make_cell_list: a counting sort of points into cells.
#include "base/cell_list.hpp"

namespace fdmsurf::detail {

CellList make_cell_list(const std::vector<float>& xyz, double size) {
    CellList c;
    const std::size_t n = xyz.size() / 3;
    double lo[3] = {0, 0, 0}, hi[3] = {0, 0, 0};
    for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            const double x = xyz[3 * i + a];
            lo[a] = i == 0 ? x : std::min(lo[a], x);
            hi[a] = i == 0 ? x : std::max(hi[a], x);
        }
    double extent = 0.0;
    for (int a = 0; a < 3; ++a) extent = std::max(extent, hi[a] - lo[a]);
    c.size = std::max(size, extent / 255.0);
    for (int a = 0; a < 3; ++a) {
        c.origin[a] = lo[a];
        c.dims[a] = std::int64_t((hi[a] - lo[a]) / c.size) + 1;
    }
    const std::size_t cells = std::size_t(c.dims[0] * c.dims[1] * c.dims[2]);
    std::vector<std::uint32_t> cell_of(n);
    c.start.assign(cells + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        cell_of[i] = std::uint32_t(
            c.index(c.axis(xyz[3 * i], 0), c.axis(xyz[3 * i + 1], 1), c.axis(xyz[3 * i + 2], 2)));
        ++c.start[cell_of[i] + 1];
    }
    for (std::size_t k = 0; k < cells; ++k) c.start[k + 1] += c.start[k];
    std::vector<std::uint32_t> fill(c.start.begin(), c.start.end() - 1);
    c.items.resize(n);
    for (std::size_t i = 0; i < n; ++i) c.items[fill[cell_of[i]]++] = std::uint32_t(i);
    return c;
}

}  // namespace fdmsurf::detail
