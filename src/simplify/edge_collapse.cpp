// Half-edge collapses in order of quadric error (M. Garland and P. S. Heckbert, "Surface
// simplification using quadric error metrics", 1997) that test the link condition as they go
// (T. K. Dey, H. Edelsbrunner, S. Guha and D. V. Nekhayev, "Topology preserving edge
// contraction", 1999): no collapse pinches a neck, folds a small piece flat or joins two sheets,
// so the result has the input's topology by construction. meshoptimizer 0.18 does not test it,
// and its defects on molecular surfaces have to be found and simplified again (region_simplify).
//
// The cost of collapsing u into its neighbour v is u's quadric (the area-weighted plane
// quadrics of its triangles, and of those collapsed into it) at v, over u's area: a mean squared
// distance, Å², as meshoptimizer ranks them. Each movable vertex is queued with its cheapest
// collapse, in buckets an eighth of an octave of cost wide; keys are kept exact as collapses
// change them (the collapsed-into vertex is costed again; each of the collapsed vertex's
// neighbours gains one candidate, or is costed again when its best was the collapsed vertex).
// Triangles are kept as corner lists per vertex in an arena: a collapse writes the merged list
// at the arena's end; a killed triangle stays in its third vertex's list until walked there.
#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "simplify/simplify_detail.hpp"

namespace fdmsurf::detail {
namespace {

using Index = std::uint32_t;
constexpr Index kNone = std::numeric_limits<Index>::max();

// Symmetric 4x4 quadric of a point's squared distances to planes: x·A·x + 2 b·x + c.
struct Quadric {
    double a00 = 0, a01 = 0, a02 = 0, a11 = 0, a12 = 0, a22 = 0, b0 = 0, b1 = 0, b2 = 0, c = 0;
    double w = 0;  // area summed into it, Å²

    void add(const Quadric& o) {
        a00 += o.a00, a01 += o.a01, a02 += o.a02, a11 += o.a11, a12 += o.a12, a22 += o.a22;
        b0 += o.b0, b1 += o.b1, b2 += o.b2, c += o.c, w += o.w;
    }
    double at(const float* p) const {
        const double x = p[0], y = p[1], z = p[2];
        const double r = x * (a00 * x + 2 * (a01 * y + a02 * z + b0)) +
                         y * (a11 * y + 2 * (a12 * z + b1)) + z * (a22 * z + 2 * b2) + c;
        return r > 0 ? r : 0;
    }
};

// kInterior: one closed fan, may move. kBorder: one open fan, or a corner of a fixed triangle:
// stays, may be collapsed into. kLocked: anything else (non-manifold, unused, more than 64
// corners): stays, never a target.
enum class Kind : std::uint8_t { kInterior, kBorder, kLocked };

// (b - a) x (c - a), in double.
std::array<double, 3> cross(const float* a, const float* b, const float* c) {
    const double u[3] = {double(b[0]) - a[0], double(b[1]) - a[1], double(b[2]) - a[2]};
    const double w[3] = {double(c[0]) - a[0], double(c[1]) - a[1], double(c[2]) - a[2]};
    return {u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]};
}

// Costs in buckets an eighth of an octave wide (a float's exponent and its first three mantissa
// bits); within one bucket, the order is the last queued first.
constexpr std::size_t kBuckets = 2048;
inline Index bucket_of(double cost) {
    const float c = static_cast<float>(cost);
    return c > 0 ? std::min<Index>(std::bit_cast<std::uint32_t>(c) >> 20, Index{kBuckets - 1}) : 0;
}

// A triangle's plane, from which each corner's vertex adds up its quadric: the normal
// n = (b - a) x (c - a), the offset d = -n.a, f = 1 / (2 |n|) (its quadric's scale: the area
// times the plane quadric of the unit normal) and the area w = |n| / 2, not positive for a
// degenerate triangle.
struct Plane {
    double n[3];
    double d, f, w;
};

// The working state, kept per thread from region to region (its memory, not its contents).
struct Collapser {
    const float* pos = nullptr;
    std::vector<Index> tri;  // 3 per triangle: the current vertices of corners 3t, 3t+1, 3t+2
    std::vector<std::uint8_t> dead;   // per triangle
    std::vector<Index> arena;         // corner lists
    std::vector<Index> first, count;  // per vertex: its corner list in the arena
    std::vector<Kind> kind;
    std::vector<std::uint8_t> stuck;  // no valid collapse when last tried
    std::vector<Quadric> quadric;
    std::vector<std::array<float, 3>> normal;  // per vertex: the input's area-weighted normal
    std::vector<Plane> plane;                  // per triangle, for the quadrics
    std::vector<Index> best;  // per vertex: the neighbour of its cheapest collapse, and its cost
    std::vector<double> best_cost;
    // The queue: per bucket a doubly linked list of vertices, and a bit per non-empty bucket.
    std::vector<Index> bucket_head = std::vector<Index>(kBuckets, kNone);
    std::vector<Index> in_bucket, before, after;  // per vertex (in_bucket kNone: not queued)
    std::array<std::uint64_t, kBuckets / 64> filled{};
    std::size_t queued = 0;
    // Scratch.
    std::vector<Index> mark;  // == token: a neighbour of the vertex being collapsed
    Index token = 0;
    std::vector<Index> nu, nv;
    std::vector<std::pair<double, Index>> options;

