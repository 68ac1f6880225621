// One region simplified by fdmsurf's own collapses (edge_collapse.cpp), or by meshopt_simplify
// without breaking its topology. meshoptimizer 0.18
// collapses edges without testing the link condition (T. K. Dey, H. Edelsbrunner, S. Guha and
// D. V. Nekhayev, "Topology preserving edge contraction", 1999), so on molecular surfaces, with
// their narrow necks and tunnels, a few collapses fold triangles onto each other: non-manifold
// edges and vertices (reported upstream as zeux/meshoptimizer#346, #699). The guard here finds
// them afterwards and simplifies again with the input frozen around them.
#include <meshoptimizer.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

#include "mesh/union_find.hpp"
#include "simplify/simplify_detail.hpp"

namespace fdmsurf::detail {
namespace {

using Index = std::uint32_t;

// One key per triangle side: lo << 33 | hi << 1 | (1 when the triangle runs hi -> lo). Sorted,
// the uses of one edge are adjacent, those along lo -> hi first.
std::vector<std::uint64_t> edge_uses(const std::vector<Index>& indices) {
    std::vector<std::uint64_t> keys;
    keys.reserve(indices.size());
    for (std::size_t c = 0; c < indices.size(); c += 3) {
        for (int k = 0; k < 3; ++k) {
            const std::uint64_t a = indices[c + k], b = indices[c + (k + 1) % 3];
            keys.push_back(a < b ? (a << 33 | b << 1) : (b << 33 | a << 1 | 1));
        }
    }
    std::sort(keys.begin(), keys.end());
    return keys;
}

struct EdgeCount {
    std::uint64_t edge;  // lo << 32 | hi
    Index forward;       // uses lo -> hi
    Index backward;      // uses hi -> lo
    bool operator<(const EdgeCount& o) const { return edge < o.edge; }
};

// The edges not used exactly once each way, sorted by edge.
std::vector<EdgeCount> irregular_edges(const std::vector<Index>& indices) {
    const std::vector<std::uint64_t> keys = edge_uses(indices);
    std::vector<EdgeCount> irregular;
    for (std::size_t i = 0; i < keys.size();) {
        const std::uint64_t edge = keys[i] >> 1;  // lo << 32 | hi
        EdgeCount e{edge, 0, 0};
        for (; i < keys.size() && keys[i] >> 1 == edge; ++i)
            ++(keys[i] & 1 ? e.backward : e.forward);
        if (e.forward != 1 || e.backward != 1) irregular.push_back(e);
    }
    return irregular;
}

std::uint64_t edge_key(Index a, Index b) {
    return a < b ? std::uint64_t{a} << 32 | b : std::uint64_t{b} << 32 | a;
}

// The corners at each vertex, by a counting sort: the corners of vertex v are
// around[start[v]] .. around[start[v + 1] - 1], each as its triangle's next and previous
// vertex (the sides v -> next and prev -> v).
struct Stars {
    std::vector<Index> start;
    std::vector<std::array<Index, 2>> around;
};

Stars vertex_stars(const std::vector<Index>& indices, std::size_t vertex_count) {
    Stars s;
    s.start.assign(vertex_count + 1, 0);
    for (Index v : indices) ++s.start[v + 1];
    for (std::size_t v = 0; v < vertex_count; ++v) s.start[v + 1] += s.start[v];
    s.around.resize(indices.size());
    std::vector<Index> fill(s.start.begin(), s.start.end() - 1);
    for (std::size_t c = 0; c < indices.size(); ++c) {
        const std::size_t t = c - c % 3;
        s.around[fill[indices[c]]++] = {indices[t + (c % 3 + 1) % 3], indices[t + (c % 3 + 2) % 3]};
    }
    return s;
}

// How many fans the n corners `o` of one vertex form: triangles sharing a neighbour share the
// edge to it, one fan. `parent` is scratch space; `shared(a, b)` is called for every pair of
// corners that share a neighbour. Valences are small: all pairs are tried.
template <class Shared>
Index star_fans(const std::array<Index, 2>* o, Index n, std::vector<Index>& parent,
                Shared&& shared) {
    parent.resize(n);
    for (Index i = 0; i < n; ++i) parent[i] = i;
    auto find = [&parent](Index x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    for (Index i = 0; i < n; ++i) {
        for (Index j = 0; j < i; ++j) {
            const auto& a = o[i];
            const auto& b = o[j];
            if (a[0] == b[0] || a[0] == b[1] || a[1] == b[0] || a[1] == b[1]) {
                parent[find(i)] = find(j);
                shared(a, b);
            }
        }
    }
    Index roots = 0;
    for (Index i = 0; i < n; ++i) roots += find(i) == i;
    return roots;
}

// Per vertex, how many fans its triangles form (triangles joined through the edges at the
// vertex): 1 on a manifold vertex, 0 on an unused one.
std::vector<Index> fan_counts(const std::vector<Index>& indices, std::size_t vertex_count) {
    const Stars stars = vertex_stars(indices, vertex_count);
    std::vector<Index> fans(vertex_count, 0);
    std::vector<Index> parent;
    for (std::size_t v = 0; v < vertex_count; ++v) {
        const Index first = stars.start[v], n = stars.start[v + 1] - first;
        if (n > 0)
            fans[v] = star_fans(&stars.around[first], n, parent, [](const auto&, const auto&) {});
    }
    return fans;
}

// The vertex triples (sorted) of triangles that share their three vertices with another.
std::vector<std::array<Index, 3>> doubled_triangles(const std::vector<Index>& indices) {
    std::vector<std::array<Index, 3>> triples(indices.size() / 3);
    for (std::size_t t = 0; t < triples.size(); ++t) {
        triples[t] = {indices[3 * t], indices[3 * t + 1], indices[3 * t + 2]};
        std::sort(triples[t].begin(), triples[t].end());
    }
    std::sort(triples.begin(), triples.end());
    std::vector<std::array<Index, 3>> doubled;
    for (std::size_t t = 1; t < triples.size(); ++t) {
        if (triples[t] == triples[t - 1] && (doubled.empty() || doubled.back() != triples[t]))
            doubled.push_back(triples[t]);
    }
    return doubled;
}

// Marks the triangles with a corner among `defects` or within `radius` (Å) of one of them.
std::size_t freeze_around(const std::vector<float>& positions, const std::vector<Index>& indices,
                          const std::vector<Index>& defects, double radius,
                          std::vector<std::uint8_t>& frozen) {
    const std::size_t nv = positions.size() / 3;
    std::vector<std::uint8_t> near(nv, 0);
    for (Index v : defects) near[v] = 1;
    if (radius > 0.0) {
        // Defects bucketed in cubes of edge `radius` (keys may collide; the distance decides).
        auto cell = [radius](float x) { return std::int64_t(std::floor(double(x) / radius)); };
        auto key = [](std::int64_t x, std::int64_t y, std::int64_t z) {
            constexpr std::uint64_t m = (1u << 21) - 1;
            return (std::uint64_t(x) & m) << 42 | (std::uint64_t(y) & m) << 21 |
                   (std::uint64_t(z) & m);
        };
        std::vector<std::pair<std::uint64_t, Index>> buckets;
        for (Index v : defects) {
            const float* p = &positions[3 * std::size_t{v}];
            buckets.push_back({key(cell(p[0]), cell(p[1]), cell(p[2])), v});
        }
        std::sort(buckets.begin(), buckets.end());
        const double r2 = radius * radius;
        for (std::size_t v = 0; v < nv; ++v) {
            if (near[v]) continue;
            const float* p = &positions[3 * v];
            const std::int64_t cx = cell(p[0]), cy = cell(p[1]), cz = cell(p[2]);
            for (int d = 0; d < 27 && !near[v]; ++d) {
                const std::uint64_t k = key(cx + d % 3 - 1, cy + d / 3 % 3 - 1, cz + d / 9 - 1);
                auto it = std::lower_bound(buckets.begin(), buckets.end(),
                                           std::pair<std::uint64_t, Index>{k, 0});
                for (; it != buckets.end() && it->first == k; ++it) {
                    const float* q = &positions[3 * std::size_t{it->second}];
                    const double dx = p[0] - q[0], dy = p[1] - q[1], dz = p[2] - q[2];
                    if (dx * dx + dy * dy + dz * dz <= r2) {
                        near[v] = 1;
                        break;
                    }
                }
            }
        }
    }
    std::size_t count = 0;
    for (std::size_t t = 0; t < frozen.size(); ++t) {
        const Index* tri = &indices[3 * t];
        if (near[tri[0]] || near[tri[1]] || near[tri[2]]) frozen[t] = 1;
        count += frozen[t];
    }
    return count;
}

double total_area(const std::vector<float>& p, const std::vector<Index>& indices) {
    double area = 0.0;
    for (std::size_t c = 0; c < indices.size(); c += 3) {
        const float* a = &p[3 * std::size_t{indices[c]}];
        const float* b = &p[3 * std::size_t{indices[c + 1]}];
        const float* d = &p[3 * std::size_t{indices[c + 2]}];
        const double u[3] = {b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const double w[3] = {d[0] - a[0], d[1] - a[1], d[2] - a[2]};
        const double x = u[1] * w[2] - u[2] * w[1], y = u[2] * w[0] - u[0] * w[2],
                     z = u[0] * w[1] - u[1] * w[0];
        area += 0.5 * std::sqrt(x * x + y * y + z * z);
    }
    return area;
}

// What new_defects needs to know of the output, from one walk over the corners at each vertex
// (a counting sort, then the small star of each vertex) instead of sorting every edge use and
// every triangle: the edges not used once each way with their counts (sorted by edge), the
// fans at each vertex, and the vertex triples of triangles that share their three vertices.
// Only for outputs without a triangle that repeats a vertex (meshoptimizer drops those);
// new_defects takes the sorting path for the others.
struct OutputStars {
    std::vector<EdgeCount> irregular;
    std::vector<Index> fans;
    std::vector<std::array<Index, 3>> doubled;
};

// `changed`: the vertices to examine (null: all). Every other vertex must have the same
// triangles in `indices` as in the input: then so have its fans, and its edges, which are
// found from their lower end only, also when the upper end is examined.
OutputStars output_stars(const std::vector<Index>& indices, std::size_t vertex_count,
                         const std::vector<std::uint8_t>* changed) {
    OutputStars s;
    const Stars stars = vertex_stars(indices, vertex_count);
    s.fans.assign(vertex_count, 0);
    std::vector<Index> parent;
    for (std::size_t v = 0; v < vertex_count; ++v) {
        const Index first = stars.start[v], n = stars.start[v + 1] - first;
        if (n == 0 || (changed && !(*changed)[v])) continue;
        const std::array<Index, 2>* o = &stars.around[first];
        s.fans[v] = star_fans(o, n, parent, [&](const auto& a, const auto& b) {
            // The same two other vertices: a triangle doubled (seen from its lowest).
            if (((a[0] == b[0] && a[1] == b[1]) || (a[0] == b[1] && a[1] == b[0])) && v < a[0] &&
                v < a[1]) {
                s.doubled.push_back({Index(v), std::min(a[0], a[1]), std::max(a[0], a[1])});
            }
        });
        // The edges v - u with u > v: side v -> u is a corner at v whose next is u (lo -> hi),
        // side u -> v one whose previous is u.
        for (Index i = 0; i < n; ++i) {
            for (int k = 0; k < 2; ++k) {
                const Index u = o[i][k];
                if (u <= v) continue;
                bool seen = false;  // counted already, from an earlier corner
                for (Index j = 0; j < i && !seen; ++j) seen = o[j][0] == u || o[j][1] == u;
                if (seen || (k == 1 && o[i][0] == u)) continue;
                EdgeCount e{edge_key(Index(v), u), 0, 0};
                for (Index j = i; j < n; ++j) {
                    e.forward += o[j][0] == u;
                    e.backward += o[j][1] == u;
                }
                if (e.forward != 1 || e.backward != 1) s.irregular.push_back(e);
            }
        }
    }
    std::sort(s.irregular.begin(), s.irregular.end());
    std::sort(s.doubled.begin(), s.doubled.end());
    s.doubled.erase(std::unique(s.doubled.begin(), s.doubled.end()), s.doubled.end());
    return s;
}

bool repeats_a_vertex(const std::vector<Index>& indices) {
    for (std::size_t c = 0; c < indices.size(); c += 3) {
        if (indices[c] == indices[c + 1] || indices[c + 1] == indices[c + 2] ||
            indices[c + 2] == indices[c])
            return true;
    }
    return false;
}

}  // namespace

std::vector<Index> piece_labels(const std::vector<Index>& indices, std::size_t vertex_count) {
    DisjointSets sets(vertex_count);
    std::vector<std::uint8_t> used(vertex_count, 0);
    for (std::size_t c = 0; c < indices.size(); c += 3) {
        sets.unite(indices[c], indices[c + 1]);
        sets.unite(indices[c], indices[c + 2]);
        used[indices[c]] = used[indices[c + 1]] = used[indices[c + 2]] = 1;
    }
    std::vector<Index> label(vertex_count);
    for (std::size_t v = 0; v < vertex_count; ++v)
        label[v] = used[v] ? sets.find(Index(v)) : kNoPiece;
    return label;
}

std::vector<Index> new_defects(const std::vector<Index>& in, const std::vector<Index>& out,
                               std::size_t vertex_count) {
    return new_defects(in, piece_labels(in, vertex_count), out, vertex_count);
}

std::vector<Index> new_defects(const std::vector<Index>& in, const std::vector<Index>& in_pieces,
                               const std::vector<Index>& out, std::size_t vertex_count,
                               std::size_t context) {
    std::vector<Index> defects;
    OutputStars stars;
    if (repeats_a_vertex(out)) {
        stars.irregular = irregular_edges(out);
        stars.fans = fan_counts(out, vertex_count);
        stars.doubled = doubled_triangles(out);
    } else if (context == 0 || 3 * context > in.size() || 3 * context > out.size()) {
        stars = output_stars(out, vertex_count, nullptr);
    } else {
        // The vertices of the triangles before the shared context, in the input or the output:
        // only at them can triangles, and so edges and fans, differ.
        std::vector<std::uint8_t> changed(vertex_count, 0);
        for (std::size_t c = 0; c + 3 * context < in.size(); ++c) changed[in[c]] = 1;
        for (std::size_t c = 0; c + 3 * context < out.size(); ++c) changed[out[c]] = 1;
        stars = output_stars(out, vertex_count, &changed);
    }
    // The input is larger than the output: it is only scanned, for the edges and vertices that
    // look wrong in the output.
    const std::vector<EdgeCount>& out_irregular = stars.irregular;
    if (!out_irregular.empty()) {
        std::vector<std::uint8_t> end(vertex_count, 0);  // an end of an irregular output edge
        for (const EdgeCount& e : out_irregular) {
            end[e.edge >> 32] = 1;
            end[e.edge & 0xffffffffu] = 1;
        }
        std::vector<EdgeCount> before(out_irregular);
        for (EdgeCount& e : before) e.forward = e.backward = 0;
        for (std::size_t c = 0; c < in.size(); c += 3) {
            for (int k = 0; k < 3; ++k) {
                const Index a = in[c + k], b = in[c + (k + 1) % 3];
                if (!end[a] || !end[b]) continue;
                const EdgeCount key{edge_key(a, b), 0, 0};
                auto it = std::lower_bound(before.begin(), before.end(), key);
                if (it != before.end() && it->edge == key.edge)
                    ++(a < b ? it->forward : it->backward);
            }
        }
        std::vector<std::uint64_t> bad;
        std::fill(end.begin(), end.end(), 0);  // now: an end of a bad edge
        for (std::size_t i = 0; i < out_irregular.size(); ++i) {
            const EdgeCount& e = out_irregular[i];
            if (e.forward != before[i].forward || e.backward != before[i].backward) {
                bad.push_back(e.edge);
                end[e.edge >> 32] = 1;
                end[e.edge & 0xffffffffu] = 1;
            }
        }
        for (std::size_t c = 0; c < out.size() && !bad.empty(); c += 3) {
            for (int k = 0; k < 3; ++k) {
                const Index a = out[c + k], b = out[c + (k + 1) % 3];
                if (end[a] && end[b] &&
                    std::binary_search(bad.begin(), bad.end(), edge_key(a, b))) {
                    defects.insert(defects.end(), {out[c], out[c + 1], out[c + 2]});
                    break;
                }
            }
        }
    }
    const std::vector<Index>& out_fans = stars.fans;
    std::vector<std::uint8_t> suspect(vertex_count, 0);
    bool any = false;
    for (std::size_t v = 0; v < vertex_count; ++v) {
        suspect[v] = out_fans[v] > 1;
        any = any || suspect[v];
    }
    if (any) {
        // The input's stars of the suspects: every triangle at one of them.
        std::vector<Index> in_stars;
        for (std::size_t c = 0; c < in.size(); c += 3) {
            if (suspect[in[c]] || suspect[in[c + 1]] || suspect[in[c + 2]]) {
                in_stars.insert(in_stars.end(), &in[c], &in[c] + 3);
            }
        }
        const std::vector<Index> in_fans = fan_counts(in_stars, vertex_count);
        for (std::size_t v = 0; v < vertex_count; ++v) {
            if (suspect[v] && out_fans[v] > in_fans[v]) defects.push_back(Index(v));
        }
    }
    // A small closed piece can fold flat into two triangles on the same three vertices (every
    // edge used once each way, one fan per vertex), and then vanish.
    const std::vector<std::array<Index, 3>>& out_doubles = stars.doubled;
    if (!out_doubles.empty()) {
        // How often the input has each of them (only its triangles on their vertices looked up).
        std::vector<std::uint8_t> corner(vertex_count, 0);
        for (const auto& t : out_doubles) corner[t[0]] = corner[t[1]] = corner[t[2]] = 1;
        std::vector<Index> uses(out_doubles.size(), 0);
        for (std::size_t c = 0; c < in.size(); c += 3) {
            if (!corner[in[c]] || !corner[in[c + 1]] || !corner[in[c + 2]]) continue;
            std::array<Index, 3> t{in[c], in[c + 1], in[c + 2]};
            std::sort(t.begin(), t.end());
            auto it = std::lower_bound(out_doubles.begin(), out_doubles.end(), t);
            if (it != out_doubles.end() && *it == t) ++uses[std::size_t(it - out_doubles.begin())];
        }
        for (std::size_t i = 0; i < out_doubles.size(); ++i) {
            if (uses[i] < 2)
                defects.insert(defects.end(), out_doubles[i].begin(), out_doubles[i].end());
        }
    }
    // The pieces of the input of which no vertex is left (a piece is labelled by one of its
    // vertices; the input is scanned only when one has gone).
    std::vector<std::uint8_t> alive(vertex_count, 0);
    for (Index v : out) {
        if (in_pieces[v] != kNoPiece) alive[in_pieces[v]] = 1;
    }
    bool gone = false;
    for (std::size_t v = 0; v < vertex_count && !gone; ++v) gone = in_pieces[v] == v && !alive[v];
    for (std::size_t c = 0; gone && c < in.size(); ++c) {
        if (!alive[in_pieces[in[c]]]) defects.push_back(in[c]);
    }
    std::sort(defects.begin(), defects.end());
    defects.erase(std::unique(defects.begin(), defects.end()), defects.end());
    return defects;
}

RegionResult simplify_region(const std::vector<float>& positions, const std::vector<Index>& indices,
                             const std::vector<Index>& context, std::size_t target,
                             double max_error, const std::vector<std::uint8_t>* keep,
                             Simplifier simplifier) {
    const std::size_t nv = positions.size() / 3, triangles = indices.size() / 3;
    RegionResult r;
    if (target >= triangles) {
        r.indices = indices;
        return r;
    }
    if (simplifier == Simplifier::kCollapse) {
        // The kept triangles stay as they are, with the context, and come last.
        std::vector<Index> open, fixed = context, kept;
        for (std::size_t t = 0; t < triangles; ++t) {
            const Index* tri = &indices[3 * t];
            if (keep && (*keep)[t]) {
                fixed.insert(fixed.end(), tri, tri + 3);
                kept.insert(kept.end(), tri, tri + 3);
            } else {
                open.insert(open.end(), tri, tri + 3);
            }
        }
        r.frozen = kept.size() / 3;
        r.attempts = 1;
        r.indices = collapse_edges(positions, open, fixed, target - std::min(target, r.frozen),
                                   max_error, &r.error);
        r.indices.insert(r.indices.end(), kept.begin(), kept.end());
        return r;
    }
    std::vector<std::uint8_t> frozen(triangles, 0);
    std::size_t kept = 0;
    if (keep) {
        for (std::size_t t = 0; t < triangles; ++t) kept += frozen[t] = (*keep)[t] != 0;
    }
    r.frozen = kept;
    const float scale = meshopt_simplifyScale(positions.data(), nv, 3 * sizeof(float));
    const float relative_error = std::isinf(max_error) || !(scale > 0.0f)
                                     ? std::numeric_limits<float>::max()
                                     : static_cast<float>(max_error / scale);
    // The kept triangles count in the target; the rest goes to the ratio that makes it up.
    const double ratio = kept >= triangles
                             ? 1.0
                             : std::clamp((static_cast<double>(target) - double(kept)) /
                                              static_cast<double>(triangles - kept),
                                          0.0, 1.0);
    // Edge of an equilateral triangle of the simplified mesh's mean area: the freezing radius
    // grows by half of it with every attempt.
    const double step = std::sqrt(4.0 / std::sqrt(3.0) * total_area(positions, indices) /
                                  static_cast<double>(std::max<std::size_t>(target, 1)));
    std::vector<Index> checked_in = indices;
    checked_in.insert(checked_in.end(), context.begin(), context.end());
    const std::vector<Index> in_pieces = piece_labels(checked_in, nv);
    // Scratch kept by each thread from region to region (its memory, not its contents).
    thread_local std::vector<Index> free, result;
    if (result.size() < indices.size()) result.resize(indices.size());
    float first_error = 0.0f;
    for (int attempt = 1; attempt <= kMaxRegionAttempts; ++attempt) {
        free.clear();
        for (std::size_t t = 0; t < triangles; ++t) {
            if (!frozen[t]) free.insert(free.end(), &indices[3 * t], &indices[3 * t] + 3);
        }
        // The free part at the region's ratio: frozen triangles come on top of the target
        // rather than making the rest coarser.
        const auto goal = static_cast<std::size_t>(std::round(ratio * double(free.size() / 3)));
        // Retries stop at the first run's error: the frozen outlines lock vertices, and the
        // goal would otherwise be met by coarser collapses elsewhere.
        const float cap = attempt == 1 ? relative_error : std::min(relative_error, first_error);
        float error = 0.0f;
        const std::size_t count =
            free.empty() ? 0
                         : meshopt_simplify(result.data(), free.data(), free.size(),
                                            positions.data(), nv, 3 * sizeof(float), 3 * goal, cap,
                                            meshopt_SimplifyLockBorder, &error);
        if (attempt == 1) first_error = error;
        std::vector<Index> out(result.begin(), result.begin() + count);
        for (std::size_t t = 0; t < triangles; ++t) {
            if (frozen[t]) out.insert(out.end(), &indices[3 * t], &indices[3 * t] + 3);
        }
        r.attempts = attempt;
        r.error = static_cast<double>(error) * scale;
        const std::size_t own = out.size();
        out.insert(out.end(), context.begin(), context.end());
        const std::vector<Index> defects =
            new_defects(checked_in, in_pieces, out, nv, context.size() / 3);
        if (defects.empty()) {
            out.resize(own);
            r.indices = std::move(out);
            return r;
        }
        r.frozen = freeze_around(positions, indices, defects, (attempt - 1) * 0.5 * step, frozen);
    }
    r.gave_up = true;
    r.indices = indices;
    r.frozen = triangles;
    r.error = 0.0;
    return r;
}

}  // namespace fdmsurf::detail
