// Removing cavities: closed pieces with negative signed volume (inward-facing shells inside
// another piece): all of them, those below a volume, or those no solvent probe fits in.
#include "mesh/cavities.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <functional>
#include <limits>
#include <mutex>
#include <optional>
#include <vector>

#include "base/cell_list.hpp"
#include "base/parallel.hpp"
#include "base/trace.hpp"
#include "fdmsurf/mesh.hpp"
#include "mesh/mesh_attributes.hpp"
#include "mesh/mesh_pieces.hpp"
#include "mesh/mesh_stats_detail.hpp"
#include "mesh/mesh_validate.hpp"

namespace fdmsurf {

namespace detail {

namespace {

using P3 = std::array<double, 3>;

// The ray of the inside test: a fixed, generic direction (it avoids the grid's axes and planes).
constexpr P3 kRay{0.5773502691896258, 0.5773502691896257 + 1.1e-3, 0.5773502691896259 - 2.3e-3};

// Does the ray from p along kRay cross triangle t (Möller-Trumbore, in front of p)?
bool ray_crosses(const P3& p, const std::array<P3, 3>& t) {
    constexpr const P3& d = kRay;
    const P3 e1{t[1][0] - t[0][0], t[1][1] - t[0][1], t[1][2] - t[0][2]};
    const P3 e2{t[2][0] - t[0][0], t[2][1] - t[0][1], t[2][2] - t[0][2]};
    const P3 q{d[1] * e2[2] - d[2] * e2[1], d[2] * e2[0] - d[0] * e2[2],
               d[0] * e2[1] - d[1] * e2[0]};
    const double det = e1[0] * q[0] + e1[1] * q[1] + e1[2] * q[2];
    if (std::abs(det) < 1e-14) return false;
    const P3 s{p[0] - t[0][0], p[1] - t[0][1], p[2] - t[0][2]};
    const double u = (s[0] * q[0] + s[1] * q[1] + s[2] * q[2]) / det;
    if (u < 0.0 || u > 1.0) return false;
    const P3 r{s[1] * e1[2] - s[2] * e1[1], s[2] * e1[0] - s[0] * e1[2],
               s[0] * e1[1] - s[1] * e1[0]};
    const double v = (d[0] * r[0] + d[1] * r[1] + d[2] * r[2]) / det;
    if (v < 0.0 || u + v > 1.0) return false;
    return (e2[0] * r[0] + e2[1] * r[1] + e2[2] * r[2]) / det > 0.0;
}

P3 cross(const P3& a, const P3& b) {
    return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

}  // namespace

bool inside_piece(const P3& p, const std::vector<std::array<P3, 3>>& tris) {
    int crossings = 0;
    for (const auto& t : tris) crossings += ray_crosses(p, t) ? 1 : 0;
    return crossings % 2 == 1;
}

RayBins::RayBins(const std::vector<std::array<P3, 3>>& tris) : tris_(&tris) {
    // Two unit axes across the ray (kRay x z, and kRay x that): the plane of the bins.
    axis_[0] = cross(kRay, {0.0, 0.0, 1.0});
    axis_[1] = cross(kRay, axis_[0]);
    for (auto& axis : axis_) {
        const double n = std::sqrt(axis[0] * axis[0] + axis[1] * axis[1] + axis[2] * axis[2]);
        for (double& c : axis) c /= n;
    }
    const std::size_t nt = tris.size();
    if (nt == 0) return;
    // Each triangle's projected box; the bins are as wide as the widest box, and a triangle goes
    // to the bin of its box's low corner, so the triangles whose box holds a point are in that
    // point's bin or the three below it. The pad (far above the rounding of the crossing test,
    // ~1e-13 Å at 1000 Å) keeps every triangle whose test could succeed among them.
    double scale = 0.0;
    for (const auto& t : tris)
        for (const auto& v : t)
            for (double c : v) scale = std::max(scale, std::abs(c));
    pad_ = 1e-6 * (1.0 + scale);
    std::vector<std::array<double, 2>> low(nt);
    double lo[2] = {1e300, 1e300}, hi[2] = {-1e300, -1e300}, width = 0.0;
    for (std::size_t i = 0; i < nt; ++i) {
        for (int a = 0; a < 2; ++a) {
            double l = 1e300, h = -1e300;
            for (const auto& v : tris[i]) {
                const double x = project(v, a);
                l = std::min(l, x), h = std::max(h, x);
            }
            low[i][a] = l - pad_;
            width = std::max(width, h - l + 2.0 * pad_);
            lo[a] = std::min(lo[a], l - pad_), hi[a] = std::max(hi[a], h + pad_);
        }
    }
    // At most about one bin per triangle.
    const double area = (hi[0] - lo[0]) * (hi[1] - lo[1]);
    cell_ = std::max({width, std::sqrt(area / double(nt)), 1e-9});
    for (int a = 0; a < 2; ++a) {
        origin_[a] = lo[a];
        dims_[a] = std::int64_t((hi[a] - lo[a]) / cell_) + 1;
    }
    std::vector<std::uint32_t> bin_of(nt);
    start_.assign(std::size_t(dims_[0] * dims_[1]) + 1, 0);
    for (std::size_t i = 0; i < nt; ++i) {
        bin_of[i] = std::uint32_t(bin(low[i][0], 0) + dims_[0] * bin(low[i][1], 1));
        ++start_[bin_of[i] + 1];
    }
    for (std::size_t k = 0; k + 1 < start_.size(); ++k) start_[k + 1] += start_[k];
    std::vector<std::uint32_t> fill(start_.begin(), start_.end() - 1);
    items_.resize(nt);
    for (std::size_t i = 0; i < nt; ++i) items_[fill[bin_of[i]]++] = std::uint32_t(i);
}

double RayBins::project(const P3& p, int a) const {
    return p[0] * axis_[a][0] + p[1] * axis_[a][1] + p[2] * axis_[a][2];
}

std::int64_t RayBins::bin(double x, int a) const {
    return std::clamp<std::int64_t>(std::int64_t(std::floor((x - origin_[a]) / cell_)), 0,
                                    dims_[a] - 1);
}

bool RayBins::inside(const P3& p) const {
    if (items_.empty()) return false;
    const double x = project(p, 0), y = project(p, 1);
    // Outside the projected boxes of all triangles (with their pads): no crossing.
    if (x < origin_[0] || y < origin_[1] || x > origin_[0] + double(dims_[0]) * cell_ + cell_ ||
        y > origin_[1] + double(dims_[1]) * cell_ + cell_)
        return false;
    const std::int64_t bx = bin(x, 0), by = bin(y, 1);
    int crossings = 0;
    for (std::int64_t j = std::max<std::int64_t>(by - 1, 0); j <= by; ++j)
        for (std::int64_t i = std::max<std::int64_t>(bx - 1, 0); i <= bx; ++i) {
            const std::size_t b = std::size_t(i + dims_[0] * j);
            for (std::uint32_t k = start_[b]; k < start_[b + 1]; ++k)
                crossings += ray_crosses(p, (*tris_)[items_[k]]) ? 1 : 0;
        }
    return crossings % 2 == 1;
}

namespace {

// The atoms near a void, with their radii, and, for the indexed search, a cell list over them
// when they are many and the search has a cap (only atoms within cap + r of a point can bring
// its clearance under the cap, so the 27 cells around it hold all that matter) and a cheap
// test that skips an atom which cannot lower the running minimum: min over those equals min
// over all, to the bit.
struct NearAtoms {
    std::vector<std::array<double, 4>> atoms;
    std::optional<CellList> cells;
    bool skip_far = false;