    const float* p(Index v) const { return pos + 3 * std::size_t{v}; }
    static Index after_corner(Index c) { return c % 3 == 2 ? c - 2 : c + 1; }
    static Index before_corner(Index c) { return c % 3 == 0 ? c + 2 : c - 1; }

    double cost(Index u, Index v) const {
        const Quadric& q = quadric[u];
        return q.w > 0 ? q.at(p(v)) / q.w : 0.0;
    }

    std::size_t lowest() const {
        for (std::size_t w = 0; w < filled.size(); ++w) {
            if (filled[w]) return 64 * w + std::size_t(std::countr_zero(filled[w]));
        }
        return kBuckets;
    }

    void unqueue(Index u) {
        const Index b = in_bucket[u];
        if (b == kNone) return;
        (before[u] == kNone ? bucket_head[b] : after[before[u]]) = after[u];
        if (after[u] != kNone) before[after[u]] = before[u];
        if (bucket_head[b] == kNone) filled[b / 64] &= ~(std::uint64_t{1} << (b % 64));
        in_bucket[u] = kNone;
        --queued;
    }

    // u queued (or moved) with u -> v at cost c as its cheapest collapse.
    void queue(Index u, Index v, double c) {
        best[u] = v;
        best_cost[u] = c;
        const Index b = bucket_of(c);
        if (in_bucket[u] == b) return;
        unqueue(u);
        in_bucket[u] = b;
        before[u] = kNone;
        after[u] = bucket_head[b];
        if (after[u] != kNone) before[after[u]] = u;
        bucket_head[b] = u;
        filled[b / 64] |= std::uint64_t{1} << (b % 64);
        ++queued;
    }

    // v's live corners, its list compacted on the way.
    template <class F>
    void corners(Index v, F&& f) {
        Index* list = arena.data() + first[v];
        Index kept = 0;
        for (Index i = 0; i < count[v]; ++i) {
            const Index c = list[i];
            if (dead[c / 3]) continue;
            list[kept++] = c;
            f(c);
        }
        count[v] = kept;
    }

    // The distinct neighbours of v into `out`. Around a vertex of one closed fan each neighbour
    // follows exactly one corner; around an open fan one more precedes one only.
    void neighbours(Index v, std::vector<Index>& out) {
        out.resize(count[v]);  // at most this many live corners
        Index* o = out.data();
        std::size_t k = 0;
        corners(v, [&](Index c) { o[k++] = tri[after_corner(c)]; });
        out.resize(k);
        if (kind[v] != Kind::kInterior) {
            const Index* list = arena.data() + first[v];
            for (Index i = 0; i < count[v]; ++i) {
                const Index prev = tri[before_corner(list[i])];
                if (std::find(out.begin(), out.end(), prev) == out.end()) out.push_back(prev);
            }
        }
    }

