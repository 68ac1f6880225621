// Counting sort of atoms into bins, and a breadth-first Chebyshev distance to non-empty bins.
#include "grid/atom_bins.hpp"

#include <atomic>

#include "base/parallel.hpp"

#include <algorithm>
#include <cmath>
#include <deque>

namespace fdmsurf::detail {

AtomBins bin_atoms(const Atoms& atoms, const GridPlan& plan, bool first_shell) {
    AtomBins bins;
    float r_max = 0.0f;
    for (float r : atoms.radius) r_max = std::max(r_max, r + plan.density.radius_add);
    bins.r2_max = r_max * r_max;
    // With bins of r_max + 0.5 Å, a point inside the van der Waals surface (pi <= 0) is certified
    // after the 27 nearest bins: farther atoms have pi >= (s-1)^2 b^2 - r_max^2 > 0.
    // Never finer than the grid (a coarse grid over a wide box: 64³ points 20 Å apart would
    // otherwise be 500³ bins, gigabytes): larger bins keep the certificate.
    const GridInfo& g = plan.info;
    bins.size = std::max(r_max + 0.5f, g.spacing);
    for (int a = 0; a < 3; ++a) {
        bins.origin[a] = g.origin[a];
        float extent = (g.dims[a] - 1) * g.spacing;
        bins.dims[a] = std::max<std::uint32_t>(
            1, static_cast<std::uint32_t>(std::floor(extent / bins.size)) + 1);
    }
    float reach = std::sqrt(plan.density.pi_cut + bins.r2_max);
    bins.max_shell = static_cast<std::uint32_t>(std::ceil(reach / bins.size)) + 1;

    const std::size_t n = atoms.size();
    std::vector<std::uint32_t> bin_of(n);
    bins.start.assign(bins.bin_count() + 1, 0);
    for (std::size_t i = 0; i < n; ++i) {
        std::uint32_t c[3];
        for (int a = 0; a < 3; ++a) {
            float f = std::floor((atoms.xyz[3 * i + a] - bins.origin[a]) / bins.size);
            c[a] = static_cast<std::uint32_t>(std::clamp(f, 0.0f, float(bins.dims[a] - 1)));
        }
        bin_of[i] = (c[2] * bins.dims[1] + c[1]) * bins.dims[0] + c[0];
        ++bins.start[bin_of[i] + 1];
    }
    for (std::size_t b = 0; b < bins.bin_count(); ++b) bins.start[b + 1] += bins.start[b];
    bins.atoms.resize(4 * n);
    std::vector<std::uint32_t> fill(bins.start.begin(), bins.start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) {
        std::uint32_t slot = fill[bin_of[i]]++;
        float r = atoms.radius[i] + plan.density.radius_add;
        bins.atoms[4 * slot + 0] = atoms.xyz[3 * i + 0];
        bins.atoms[4 * slot + 1] = atoms.xyz[3 * i + 1];
        bins.atoms[4 * slot + 2] = atoms.xyz[3 * i + 2];
        bins.atoms[4 * slot + 3] = r * r;
    }

    if (!first_shell) return bins;
    // Multi-source BFS over 26-neighbours gives the Chebyshev distance in bins.
    const std::uint32_t cap = bins.max_shell + 1;
    bins.first_shell.assign(bins.bin_count(), cap);
    std::deque<std::uint32_t> queue;
    for (std::uint32_t b = 0; b < bins.bin_count(); ++b)
        if (bins.start[b + 1] > bins.start[b]) {
            bins.first_shell[b] = 0;
            queue.push_back(b);
        }
    const int nx = int(bins.dims[0]), ny = int(bins.dims[1]), nz = int(bins.dims[2]);
    while (!queue.empty()) {
        std::uint32_t b = queue.front();
        queue.pop_front();
        std::uint32_t d = bins.first_shell[b];
        if (d + 1 >= cap) continue;
        int x = int(b % bins.dims[0]), y = int((b / bins.dims[0]) % bins.dims[1]),
            z = int(b / (bins.dims[0] * bins.dims[1]));
        for (int dz = -1; dz <= 1; ++dz)
            for (int dy = -1; dy <= 1; ++dy)
                for (int dx = -1; dx <= 1; ++dx) {
                    int X = x + dx, Y = y + dy, Z = z + dz;
                    if (X < 0 || Y < 0 || Z < 0 || X >= nx || Y >= ny || Z >= nz) continue;
                    std::uint32_t nb = std::uint32_t((Z * ny + Y) * nx + X);
                    if (bins.first_shell[nb] > d + 1) {
                        bins.first_shell[nb] = d + 1;
                        queue.push_back(nb);
                    }
                }
    }
    return bins;
}

std::vector<std::uint32_t> reached_boxes(const AtomBins& bins, const GridPlan& plan,
                                         const std::uint32_t group[3]) {
    const GridInfo& g = plan.info;
    std::uint32_t n[3];
    for (int a = 0; a < 3; ++a) n[a] = (g.dims[a] + group[a] - 1) / group[a];
    const std::size_t box_count = std::size_t{n[0]} * n[1] * n[2];
    std::vector<std::uint8_t> reached(box_count, 0);
    const double h = g.spacing;
    // Box k along axis a spans the points [k G, min(k G + G - 1, dims - 1)]: its ends, once.
    std::vector<double> box_lo[3], box_hi[3];
    for (int a = 0; a < 3; ++a) {
        box_lo[a].resize(n[a]);
        box_hi[a].resize(n[a]);
        for (std::uint32_t k = 0; k < n[a]; ++k) {
            box_lo[a][k] = g.origin[a] + h * (double(k) * group[a]);
            box_hi[a][k] = g.origin[a] + h * std::min<double>(double(k) * group[a] + group[a] - 1,
                                                             g.dims[a] - 1);
        }
    }
    // Distance from c to box k along axis a.
    auto gap = [&](int a, std::uint32_t k, double c) {
        return std::max(std::max(box_lo[a][k] - c, c - box_hi[a][k]), 0.0);
    };
    // Boxes along axis a within `s` of c (an over-estimate by a point's width each way).
    auto range = [&](int a, double c, double s, std::uint32_t& first, std::uint32_t& last) {
        double lo = std::floor((c - s - g.origin[a]) / h) - 1.0;
        double hi = std::ceil((c + s - g.origin[a]) / h) + 1.0;
        lo = std::clamp(std::floor(lo / group[a]), 0.0, double(n[a] - 1));
        hi = std::clamp(std::floor(hi / group[a]), 0.0, double(n[a] - 1));
        first = std::uint32_t(lo);
        last = std::uint32_t(hi);
    };
    // Atoms in chunks on all threads; a box reached twice is marked twice with the same value.
    const std::size_t count = bins.atoms.size() / 4;
    constexpr std::size_t kChunk = 1024;
    parallel_chunks((count + kChunk - 1) / kChunk, thread_count(), [&](std::size_t chunk) {
        for (std::size_t i = chunk * kChunk; i < std::min(count, (chunk + 1) * kChunk); ++i) {
            const double c[3] = {bins.atoms[4 * i], bins.atoms[4 * i + 1], bins.atoms[4 * i + 2]};
            // Slack so that float rounding on the GPU never turns a skipped box into a reached one.
            const double reach2 =
                (double(plan.density.pi_cut) + bins.atoms[4 * i + 3]) * (1.0 + 1e-4) + 1e-4;
            const double reach = std::sqrt(reach2);
            std::uint32_t z0, z1, y0, y1, x0, x1;
            range(2, c[2], reach, z0, z1);
            range(1, c[1], reach, y0, y1);
            for (std::uint32_t z = z0; z <= z1; ++z) {
                const double dz = gap(2, z, c[2]);
                const double rz = reach2 - dz * dz;
                if (rz < 0.0) continue;
                for (std::uint32_t y = y0; y <= y1; ++y) {
                    const double dy = gap(1, y, c[1]);
                    const double ry = rz - dy * dy;
                    if (ry < 0.0) continue;
                    const double rx = std::sqrt(ry);
                    range(0, c[0], rx, x0, x1);
                    std::uint8_t* row = &reached[(std::size_t(z) * n[1] + y) * n[0]];
                    for (std::uint32_t x = x0; x <= x1; ++x)
                        if (gap(0, x, c[0]) <= rx)
                            std::atomic_ref<std::uint8_t>(row[x]).store(1, std::memory_order_relaxed);
                }
            }
        }
    });
    std::vector<std::uint32_t> boxes;
    for (std::size_t b = 0; b < reached.size(); ++b)
        if (reached[b]) boxes.push_back(static_cast<std::uint32_t>(b));
    return boxes;
}

}  // namespace fdmsurf::detail