    void index(double cap, float r_max) {
        skip_far = true;
        if (!std::isfinite(cap) || atoms.size() < 64) return;
        std::vector<float> xyz;
        xyz.reserve(3 * atoms.size());
        for (const auto& a : atoms) xyz.insert(xyz.end(), {float(a[0]), float(a[1]), float(a[2])});
        cells = make_cell_list(xyz, cap + double(r_max) + 1e-3);
    }

    // min(cap, min_i |p - c_i| - r_i)
    double clearance(const P3& p, double cap) const {
        double best = cap;
        const auto visit = [&](std::size_t i) {
            const auto& a = atoms[i];
            const double dx = p[0] - a[0], dy = p[1] - a[1], dz = p[2] - a[2];
            // Farther than best + r by 1e-6 Å (far above the rounding of hypot and of the
            // difference): hypot - r would not be below best.
            const double reach = best + a[3] + 1e-6;
            if (skip_far && reach > 1e-6 && dx * dx + dy * dy + dz * dz > reach * reach) return;
            best = std::min(best, std::hypot(dx, dy, dz) - a[3]);
        };
        if (cells) {
            cells->for_each_near(p.data(), visit);
        } else {
            for (std::size_t i = 0; i < atoms.size(); ++i) visit(i);
        }
        return best;
    }
};

}  // namespace

AtomCells::AtomCells(const Atoms& atoms) {
    for (float r : atoms.radius) r_max = std::max(r_max, r);
    // Cells of about 8 Å: a void's box with its margin (~3.4 Å with the probe) overlaps a few.
    cells = make_cell_list(atoms.xyz, 8.0);
}

namespace {

// The samples of one axis of the search grid, as the plain loop makes them: lo + step / 2, then
// step added, while below hi.
std::vector<double> axis_samples(double lo, double hi, double step) {
    std::vector<double> s;
    for (double x = lo + 0.5 * step; x < hi; x += step) s.push_back(x);
    return s;
}

// The grid's samples in tiles of kTile³ samples, and the near atoms that can give the
// clearance somewhere in a box (a block of tiles: their samples and half a step around them):
// an atom whose distance to the box, less its radius, exceeds the least over the atoms of their
// farthest distance to the box less radius (or the cap) is never the nearest there. The min
// over the box's atoms is then the min over all, to the bit (a margin of 1e-6 Å, far above
// rounding, keeps the doubtful ones), and that least farthest distance bounds every clearance
// in the box. Blocks are halved, from the whole grid down to tiles, each sorting out its
// parent's atoms, and only where the search needs them.
class SampleTiles {
public:
    static constexpr std::size_t kTile = 2;