    // Whether collapsing the interior vertex u (neighbours in `nu`) into its neighbour v keeps
    // the surface a manifold of the same topology with no triangle turned over.
    bool valid(Index u, Index v) {
        if (kind[v] == Kind::kLocked) return false;
        neighbours(v, nv);
        // The link condition on an edge inside the surface: its ends share exactly the two
        // vertices opposite it.
        ++token;
        for (Index a : nu) mark[a] = token;
        Index shared = 0;
        for (Index a : nv) shared += mark[a] == token;
        if (shared != 2) return false;
        // And the links share no edge: with u of valence 3 (neighbours v, a, b), its triangle
        // u a b becomes v a b, which must not be there already (a tetrahedron folding flat).
        if (nu.size() == 3) {
            Index a = kNone, b = kNone;
            for (Index x : nu) {
                if (x != v) (a == kNone ? a : b) = x;
            }
            const Index* list = arena.data() + first[v];
            for (Index i = 0; i < count[v]; ++i) {
                const Index x = tri[after_corner(list[i])], y = tri[before_corner(list[i])];
                if ((x == a && y == b) || (x == b && y == a)) return false;
            }
        }
        // No triangle of u that stays may turn by more than 75 degrees (cos > 1/4) or become
        // degenerate.
        const float *pu = p(u), *pv = p(v);
        const Index* list = arena.data() + first[u];
        for (Index i = 0; i < count[u]; ++i) {
            const Index c = list[i];
            const Index a = tri[after_corner(c)], b = tri[before_corner(c)];
            if (a == v || b == v) continue;
            const auto n0 = cross(pu, p(a), p(b)), n1 = cross(pv, p(a), p(b));
            const double d = n0[0] * n1[0] + n0[1] * n1[1] + n0[2] * n1[2];
            const double l0 = n0[0] * n0[0] + n0[1] * n0[1] + n0[2] * n0[2];
            const double l1 = n1[0] * n1[0] + n1[1] * n1[1] + n1[2] * n1[2];
            if (!(d > 0 && 16 * d * d > l0 * l1)) return false;
            // Nor face against the input's normals at its corners (turns that add up over
            // collapses).
            const auto &m = normal[v], &ma = normal[a], &mb = normal[b];
            if (!(n1[0] * (m[0] + ma[0] + mb[0]) + n1[1] * (m[1] + ma[1] + mb[1]) +
                      n1[2] * (m[2] + ma[2] + mb[2]) >
                  0))
                return false;
        }
        return true;
    }

    // u's collapses into its neighbours `ring` into `options`; the position of the cheapest.
    std::size_t cost_options(Index u, const std::vector<Index>& ring) {
        const Quadric& q = quadric[u];
        const double scale = q.w > 0 ? 1.0 / q.w : 0.0;
        options.resize(ring.size());
        std::size_t cheapest = 0;
        for (std::size_t i = 0; i < ring.size(); ++i) {
            options[i] = {q.at(p(ring[i])) * scale, ring[i]};
            if (options[i].first < options[cheapest].first) cheapest = i;
        }
        return cheapest;
    }

    // u costed from scratch and queued with its cheapest collapse.
    void refresh(Index u) {
        stuck[u] = 0;
        neighbours(u, nv);
        const std::size_t cheapest = cost_options(u, nv);
        if (!options.empty()) queue(u, options[cheapest].second, options[cheapest].first);
    }

