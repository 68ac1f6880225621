// The vertex atoms on the host (vertex_atoms_host.hpp). The vertices go in layers of cells a few
// Å wide, the cells in groups; a group gets one list of candidate atoms (every atom that can be
// the least in power somewhere in its vertices' box) from one scan of the atoms' cells around the
// box, each cell narrows it to its own box, and each candidate is tried against all the cell's
// vertices, eight lanes at a time. Compiled
// with -ffp-contract=off (CMakeLists.txt): the power is the shader's expression, each product
// and sum rounded apart.
#include "properties/vertex_atoms_host.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstring>
#include <limits>
#include <memory>
#include <vector>

#include "base/cpu_features.hpp"
#include "base/fresh_pages.hpp"
#include "base/parallel.hpp"
#include "base/trace.hpp"

namespace fdmsurf::detail {
namespace {

constexpr std::uint32_t kNone = 0xffffffffu;
// The atoms' cells and the vertices' cells (Å); wider where a dense table would be too large.
// (3 Å vertex cells in groups of 2 x 2: on the shell of issue 36 at 1 Å, 12 vertices a cell;
// on 1AON at 0.5 Å, 44. 2 and 2.5 Å cells, or groups of 4 x 4, were no faster on 1AON.)
constexpr float kAtomCell = 3.0f;
constexpr float kVertexCell = 3.0f;
constexpr std::uint32_t kGroupBits = 1;  // groups of 2^kGroupBits x 2^kGroupBits cells
// The next group's first scan reaches this much farther than the last group needed.
constexpr float kGuess = 1.05f;

using V8 = float __attribute__((vector_size(32)));
using U8 = std::uint32_t __attribute__((vector_size(32)));
using I8 = std::int32_t __attribute__((vector_size(32)));  // a comparison's lanes

// Cubic cells of `size` Å from `origin`, numbered x fastest.
struct Grid {
    float origin[3] = {0, 0, 0};
    float size = 1.0f;
    int dims[3] = {1, 1, 1};
    std::size_t count() const { return std::size_t(dims[0]) * dims[1] * dims[2]; }
    // The cell's coordinate along axis a (clamped into the grid), monotone in v.
    int at(float v, int a) const {
        const float f = std::floor((v - origin[a]) / size);
        return int(std::clamp(f, 0.0f, float(dims[a] - 1)));
    }
    std::size_t cell(int x, int y, int z) const {
        return (std::size_t(z) * std::size_t(dims[1]) + std::size_t(y)) * std::size_t(dims[0]) +
               std::size_t(x);
    }
};

// Cells of `size` over [lo, hi], wider (x1.5 at a time) until `fits(dims)`.
template <class Fits>
Grid make_grid(const float lo[3], const float hi[3], float size, Fits fits) {
    Grid g;
    g.size = size;
    for (;;) {
        for (int a = 0; a < 3; ++a)
            g.dims[a] = int(std::min(std::floor((hi[a] - lo[a]) / g.size) + 1.0f, 1e9f));
        if (fits(g.dims)) break;
        g.size *= 1.5f;
    }
    for (int a = 0; a < 3; ++a) g.origin[a] = lo[a];
    return g;
}

bool finite3(const float* p) {
    return std::isfinite(p[0]) && std::isfinite(p[1]) && std::isfinite(p[2]);
}

// The atoms sorted into cells (x, y, z and (r + radius_add)² apart, for the vector loops).
struct AtomTable {
    Grid grid;
    float r2_max = 0.0f;
    std::vector<float> x, y, z, r2;
    std::vector<std::uint32_t> index;  // the atom's place in the input
    std::vector<std::uint32_t> start;  // cell c holds [start[c], start[c + 1])
};

AtomTable sort_atoms(const Atoms& atoms, const float vlo[3], const float vhi[3],
                     float radius_add) {
    AtomTable t;
    const std::size_t n = atoms.size();
    float lo[3], hi[3];
    for (int a = 0; a < 3; ++a) lo[a] = vlo[a], hi[a] = vhi[a];
    for (std::size_t i = 0; i < n; ++i)
        for (int a = 0; a < 3; ++a) {
            lo[a] = std::min(lo[a], atoms.xyz[3 * i + a]);
            hi[a] = std::max(hi[a], atoms.xyz[3 * i + a]);
        }
    // A dense table of at most 2^24 cells (64 MiB of starts) or 4 per atom.
    const std::size_t cap = std::max<std::size_t>(std::size_t(1) << 24, 4 * n);
    t.grid = make_grid(lo, hi, kAtomCell, [&](const int* d) {
        return double(d[0]) * d[1] * d[2] <= double(cap);
    });
    std::vector<std::uint32_t> cell_of(n);
    const unsigned threads = thread_count(0);
    parallel_chunks(threads, threads, [&](std::size_t k) {
        for (std::size_t i = n * k / threads; i < n * (k + 1) / threads; ++i) {
            const float* p = &atoms.xyz[3 * i];
            cell_of[i] = std::uint32_t(t.grid.cell(t.grid.at(p[0], 0), t.grid.at(p[1], 1),
                                                   t.grid.at(p[2], 2)));
        }
    });
    t.start.assign(t.grid.count() + 1, 0);
    for (std::size_t i = 0; i < n; ++i) ++t.start[cell_of[i] + 1];
    for (std::size_t c = 0; c < t.grid.count(); ++c) t.start[c + 1] += t.start[c];
    // The slots' atoms (a scatter of indices only), then their values gathered on all threads.
    t.index.resize(n);
    std::vector<std::uint32_t> fill(t.start.begin(), t.start.end() - 1);
    for (std::size_t i = 0; i < n; ++i) t.index[fill[cell_of[i]]++] = std::uint32_t(i);
    t.x.resize(n), t.y.resize(n), t.z.resize(n), t.r2.resize(n);
    std::vector<float> r2_max(threads, 0.0f);
    parallel_chunks(threads, threads, [&](std::size_t k) {
        for (std::size_t slot = n * k / threads; slot < n * (k + 1) / threads; ++slot) {
            const std::size_t i = t.index[slot];
            const float r = atoms.radius[i] + radius_add;  // the shader's (r + add)²
            t.x[slot] = atoms.xyz[3 * i], t.y[slot] = atoms.xyz[3 * i + 1];
            t.z[slot] = atoms.xyz[3 * i + 2], t.r2[slot] = r * r;
            r2_max[k] = std::max(r2_max[k], r * r);
        }
    });
    t.r2_max = *std::max_element(r2_max.begin(), r2_max.end());
    return t;
}

// The least power over `count` candidates at each of `padded` (a multiple of 8) vertices, the
// lower index on ties: vertex_atoms.comp's expression and rule, eight vertices a vector (two
// SSE vectors on any x86-64; one AVX2 vector where the CPU has it).
FDMSURF_AVX2_CLONES
void try_candidates(const float* vx, const float* vy, const float* vz, std::size_t padded,
                    const float* cx, const float* cy, const float* cz, const float* cr2,
                    const std::uint32_t* cidx, std::size_t count, std::uint32_t* best_atom) {
    for (std::size_t j = 0; j < padded; j += 8) {
        V8 px, py, pz;
        std::memcpy(&px, vx + j, sizeof px);
        std::memcpy(&py, vy + j, sizeof py);
        std::memcpy(&pz, vz + j, sizeof pz);
        V8 best = V8{} + 3.0e38f;
        U8 atom = U8{} + kNone;
        for (std::size_t k = 0; k < count; ++k) {
            const V8 d0 = px - cx[k], d1 = py - cy[k], d2 = pz - cz[k];
            const V8 pw = (d0 * d0 + d1 * d1 + d2 * d2) - cr2[k];
            const U8 idx = U8{} + cidx[k];
            const I8 take = (pw < best) | ((pw == best) & (idx < atom));
            best = take ? pw : best;
            atom = take ? idx : atom;
        }
        std::memcpy(best_atom + j, &atom, sizeof atom);
    }
}

// For the `count` atoms at x, y, z with (r + radius_add)² r2: each one's least power over the
// box [blo, bhi] into near[], and the least over them of their largest power over the box
// (returned). Eight atoms a vector.
FDMSURF_AVX2_CLONES
float box_powers(const float* x, const float* y, const float* z, const float* r2,
                 std::size_t count, const float blo[3], const float bhi[3], float* near) {
    V8 lo[3], hi[3];
    for (int a = 0; a < 3; ++a) lo[a] = V8{} + blo[a], hi[a] = V8{} + bhi[a];
    V8 bound8 = V8{} + std::numeric_limits<float>::infinity();
    const float* coord[3] = {x, y, z};
    std::size_t k = 0;
    for (; k + 8 <= count; k += 8) {
        V8 n2 = V8{}, f2 = V8{};
        for (int a = 0; a < 3; ++a) {
            V8 c;
            std::memcpy(&c, coord[a] + k, sizeof c);
            const V8 below = lo[a] - c, above = c - hi[a];
            V8 n = below > above ? below : above;
            n = n > V8{} ? n : V8{};
            const V8 from_lo = c - lo[a], from_hi = hi[a] - c;
            const V8 f = from_lo > from_hi ? from_lo : from_hi;
            n2 += n * n;
            f2 += f * f;
        }
        V8 w;
        std::memcpy(&w, r2 + k, sizeof w);
        const V8 np = n2 - w, fp = f2 - w;
        bound8 = fp < bound8 ? fp : bound8;
        std::memcpy(near + k, &np, sizeof np);
    }
    float bound = std::numeric_limits<float>::infinity();
    for (int l = 0; l < 8; ++l) bound = std::min(bound, bound8[l]);
    for (; k < count; ++k) {
        float n2 = 0.0f, f2 = 0.0f;
        for (int a = 0; a < 3; ++a) {
            const float c = coord[a][k];
            const float n = std::max({blo[a] - c, c - bhi[a], 0.0f});
            const float f = std::max(c - blo[a], bhi[a] - c);
            n2 += n * n;
            f2 += f * f;
        }
        near[k] = n2 - r2[k];
        bound = std::min(bound, f2 - r2[k]);
    }
    return bound;
}

// Scans the atoms of the cells around a box, keeping the powers a candidate rule needs: each
// scanned atom's least power over the box (its slot and that power) and the least over atoms of
// their largest power over the box, an upper bound on every vertex's least power.
struct Scan {
    std::vector<std::uint32_t> slot;  // [0, count) used; grown, never shrunk
    std::vector<float> near;
    std::size_t count = 0;
    float bound = std::numeric_limits<float>::infinity();
    bool whole = false;  // every cell was scanned
};

void scan_atoms(const AtomTable& t, const float blo[3], const float bhi[3], float reach,
                Scan& s) {
    const Grid& g = t.grid;
    int clo[3], chi[3];
    s.whole = true;
    for (int a = 0; a < 3; ++a) {
        clo[a] = g.at(blo[a] - reach - 0.01f, a);
        chi[a] = g.at(bhi[a] + reach + 0.01f, a);
        s.whole = s.whole && clo[a] == 0 && chi[a] == g.dims[a] - 1;
    }
    s.count = 0;
    float bound = std::numeric_limits<float>::infinity();
    const float reach2 = (reach + 0.02f) * (reach + 0.02f);
    auto gap = [&](int c, int a) {  // box to cell along a, the cell grown by 0.01 Å
        const float cell_lo = g.origin[a] + float(c) * g.size - 0.01f;
        const float cell_hi = cell_lo + g.size + 0.02f;
        return std::max({cell_lo - bhi[a], blo[a] - cell_hi, 0.0f});
    };
    for (int z = clo[2]; z <= chi[2]; ++z) {
        const float gz = gap(z, 2);
        for (int y = clo[1]; y <= chi[1]; ++y) {
            const float gy = gap(y, 1);
            if (gy * gy + gz * gz > reach2) continue;
            // The row's cells clo[0]..chi[0] are one run of slots.
            const std::uint32_t k0 = t.start[g.cell(clo[0], y, z)];
            const std::uint32_t k1 = t.start[g.cell(chi[0], y, z) + 1];
            if (k0 == k1) continue;
            const std::size_t at = s.count;
            if (s.near.size() < at + (k1 - k0) + 8) {
                s.near.resize(2 * (at + (k1 - k0) + 8));
                s.slot.resize(s.near.size());
            }
            bound = std::min(bound, box_powers(&t.x[k0], &t.y[k0], &t.z[k0], &t.r2[k0], k1 - k0,
                                               blo, bhi, &s.near[at]));
            for (std::uint32_t j = 0; j < k1 - k0; ++j) s.slot[at + j] = k0 + j;
            s.count = at + (k1 - k0);
        }
    }
    s.bound = bound;
}

// Candidate atoms, x, y, z, (r + radius_add)² and index apart; [0, count) used.
struct Candidates {
    std::vector<float> x, y, z, r2;
    std::vector<std::uint32_t> index;
    std::size_t count = 0;
    void reserve(std::size_t n) {
        if (index.size() >= n) return;
        x.resize(n), y.resize(n), z.resize(n), r2.resize(n), index.resize(n);
    }
};

// The per-thread buffers of one layer of vertex cells.
struct Layer {
    std::vector<std::uint32_t> key, tmp, sorted, count, ids;
    std::vector<float> vx, vy, vz, near;
    std::vector<std::uint32_t> pick;  // the candidates kept, before their atoms are gathered
    Candidates group, cell;
    std::vector<std::uint32_t> best_atom;
    Scan scan;
    float reach = 8.0f;  // the last group's, a first guess for the next
};

// The largest least power a candidate of the box [blo, bhi] may have, from `bound` (a float
// upper bound on every vertex's least power there): the bound grown past its own float rounding,
// then the room for the rounding of the vertices' float powers (also far from the origin, where
// a difference of coordinates rounds to ulp(coordinate)).
double candidate_limit(float bound, double r2_max, const float blo[3], const float bhi[3]) {
    const double b = double(bound) + 1e-5 * (std::abs(double(bound)) + r2_max + 1.0);
    double coord = 0.0;
    for (int k = 0; k < 3; ++k)
        coord = std::max({coord, std::abs(double(blo[k])), std::abs(double(bhi[k]))});
    const double slack = 1e-4 * (1.0 + std::abs(b) + 2.0 * r2_max) +
                         1e-6 * coord * (1.0 + std::sqrt(std::max(b + r2_max, 0.0)));
    return b + slack;
}

// Atoms with a float least power `near` within `limit` (plus room for that power's rounding).
float keep_below(double limit, double r2_max) {
    return float(limit + 1e-5 * (std::abs(limit) + r2_max + 1.0));
}

// The candidates of the box [blo, bhi] into w.group: every atom whose least power over the box
// is within candidate_limit of the least largest power, found by scans of the atoms' cells.
void find_candidates(const AtomTable& t, const float blo[3], const float bhi[3], Layer& w) {
    Scan& s = w.scan;
    float reach = w.reach;
    double limit = 0.0;
    for (;;) {
        scan_atoms(t, blo, bhi, reach, s);
        if (!std::isfinite(s.bound)) {
            if (s.whole) {  // no finite power anywhere: every atom is a candidate
                limit = std::numeric_limits<double>::infinity();
                break;
            }
            reach = 2.0f * reach + 1.0f;
            continue;
        }
        limit = candidate_limit(s.bound, t.r2_max, blo, bhi);
        const double need = std::sqrt(std::max(limit + double(t.r2_max), 0.0)) + 0.01;
        if (need <= double(reach) || s.whole) {
            w.reach = float(need) * kGuess;
            break;
        }
        reach = float(need) * 1.05f;  // a wider scan only lowers the bound: one more suffices
    }
    // The slots kept (each written, kept when near: no branch), then their atoms gathered.
    const float below = keep_below(limit, t.r2_max);
    w.pick.resize(s.count);
    std::size_t kept = 0;
    for (std::size_t j = 0; j < s.count; ++j) {
        w.pick[kept] = s.slot[j];
        kept += !(s.near[j] > below);
    }
    Candidates& c = w.group;
    c.reserve(kept);
    for (std::size_t q = 0; q < kept; ++q) {
        const std::uint32_t k = w.pick[q];
        c.x[q] = t.x[k], c.y[q] = t.y[k], c.z[q] = t.z[k], c.r2[q] = t.r2[k];
        c.index[q] = t.index[k];
    }
    c.count = kept;
}

// The candidates of a box inside the group's box, from the group's candidates (which hold every
// atom that can be least in power anywhere in the group's box): the same rule with a bound from
// those candidates' largest powers over the smaller box.
void filter_candidates(const Candidates& from, double r2_max, const float blo[3],
                       const float bhi[3], Layer& w) {
    w.near.resize(from.count + 8);
    const float bound = box_powers(from.x.data(), from.y.data(), from.z.data(), from.r2.data(),
                                   from.count, blo, bhi, w.near.data());
    const float below = std::isfinite(bound)
                            ? keep_below(candidate_limit(bound, r2_max, blo, bhi), r2_max)
                            : std::numeric_limits<float>::infinity();
    w.pick.resize(from.count);
    std::size_t kept = 0;
    for (std::size_t j = 0; j < from.count; ++j) {
        w.pick[kept] = std::uint32_t(j);
        kept += !(w.near[j] > below);
    }
    Candidates& c = w.cell;
    c.reserve(kept);
    for (std::size_t q = 0; q < kept; ++q) {
        const std::uint32_t j = w.pick[q];
        c.x[q] = from.x[j], c.y[q] = from.y[j], c.z[q] = from.z[j];
        c.r2[q] = from.r2[j], c.index[q] = from.index[j];
    }
    c.count = kept;
}

// The vertices `ids` (one layer) sorted into cells of g, the cells in groups of 2 x 2 (x, y),
// their positions gathered into w.vx, vy, vz (padded by 8). w.key is each one's cell: its group
// is key >> 2.
void sort_layer(const Grid& g, const float* positions, const std::uint32_t* ids, std::size_t m,
                Layer& w) {
    w.key.resize(m), w.tmp.resize(m), w.sorted.resize(m);
    for (std::size_t j = 0; j < m; ++j) {
        const float* p = positions + 3 * std::size_t(ids[j]);
        const std::uint32_t x = std::uint32_t(g.at(p[0], 0)), y = std::uint32_t(g.at(p[1], 1));
        const std::uint32_t b = kGroupBits, mask = (1u << b) - 1;
        w.key[j] = (y >> b) << 17 | (x >> b) << (2 * b) | (y & mask) << b | (x & mask);
    }
    // Two counting passes, the low 17 bits then the rest (stable); the low ones only as far as
    // the grid's x reaches (a table of 2^17 counts a layer cost as much as its vertices).
    const std::size_t low = ((std::size_t(g.dims[0] - 1) >> kGroupBits) << (2 * kGroupBits)) +
                            (std::size_t(1) << (2 * kGroupBits));
    const std::size_t high = (std::size_t(g.dims[1]) >> kGroupBits) + 1;
    w.count.assign(low + 1, 0);
    for (std::size_t j = 0; j < m; ++j) ++w.count[(w.key[j] & 0x1ffff) + 1];
    for (std::size_t c = 0; c < low; ++c) w.count[c + 1] += w.count[c];
    for (std::size_t j = 0; j < m; ++j) w.tmp[w.count[w.key[j] & 0x1ffff]++] = std::uint32_t(j);
    w.count.assign(high + 1, 0);
    for (std::size_t j = 0; j < m; ++j) ++w.count[(w.key[j] >> 17) + 1];
    for (std::size_t c = 0; c < high; ++c) w.count[c + 1] += w.count[c];
    for (std::size_t t = 0; t < m; ++t) w.sorted[w.count[w.key[w.tmp[t]] >> 17]++] = w.tmp[t];
    w.ids.resize(m + 8);
    w.vx.resize(m + 8), w.vy.resize(m + 8), w.vz.resize(m + 8);
    for (std::size_t t = 0; t < m; ++t) {
        const std::uint32_t j = w.sorted[t];
        const float* p = positions + 3 * std::size_t(ids[j]);
        w.ids[t] = ids[j];
        w.vx[t] = p[0], w.vy[t] = p[1], w.vz[t] = p[2];
        w.tmp[t] = w.key[j];
    }
    std::swap(w.key, w.tmp);  // w.key[t]: the cell of sorted vertex t
    for (std::size_t t = m; t < m + 8; ++t) w.vx[t] = w.vy[t] = w.vz[t] = 0.0f;
}

// The box of vertices [first, end) of the layer. (In locals: stored through blo and bhi at each
// vertex, every step waited on the last one's store.)
void vertex_box(const Layer& w, std::size_t first, std::size_t end, float blo[3], float bhi[3]) {
    const float* v[3] = {w.vx.data(), w.vy.data(), w.vz.data()};
    for (int a = 0; a < 3; ++a) {
        const float* c = v[a];
        float lo = c[first], hi = c[first];
        for (std::size_t j = first + 1; j < end; ++j) lo = std::min(lo, c[j]), hi = std::max(hi, c[j]);
        blo[a] = lo, bhi[a] = hi;
    }
}

// One layer's vertices, group by group of cells: one scan of the atoms' cells per group (the
// scans' rows are scattered in memory), its candidates narrowed for each cell.
void search_layer(const AtomTable& t, const Grid& g, const float* positions,
                  const std::uint32_t* ids, std::size_t m, std::uint32_t* out,
                  std::size_t stride, Layer& w) {
    sort_layer(g, positions, ids, m, w);
    w.best_atom.resize(m + 8);
    for (std::size_t group = 0; group < m;) {
        std::size_t group_end = group + 1;
        while (group_end < m && w.key[group_end] >> (2 * kGroupBits) == w.key[group] >> (2 * kGroupBits)) ++group_end;
        float blo[3], bhi[3];
        vertex_box(w, group, group_end, blo, bhi);
        find_candidates(t, blo, bhi, w);
        for (std::size_t first = group; first < group_end;) {
            std::size_t end = first + 1;
            while (end < group_end && w.key[end] == w.key[first]) ++end;
            const Candidates* c = &w.group;
            if (first != group || end != group_end) {  // a cell of several: narrowed
                vertex_box(w, first, end, blo, bhi);
                filter_candidates(w.group, t.r2_max, blo, bhi, w);
                c = &w.cell;
            }
            const std::size_t padded = (end - first + 7) & ~std::size_t(7);
            try_candidates(&w.vx[first], &w.vy[first], &w.vz[first], padded, c->x.data(),
                           c->y.data(), c->z.data(), c->r2.data(), c->index.data(), c->count,
                           w.best_atom.data());
            for (std::size_t j = first; j < end; ++j)
                out[std::size_t(w.ids[j]) * stride] = w.best_atom[j - first];
            first = end;
        }
        group = group_end;
    }
}

}  // namespace

void host_vertex_atoms(const Atoms& atoms, const float* positions, std::size_t n,
                       float radius_add, std::uint32_t* out, std::size_t stride) {
    if (n == 0) return;
    const unsigned threads = thread_count(0);
    // The box of the finite vertices; the others have no atom.
    std::vector<float> boxes(6 * threads);
    parallel_chunks(threads, threads, [&](std::size_t k) {
        // In locals (through `boxes`, each vertex's steps waited on the last one's stores).
        float lo[3], hi[3];
        for (int a = 0; a < 3; ++a) lo[a] = std::numeric_limits<float>::max(), hi[a] = -lo[a];
        for (std::size_t v = n * k / threads; v < n * (k + 1) / threads; ++v) {
            const float* p = positions + 3 * v;
            if (!finite3(p)) {
                out[v * stride] = kNone;
                continue;
            }
            for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], p[a]), hi[a] = std::max(hi[a], p[a]);
        }
        for (int a = 0; a < 3; ++a) boxes[6 * k + a] = lo[a], boxes[6 * k + 3 + a] = hi[a];
    });
    float lo[3], hi[3];
    for (int a = 0; a < 3; ++a) {
        lo[a] = std::numeric_limits<float>::max(), hi[a] = -lo[a];
        for (unsigned k = 0; k < threads; ++k)
            lo[a] = std::min(lo[a], boxes[6 * k + a]), hi[a] = std::max(hi[a], boxes[6 * k + 3 + a]);
    }
    if (lo[0] > hi[0]) return;  // no finite vertex
    if (atoms.empty()) {
        for (std::size_t v = 0; v < n; ++v) out[v * stride] = kNone;
        return;
    }
    const AtomTable table = sort_atoms(atoms, lo, hi, radius_add);
    trace("vertex atoms: atoms sorted into cells");
    // Layers of vertex cells along z; x and y numbered in 16 bits each.
    const Grid g = make_grid(lo, hi, kVertexCell, [](const int* d) {
        return d[0] <= 0xffff && d[1] <= 0xffff && d[2] <= (1 << 20);
    });
    const std::size_t layers = std::size_t(g.dims[2]);
    std::vector<std::uint32_t> counts(threads * (layers + 1), 0);
    auto range = [&](std::size_t k) { return std::pair(n * k / threads, n * (k + 1) / threads); };
    parallel_chunks(threads, threads, [&](std::size_t k) {
        std::uint32_t* c = &counts[k * (layers + 1)];
        for (auto [v, e] = range(k); v < e; ++v)
            if (finite3(positions + 3 * v)) ++c[g.at(positions[3 * v + 2], 2)];
    });
    // Each thread's first slot in each layer: layers in order, threads in order within one.
    std::vector<std::uint32_t> layer_start(layers + 1, 0);
    std::uint32_t next = 0;
    for (std::size_t l = 0; l < layers; ++l) {
        layer_start[l] = next;
        for (unsigned k = 0; k < threads; ++k) {
            const std::uint32_t c = counts[k * (layers + 1) + l];
            counts[k * (layers + 1) + l] = next;
            next += c;
        }
    }
    layer_start[layers] = next;
    // Every slot is written below: not zeroed first, its pages provided on all threads.
    const std::unique_ptr<std::uint32_t[]> order(new std::uint32_t[next]);
    populate_pages({{order.get(), sizeof(std::uint32_t) * next}});
    parallel_chunks(threads, threads, [&](std::size_t k) {
        std::uint32_t* c = &counts[k * (layers + 1)];
        for (auto [v, e] = range(k); v < e; ++v)
            if (finite3(positions + 3 * v))
                order[c[g.at(positions[3 * v + 2], 2)]++] = std::uint32_t(v);
    });
    trace("vertex atoms: vertices sorted into layers");
    // Layers taken in order by whichever thread is free, each thread with buffers of its own.
    std::atomic<std::size_t> next_layer{0};
    parallel_chunks(threads, threads, [&](std::size_t) {
        Layer w;
        for (std::size_t l; (l = next_layer++) < layers;)
            if (layer_start[l + 1] > layer_start[l])
                search_layer(table, g, positions, &order[layer_start[l]],
                             layer_start[l + 1] - layer_start[l], out, stride, w);
    });
    trace("vertex atoms: searched");
}

}  // namespace fdmsurf::detail