    SampleTiles(const std::vector<std::array<double, 4>>& atoms,
                const std::array<std::vector<double>, 3>& axes, double step, double cap)
        : atoms_(atoms), axes_(axes), step_(step), cap_(cap) {
        for (int a = 0; a < 3; ++a) dims_[a] = (axes[a].size() + kTile - 1) / kTile;
        tiles_.resize(dims_[0] * dims_[1] * dims_[2]);
        all_.resize(atoms.size());
        for (std::size_t n = 0; n < atoms.size(); ++n) all_[n] = std::uint32_t(n);
    }

    // The grid's first `want` samples inside (inside(p)) by clearance, best first, those of equal
    // clearance in the plain loop's order: what that loop keeps, found best first. Blocks are
    // taken in the order of their bounds (halved, or their samples measured), and a sample once
    // no block left can hold one as good: only the samples that can be among the best are
    // measured, and only those taken are tested for inside. Returns true, at once, when a sample
    // inside reaches the cap.
    template <class Inside>
    bool best_inside(const Inside& inside, std::size_t want,
                     std::vector<std::pair<double, P3>>& best) {
        const std::size_t nx = axes_[0].size(), ny = axes_[1].size(), nz = axes_[2].size();
        // Measured samples, a heap with the best (largest clearance, then first in the plain
        // loop's order) on top; blocks, a heap with the largest bound on top.
        struct Sample {
            double c;
            std::size_t at;  // (k ny + j) nx + i
        };
        const auto worse = [](const Sample& a, const Sample& b) {
            return a.c < b.c || (a.c == b.c && a.at > b.at);
        };
        const auto lower = [](const Box& a, const Box& b) { return a.upper < b.upper; };
        std::vector<Sample> samples;
        std::vector<Box> boxes;
        boxes.push_back(box({0, 0, 0}, {dims_[0], dims_[1], dims_[2]}, all_.data(), all_.size()));
        while (best.size() < want) {
            // A sample is taken when it beats every bound of the blocks left (by the margin).
            if (!samples.empty() &&
                (boxes.empty() || samples.front().c > boxes.front().upper + 1e-6)) {
                std::pop_heap(samples.begin(), samples.end(), worse);
                const Sample s = samples.back();
                samples.pop_back();
                const P3 p = point(s.at);
                if (!inside(p)) continue;
                if (s.c >= cap_) return true;
                best.push_back({s.c, p});
                continue;
            }
            if (boxes.empty()) break;
            std::pop_heap(boxes.begin(), boxes.end(), lower);
            const Box b = boxes.back();
            boxes.pop_back();
            if (b.to[0] - b.from[0] == 1 && b.to[1] - b.from[1] == 1 && b.to[2] - b.from[2] == 1) {
                // A tile: kept for the pattern search, its samples measured.
                Tile& tl = tiles_[tile_index(b.from[0], b.from[1], b.from[2])];
                tl.filled = true;
                tl.box = b;
                for (std::size_t k = b.from[2] * kTile; k < std::min(nz, b.to[2] * kTile); ++k)
                    for (std::size_t j = b.from[1] * kTile; j < std::min(ny, b.to[1] * kTile); ++j)
                        for (std::size_t i = b.from[0] * kTile; i < std::min(nx, b.to[0] * kTile);
                             ++i) {
                            const std::size_t at = (k * ny + j) * nx + i;
                            samples.push_back({in_box(point(at), b), at});
                            std::push_heap(samples.begin(), samples.end(), worse);
                        }
                continue;
            }
            // Halved along every axis longer than a tile.
            std::size_t mid[3];
            for (int a = 0; a < 3; ++a) mid[a] = (b.from[a] + b.to[a] + 1) / 2;
            for (int z = 0; z < 2; ++z)
                for (int y = 0; y < 2; ++y)
                    for (int x = 0; x < 2; ++x) {
                        const int half[3] = {x, y, z};
                        std::array<std::size_t, 3> from, to;
                        bool empty = false;
                        for (int a = 0; a < 3; ++a) {
                            from[a] = half[a] ? mid[a] : b.from[a];
                            to[a] = half[a] ? b.to[a] : mid[a];
                            empty = empty || from[a] >= to[a];
                        }
                        if (empty) continue;
                        boxes.push_back(box(from, to, pool_.data() + b.first, b.count));
                        std::push_heap(boxes.begin(), boxes.end(), lower);
                    }
        }
        return false;
    }