    // u's live triangles moved to v, the two on the edge killed; v's list rewritten at the
    // arena's end. Returns the triangles killed.
    std::size_t collapse(Index u, Index v) {
        std::size_t killed = 0;
        const Index start = static_cast<Index>(arena.size());
        for (Index i = 0; i < count[v]; ++i) {
            const Index c = arena[first[v] + i];
            const Index t = c / 3;
            if (dead[t]) continue;
            if (tri[3 * t] == u || tri[3 * t + 1] == u || tri[3 * t + 2] == u) {
                dead[t] = 1;
                ++killed;
                continue;
            }
            arena.push_back(c);
        }
        for (Index i = 0; i < count[u]; ++i) {
            const Index c = arena[first[u] + i];
            if (dead[c / 3]) continue;
            tri[c] = v;
            arena.push_back(c);
        }
        first[v] = start;
        count[v] = static_cast<Index>(arena.size()) - start;
        count[u] = 0;
        quadric[v].add(quadric[u]);
        return killed;
    }
};

// A vertex's kind from its corners' (next, previous) vertices: interior when they chain (each
// corner's next the previous of exactly one other) into one closed fan, border when into one
// open fan, else locked.
constexpr std::size_t kMaxStar = 64;  // more corners at one vertex: locked
using Star = std::array<std::array<Index, 2>, kMaxStar>;

Kind classify(const Star& star, std::size_t n) {
    if (n == 0 || n > kMaxStar) return Kind::kLocked;
    // One closed fan: from corner 0, the corner whose previous vertex is this one's next, and
    // so on, back at corner 0 after exactly n steps (each corner met once).
    std::size_t i = 0, steps = 0;
    do {
        std::size_t j = 0;
        while (j < n && star[j][1] != star[i][0]) ++j;
        if (j == n) break;
        i = j;
    } while (++steps < n && i != 0);
    if (i == 0 && steps == n) return Kind::kInterior;
    // One open fan: every side used once, one corner starts the chain, which meets all.
    bool simple = true;
    std::size_t ends = 0, starts = 0, start = 0;
    for (i = 0; i < n && simple; ++i) {
        std::size_t matches = 0, back = 0;
        for (std::size_t j = 0; j < n; ++j) {
            matches += star[j][1] == star[i][0];
            back += star[j][0] == star[i][1];
            if (j != i && star[j][0] == star[i][0]) simple = false;
        }
        if (matches > 1 || back > 1) simple = false;
        ends += matches == 0;
        if (back == 0) ++starts, start = i;
    }
    if (!simple || ends != 1 || starts != 1) return Kind::kLocked;
    std::size_t walked = 1;
    for (i = start; walked < n; ++walked) {
        std::size_t j = 0;
        while (j < n && star[j][1] != star[i][0]) ++j;
        if (j == n) break;
        i = j;
    }
    return walked == n ? Kind::kBorder : Kind::kLocked;
}

}  // namespace

std::vector<Index> collapse_edges(const std::vector<float>& positions,
                                  const std::vector<Index>& indices,
                                  const std::vector<Index>& fixed, std::size_t target,
                                  double max_error, double* error) {
    thread_local Collapser s;
    const std::size_t nv = positions.size() / 3, own = indices.size() / 3;
    if (error) *error = 0.0;
    if (target >= own) return indices;
    s.pos = positions.data();
    s.tri = indices;
    s.tri.insert(s.tri.end(), fixed.begin(), fixed.end());
    const std::size_t triangles = s.tri.size() / 3, corners = s.tri.size();
    s.dead.assign(triangles, 0);
    // The corner lists, by a counting sort; room behind them for the lists collapses write.
    s.count.assign(nv, 0);
    for (Index v : s.tri) ++s.count[v];
    s.first.resize(nv);
    Index at = 0;
    for (std::size_t v = 0; v < nv; ++v) s.first[v] = at, at += s.count[v];
    s.arena.resize(corners);
    s.arena.reserve(corners + 16 * (own - std::min(own, target)));
    {
        std::vector<Index>& fill = s.best;  // scratch here: the next free slot per vertex
        fill.assign(s.first.begin(), s.first.end());
        for (std::size_t c = 0; c < corners; ++c) s.arena[fill[s.tri[c]]++] = Index(c);
    }
    // Each triangle's plane, in one sweep.
    s.plane.resize(triangles);
    for (std::size_t t = 0; t < triangles; ++t) {
        const float *a = s.p(s.tri[3 * t]), *b = s.p(s.tri[3 * t + 1]), *c = s.p(s.tri[3 * t + 2]);
        const auto n = cross(a, b, c);
        Plane& pl = s.plane[t];
        pl.n[0] = n[0], pl.n[1] = n[1], pl.n[2] = n[2];
        const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
        pl.d = -(n[0] * a[0] + n[1] * a[1] + n[2] * a[2]);
        pl.f = 0.5 / len;
        pl.w = len > 0 ? 0.5 * len : 0.0;
    }
    s.quadric.resize(nv);
    s.normal.resize(nv);
    s.kind.resize(nv);
    s.stuck.assign(nv, 0);
    s.mark.assign(nv, 0);
    s.token = 0;
    s.best.assign(nv, kNone);
    s.best_cost.assign(nv, std::numeric_limits<double>::infinity());
    std::fill(s.bucket_head.begin(), s.bucket_head.end(), kNone);
    s.in_bucket.assign(nv, kNone);
    s.before.resize(nv);
    s.after.resize(nv);
    s.filled.fill(0);
    s.queued = 0;
    // Then each vertex in one visit of its corners (in triangle order): its kind, its quadric
    // (the area times the plane quadric of the unit normal, summed over its triangles) and its
    // input normal, and, when it may move, its cheapest collapse (each neighbour of a vertex
    // inside the surface follows exactly one of its corners), queued.
    const Index own_corners = static_cast<Index>(indices.size());
    Star star;
    for (std::size_t v = 0; v < nv; ++v) {
        const Index* list = s.arena.data() + s.first[v];
        const std::size_t n = s.count[v];
        Quadric q;
        std::array<float, 3> normal{0.0f, 0.0f, 0.0f};
        bool on_fixed = false;
        for (std::size_t i = 0; i < n; ++i) {
            const Index c = list[i];
            on_fixed |= c >= own_corners;
            if (i < kMaxStar) {
                star[i] = {s.tri[Collapser::after_corner(c)], s.tri[Collapser::before_corner(c)]};
            }
            const Plane& pl = s.plane[c / 3];
            if (!(pl.w > 0)) continue;
            const double f = pl.f, x = pl.n[0], y = pl.n[1], z = pl.n[2], d = pl.d;
            q.a00 += f * x * x, q.a01 += f * x * y, q.a02 += f * x * z;
            q.a11 += f * y * y, q.a12 += f * y * z, q.a22 += f * z * z;
            q.b0 += f * d * x, q.b1 += f * d * y, q.b2 += f * d * z;
            q.c += f * d * d, q.w += pl.w;
            for (int j = 0; j < 3; ++j) normal[j] += static_cast<float>(pl.n[j]);
        }
        s.quadric[v] = q;
        s.normal[v] = normal;
        Kind kind = classify(star, n);
        // The corners of the fixed triangles stay where they are (collapses may end there).
        if (on_fixed && kind == Kind::kInterior) kind = Kind::kBorder;
        s.kind[v] = kind;
        if (kind != Kind::kInterior) continue;
        double best = std::numeric_limits<double>::infinity();
        Index into = kNone;
        for (std::size_t i = 0; i < n; ++i) {
            const double cost = s.cost(Index(v), star[i][0]);
            if (cost < best) best = cost, into = star[i][0];
        }
        s.queue(Index(v), into, best);
    }
    const double limit =
        std::isinf(max_error) ? std::numeric_limits<double>::infinity() : max_error * max_error;
    double worst = 0.0;
    std::size_t live = own;
    while (live > target && s.queued > 0) {
        const std::size_t current = s.lowest();
        const Index u = s.bucket_head[current];
        s.unqueue(u);
        s.neighbours(u, s.nu);
        Index into = s.best[u];
        double cost = s.best_cost[u];
        if (!s.valid(u, into)) {
            // The others, cheapest first; one dearer than this bucket waits its turn.
            s.cost_options(u, s.nu);
            std::sort(s.options.begin(), s.options.end());
            const Index tried = into;
            into = kNone;
            bool later = false;
            for (const auto& [c, v] : s.options) {
                if (v == tried) continue;
                if (bucket_of(c) > current) {
                    s.queue(u, v, c);
                    later = true;
                    break;
                }
                if (s.valid(u, v)) {
                    into = v, cost = c;
                    break;
                }
            }
            if (later) continue;
            if (into == kNone) {
                s.stuck[u] = 1;  // until a neighbour's collapse changes its star
                continue;
            }
        }
        if (cost > limit) break;  // the collapses left cost about as much or more
        worst = std::max(worst, cost);
        live -= s.collapse(u, into);
        // Keys kept exact: `into` has a new quadric and new neighbours; each of u's other
        // neighbours lost u and gained `into` (a collapse into it costs what it would have:
        // `into` did not move).
        if (s.kind[into] == Kind::kInterior) s.refresh(into);
        for (Index n : s.nu) {
            if (n == into || s.kind[n] != Kind::kInterior) continue;
            if (s.stuck[n] || s.best[n] == u) {
                s.refresh(n);
            } else {
                const double c = s.cost(n, into);
                if (c < s.best_cost[n]) s.queue(n, into, c);
            }
        }
    }
    if (error) *error = std::sqrt(worst);
    std::vector<Index> out;
    out.reserve(3 * live);
    for (std::size_t t = 0; t < own; ++t) {
        if (!s.dead[t]) out.insert(out.end(), &s.tri[3 * t], &s.tri[3 * t] + 3);
    }
    return out;
}

}  // namespace fdmsurf::detail