    // Sorts out the near atoms that can give the clearance within h of p (the pattern search's
    // next points): of p's tile when the ball lies in it, else of all.
    void around(const P3& p, double h) {
        const double reach = h * (1.0 + 1e-9) + 1e-9;
        const std::uint32_t* from = all_.data();
        std::size_t count = all_.size();
        std::size_t t[3];
        bool in_grid = true;
        for (int a = 0; a < 3; ++a) {
            const double f = std::floor((p[a] - (axes_[a][0] - 0.5 * step_)) / (kTile * step_));
            in_grid = in_grid && f >= 0.0 && f < double(dims_[a]);
            t[a] = in_grid ? std::size_t(f) : 0;
        }
        if (in_grid) {
            Tile& tl = tiles_[tile_index(t[0], t[1], t[2])];
            if (!tl.filled) {
                tl.filled = true;
                tl.box = box({t[0], t[1], t[2]}, {t[0] + 1, t[1] + 1, t[2] + 1}, all_.data(),
                             all_.size());
            }
            bool in_tile = true;
            for (int a = 0; a < 3; ++a)
                in_tile = in_tile && p[a] - reach >= tl.box.lo[a] && p[a] + reach <= tl.box.hi[a];
            if (in_tile) from = pool_.data() + tl.box.first, count = tl.box.count;
        }
        // Each atom's distance from p less radius, within reach of it either way.
        ball_.clear();
        dist_.resize(count);
        double upper = cap_;
        for (std::size_t n = 0; n < count; ++n) {
            const auto& c = atoms_[from[n]];
            const double dx = p[0] - c[0], dy = p[1] - c[1], dz = p[2] - c[2];
            dist_[n] = std::sqrt(dx * dx + dy * dy + dz * dz) - c[3];
            upper = std::min(upper, dist_[n] + reach);
        }
        for (std::size_t n = 0; n < count; ++n)
            if (dist_[n] - reach <= upper + 1e-6) ball_.push_back(from[n]);
    }

    // min(cap, min over the atoms of |q - c| - r) for q within h of the last around(p, h).
    double near(const P3& q) const { return over(q, ball_.data(), ball_.size()); }

private:
    struct Box {
        std::array<std::size_t, 3> from, to;  // tiles
        P3 lo, hi;
        double upper;
        std::uint32_t first, count;  // its atoms, in pool_
    };
    struct Tile {
        bool filled = false;
        Box box;
    };

    std::size_t tile_index(std::size_t i, std::size_t j, std::size_t k) const {
        return (k * dims_[1] + j) * dims_[0] + i;
    }

    P3 point(std::size_t at) const {
        const std::size_t nx = axes_[0].size(), ny = axes_[1].size();
        return {axes_[0][at % nx], axes_[1][at / nx % ny], axes_[2][at / (nx * ny)]};
    }

    // Exactly NearAtoms::clearance's min, over the atoms listed.
    double over(const P3& p, const std::uint32_t* list, std::size_t count) const {
        double best = cap_;
        for (std::size_t s = 0; s < count; ++s) {
            const auto& a = atoms_[list[s]];
            const double dx = p[0] - a[0], dy = p[1] - a[1], dz = p[2] - a[2];
            const double reach = best + a[3] + 1e-6;
            if (reach > 1e-6 && dx * dx + dy * dy + dz * dz > reach * reach) continue;
            best = std::min(best, std::hypot(dx, dy, dz) - a[3]);
        }
        return best;
    }
    double in_box(const P3& p, const Box& b) const { return over(p, pool_.data() + b.first, b.count); }

    // The block of tiles [from, to) with the atoms of `parent` that can give its clearance.
    Box box(const std::array<std::size_t, 3>& from, const std::array<std::size_t, 3>& to,
            const std::uint32_t* parent, std::size_t count) {
        Box b{from, to, {}, {}, cap_, 0, 0};
        for (int a = 0; a < 3; ++a) {
            const std::vector<double>& s = axes_[a];
            b.lo[a] = s[from[a] * kTile] - 0.5 * step_;
            b.hi[a] = s[std::min(s.size(), to[a] * kTile) - 1] + 0.5 * step_;
        }
        // Each atom's nearest and farthest distance to the box, squared: the bound is the least
        // farthest distance less radius (a root taken only where it may be less), and an atom
        // is kept when its nearest distance less radius is within the bound and margin.
        near2_.resize(count);
        for (std::size_t n = 0; n < count; ++n) {
            const auto& c = atoms_[parent[n]];
            double near2 = 0.0, far2 = 0.0;
            for (int a = 0; a < 3; ++a) {
                const double out = std::max({b.lo[a] - c[a], c[a] - b.hi[a], 0.0});
                const double across = std::max(c[a] - b.lo[a], b.hi[a] - c[a]);
                near2 += out * out;
                far2 += across * across;
            }
            near2_[n] = near2;
            const double reach = b.upper + c[3];
            if (reach > 0.0 && far2 < reach * reach)
                b.upper = std::min(b.upper, std::sqrt(far2) - c[3]);
        }
        // (The parent's list may move as the pool grows: its entries are read first.)
        kept_.clear();
        for (std::size_t n = 0; n < count; ++n) {
            const double reach = b.upper + atoms_[parent[n]][3] + 1e-6;
            if (reach >= 0.0 && near2_[n] <= reach * reach) kept_.push_back(parent[n]);
        }
        b.first = std::uint32_t(pool_.size());
        b.count = std::uint32_t(kept_.size());
        pool_.insert(pool_.end(), kept_.begin(), kept_.end());
        return b;
    }

    const std::vector<std::array<double, 4>>& atoms_;
    const std::array<std::vector<double>, 3>& axes_;
    double step_, cap_;
    std::size_t dims_[3];
    std::vector<Tile> tiles_;
    std::vector<std::uint32_t> all_, pool_, kept_, ball_;
    std::vector<double> near2_, dist_;
};

}  // namespace

double cavity_clearance(const std::vector<std::array<P3, 3>>& tris, const Atoms& atoms, double step,
                        double cap, const AtomCells* index) {
    P3 lo{1e300, 1e300, 1e300}, hi{-1e300, -1e300, -1e300};
    for (const auto& t : tris)
        for (const auto& v : t)
            for (int a = 0; a < 3; ++a)
                lo[a] = std::min(lo[a], v[a]), hi[a] = std::max(hi[a], v[a]);
    // At most about 20,000 samples, whatever the void's size.
    const double box = (hi[0] - lo[0]) * (hi[1] - lo[1]) * (hi[2] - lo[2]);
    step = std::max(step, std::cbrt(box / 20000.0));
    // The atoms that can be nearest to a point of the box: within the largest radius plus the
    // box's diagonal of it, or, with a cap, within cap + the largest radius (an atom farther from
    // every point of the box cannot bring the clearance under the cap).
    float r_max = 0.0f;
    if (index) {
        r_max = index->r_max;
    } else {
        for (float r : atoms.radius) r_max = std::max(r_max, r);
    }
    const double diagonal = std::hypot(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]);
    const double margin = std::isfinite(cap) ? cap + r_max + 1e-3 : diagonal + 2.0 * r_max;
    NearAtoms near_atoms;
    std::vector<std::array<double, 4>>& near = near_atoms.atoms;
    auto consider = [&](std::size_t i) {
        const P3 ci{atoms.xyz[3 * i], atoms.xyz[3 * i + 1], atoms.xyz[3 * i + 2]};
        bool close = true;
        for (int a = 0; a < 3; ++a)
            close = close && ci[a] > lo[a] - margin && ci[a] < hi[a] + margin;
        if (close) near.push_back({ci[0], ci[1], ci[2], double(atoms.radius[i])});
    };
    if (index) {
        // Only the atoms of the cells the box with its margin overlaps (the min below does not
        // depend on their order).
        const CellList& cells = index->cells;
        std::int64_t from[3], to[3];
        for (int a = 0; a < 3; ++a)
            from[a] = cells.axis(lo[a] - margin, a), to[a] = cells.axis(hi[a] + margin, a);
        for (std::int64_t z = from[2]; z <= to[2]; ++z)
            for (std::int64_t y = from[1]; y <= to[1]; ++y) {
                const std::uint32_t first = cells.start[std::size_t(cells.index(from[0], y, z))];
                const std::uint32_t end = cells.start[std::size_t(cells.index(to[0], y, z)) + 1];
                for (std::uint32_t s = first; s < end; ++s) consider(cells.items[s]);
            }
    } else {
        for (std::size_t i = 0; i < atoms.size(); ++i) consider(i);
    }
    // With the index, the triangles binned across the ray when they are many (a ray test
    // against each triangle is the dear part of a large void's search), and the near atoms
    // sorted into the grid's tiles; without, the plain search, the reference of the tests.
    std::optional<RayBins> bins;
    if (index) {
        near_atoms.index(cap, r_max);
        if (tris.size() > 256) bins.emplace(tris);
    }
    const std::array<std::vector<double>, 3> axes{axis_samples(lo[0], hi[0], step),
                                                  axis_samples(lo[1], hi[1], step),
                                                  axis_samples(lo[2], hi[2], step)};
    std::optional<SampleTiles> tiles;
    if (index && !axes[0].empty() && !axes[1].empty() && !axes[2].empty())
        tiles.emplace(near, axes, step, cap);
    const auto all = [&](const P3& p) { return near_atoms.clearance(p, cap); };
    auto inside = [&](const P3& p) { return bins ? bins->inside(p) : inside_piece(p, tris); };
    // Samples on a grid inside the piece (ending at the first that reaches the cap), keeping
    // the best four inside; the inside test (a ray against every triangle) is the dear part, so
    // it is asked only of samples that would enter the four, and with the tiles a sample whose
    // tile's bound cannot enter them is not even measured. Then a pattern search from those.
    constexpr std::size_t kSeeds = 4;
    std::vector<std::pair<double, P3>> samples;  // best first
    if (tiles) {
        if (tiles->best_inside(inside, kSeeds, samples)) return cap;
    } else {
        for (double z = lo[2] + 0.5 * step; z < hi[2]; z += step)
            for (double y = lo[1] + 0.5 * step; y < hi[1]; y += step)
                for (double x = lo[0] + 0.5 * step; x < hi[0]; x += step) {
                    const P3 p{x, y, z};
                    const double c = all(p);
                    if (samples.size() == kSeeds && c <= samples.back().first) continue;
                    if (!inside(p)) continue;
                    if (c >= cap) return cap;
                    auto at = std::find_if(samples.begin(), samples.end(),
                                           [&](const auto& e) { return c > e.first; });
                    samples.insert(at, {c, p});
                    if (samples.size() > kSeeds) samples.pop_back();
                }
    }
    if (samples.empty()) return -std::numeric_limits<double>::infinity();
    const std::size_t keep = samples.size();
    double best = samples.front().first;
    for (std::size_t k = 0; k < keep && best < cap; ++k) {
        auto [value, p] = samples[k];
        // All 26 directions of a cube's neighbours: at a point where several atoms are equally
        // near (a kink of the min), only a diagonal move raises all their distances at once.
        // With the tiles, the atoms that can be nearest within h of p are sorted out again
        // whenever p moves or h halves.
        for (double h = 0.5 * step; h > 1e-3 && value < cap; h *= 0.5) {
            bool moved = true;
            if (tiles) tiles->around(p, h);
            while (moved && value < cap) {
                moved = false;
                for (int dz = -1; dz <= 1; ++dz)
                    for (int dy = -1; dy <= 1; ++dy)
                        for (int dx = -1; dx <= 1; ++dx) {
                            if (dx == 0 && dy == 0 && dz == 0) continue;
                            const double len = std::sqrt(double(dx * dx + dy * dy + dz * dz));
                            const P3 q{p[0] + h * dx / len, p[1] + h * dy / len,
                                       p[2] + h * dz / len};
                            const double c = tiles ? tiles->near(q) : all(q);
                            if (c > value && inside(q)) {
                                value = c, p = q, moved = true;
                                if (tiles) tiles->around(p, h);
                            }
                        }
            }
        }
        best = std::max(best, value);
    }
    return best;
}

std::size_t remove_pieces_if(Mesh& mesh, const std::function<bool(double)>& candidate,
                             const std::function<bool(const MeshPiece&)>& remove, bool concurrent,
                             MeshAnalysis* analysis) {
    // The indices are checked by the analysis.
    validate_mesh_arrays(mesh, "remove_cavities", true);
    validate_attributes(mesh, "remove_cavities");
    if (mesh.triangle_count() == 0) return 0;
    std::optional<MeshAnalysis> own;
    if (!analysis) analysis = &own.emplace(analyse_mesh(mesh, false, "remove_cavities"));
    const std::size_t count = analysis->pieces.count;
    // The triangles of each candidate piece, for the predicate: read run by run, so that only
    // the candidates' runs are visited.
    std::vector<std::uint32_t> candidate_of(count, UINT32_MAX);
    std::vector<MeshPiece> pieces;
    for (std::size_t q = 0; q < count; ++q) {
        if (!candidate(analysis->stats[q].volume)) continue;
        candidate_of[q] = static_cast<std::uint32_t>(pieces.size());
        pieces.push_back(MeshPiece{analysis->stats[q].volume, {}});
        pieces.back().triangles.reserve(analysis->stats[q].triangles);
    }
    if (pieces.empty()) return 0;
    const float* p = mesh.positions.data();
    std::size_t first = 0;
    for (const TriangleRun& run : analysis->runs) {
        const std::uint32_t c = candidate_of[run.piece];
        for (std::size_t t = first; c != UINT32_MAX && t < first + run.triangles; ++t) {
            std::array<P3, 3> tri;
            for (int k = 0; k < 3; ++k)
                for (int a = 0; a < 3; ++a) tri[k][a] = p[3 * mesh.indices[3 * t + k] + a];
            pieces[c].triangles.push_back(tri);
        }
        first += run.triangles;
    }
    trace("cavities: candidates gathered");
    // The verdicts, in piece order, on all threads when `remove` allows it.
    std::vector<char> verdict(pieces.size(), 0);
    parallel_chunks(pieces.size(), concurrent ? thread_count() : 1,
                    [&](std::size_t i) { verdict[i] = remove(pieces[i]) ? 1 : 0; });
    trace("cavities: verdicts");
    std::vector<char> drop(count, 0);
    std::size_t removed = 0;
    for (std::size_t q = 0; q < count; ++q) {
        if (candidate_of[q] == UINT32_MAX || !verdict[candidate_of[q]]) continue;
        drop[q] = 1;
        ++removed;
    }
    // Every per-vertex array (positions, normals, atoms, colours, scalars) follows the vertices;
    // unreferenced vertices are kept, as before.
    if (removed > 0) keep_pieces(mesh, *analysis, drop, !own);
    return removed;
}

std::size_t remove_cavities_if(Mesh& mesh, const std::function<bool(const MeshPiece&)>& remove,
                               bool concurrent, MeshAnalysis* analysis) {
    return remove_pieces_if(
        mesh, [](double volume) { return volume < 0.0; }, remove, concurrent, analysis);
}

std::size_t remove_cavities_below(Mesh& mesh, double max_volume, MeshAnalysis* analysis) {
    return remove_cavities_if(
        mesh, [&](const MeshPiece& c) { return -c.volume < max_volume; }, false, analysis);
}

std::size_t remove_cavities_without_probe(Mesh& mesh, const Atoms& atoms, double probe,
                                          MeshAnalysis* analysis, double step) {
    // A void that holds a probe ball encloses at least the ball's volume; below half of it
    // (room for the approximate surface's own error) no search is needed.
    const double half_ball = 0.5 * 4.0 / 3.0 * 3.14159265358979 * probe * probe * probe;
    std::optional<AtomCells> index;  // built at the first void that needs a search
    std::once_flag built;
    return remove_cavities_if(
        mesh,
        [&](const MeshPiece& c) {
            if (-c.volume < half_ball) return true;
            std::call_once(built, [&] { index.emplace(atoms); });
            return cavity_clearance(c.triangles, atoms, step, probe, &*index) < probe;
        },
        true, analysis);
}

std::size_t remove_specks(Mesh& mesh, double max_volume, MeshAnalysis* analysis) {
    return remove_pieces_if(
        mesh, [&](double volume) { return std::abs(volume) < max_volume; },
        [](const MeshPiece&) { return true; }, false, analysis);
}

}  // namespace detail

std::size_t remove_cavities(Mesh& mesh, double max_volume) {
    return detail::remove_cavities_below(mesh, max_volume, nullptr);
}

}  // namespace fdmsurf
