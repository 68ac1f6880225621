// Mesh statistics: area, signed volume, connected pieces, and the edge and vertex topology checks.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "mesh/mesh_validate.hpp"
#include "mesh/union_find.hpp"

namespace fdmsurf {
namespace detail {
namespace {

using Index = std::uint32_t;

// One triangle's use of an undirected edge {lo, hi}, lo < hi. Uses are bucketed by lo (a
// counting sort, linear time) and sorted by hi inside each bucket, which is short.
struct EdgeUse {
    Index hi;
    Index corner_lo;  // 3 t + k: the triangle's corner at lo
    bool forward;     // the triangle runs lo -> hi
};

Index next_corner(Index c) { return c % 3 == 2 ? c - 2 : c + 1; }
Index prev_corner(Index c) { return c % 3 == 0 ? c + 2 : c - 1; }
Index corner_hi(const EdgeUse& u) {
    return u.forward ? next_corner(u.corner_lo) : prev_corner(u.corner_lo);
}

bool is_degenerate(const Index* t) { return t[0] == t[1] || t[1] == t[2] || t[2] == t[0]; }

std::array<double, 3> position(const Mesh& mesh, Index v) {
    const float* p = &mesh.positions[3 * std::size_t{v}];
    return {p[0], p[1], p[2]};
}

// Piece number of every vertex, numbered by smallest vertex; unreferenced vertices get none.
struct Pieces {
    std::vector<Index> of_vertex;
    std::size_t count = 0;
};

constexpr Index no_piece = ~Index{0};

Pieces find_pieces(const Mesh& mesh) {
    const std::size_t n = mesh.vertex_count();
    DisjointSets sets(n);
    std::vector<bool> referenced(n, false);
    for (std::size_t c = 0; c < mesh.indices.size(); c += 3) {
        const Index* t = &mesh.indices[c];
        sets.unite(t[0], t[1]);
        sets.unite(t[0], t[2]);
        referenced[t[0]] = referenced[t[1]] = referenced[t[2]] = true;
    }
    Pieces pieces;
    pieces.of_vertex.assign(n, no_piece);
    // Roots are smallest members, so a root is met before the rest of its set.
    for (Index v = 0; v < n; ++v) {
        if (!referenced[v]) continue;
        const Index root = sets.find(v);
        pieces.of_vertex[v] = root == v ? Index(pieces.count++) : pieces.of_vertex[root];
    }
    return pieces;
}

// Edge uses of the non-degenerate triangles, grouped by edge: bucket lo is
// uses[start[lo], start[lo + 1]), sorted by hi.
struct EdgeTable {
    std::vector<Index> start;
    std::vector<EdgeUse> uses;
};

EdgeTable build_edges(const Mesh& mesh) {
    const std::size_t n = mesh.vertex_count();
    EdgeTable table;
    table.start.assign(n + 1, 0);
    const auto& idx = mesh.indices;
    for (std::size_t c = 0; c < idx.size(); c += 3) {
        if (is_degenerate(&idx[c])) continue;
        for (std::size_t k = 0; k < 3; ++k) {
            ++table.start[std::min(idx[c + k], idx[c + (k + 1) % 3])];
        }
    }
    // Inclusive prefix sums give each bucket's end; filling backwards leaves its start.
    for (std::size_t v = 1; v <= n; ++v) table.start[v] += table.start[v - 1];
    table.uses.resize(table.start[n]);
    for (std::size_t c = 0; c < idx.size(); c += 3) {
        if (is_degenerate(&idx[c])) continue;
        for (std::size_t k = 0; k < 3; ++k) {
            const Index a = idx[c + k];
            const Index b = idx[c + (k + 1) % 3];
            const auto corner_a = Index(c + k);
            const auto corner_b = Index(c + (k + 1) % 3);
            const EdgeUse use = a < b ? EdgeUse{b, corner_a, true} : EdgeUse{a, corner_b, false};
            table.uses[--table.start[std::min(a, b)]] = use;
        }
    }
    for (std::size_t v = 0; v < n; ++v) {
        std::sort(table.uses.begin() + table.start[v], table.uses.begin() + table.start[v + 1],
                  [](const EdgeUse& x, const EdgeUse& y) { return x.hi < y.hi; });
    }
    return table;
}

// Statistics of every piece, in piece order; `vertices` counts referenced vertices only.
std::vector<MeshStats> analyse_pieces(const Mesh& mesh) {
    // Normals play no part in the statistics, so they are not checked.
    validate_mesh(mesh, "mesh statistics", false);
    const auto& idx = mesh.indices;
    const Pieces pieces = find_pieces(mesh);
    std::vector<MeshStats> stats(pieces.count);
    std::vector<long> edge_count(pieces.count, 0);
    std::vector<long> face_count(pieces.count, 0);  // non-degenerate triangles

    for (Index v = 0; v < mesh.vertex_count(); ++v) {
        if (pieces.of_vertex[v] != no_piece) ++stats[pieces.of_vertex[v]].vertices;
    }
    for (std::size_t c = 0; c < idx.size(); c += 3) {
        const Index p = pieces.of_vertex[idx[c]];
        MeshStats& s = stats[p];
        const auto a = position(mesh, idx[c]);
        const auto b = position(mesh, idx[c + 1]);
        const auto d = position(mesh, idx[c + 2]);
        const std::array<double, 3> u{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
        const std::array<double, 3> w{d[0] - a[0], d[1] - a[1], d[2] - a[2]};
        const std::array<double, 3> cr{u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2],
                                       u[0] * w[1] - u[1] * w[0]};
        ++s.triangles;
        s.area += 0.5 * std::sqrt(cr[0] * cr[0] + cr[1] * cr[1] + cr[2] * cr[2]);
        s.volume += (a[0] * (b[1] * d[2] - b[2] * d[1]) + a[1] * (b[2] * d[0] - b[0] * d[2]) +
                     a[2] * (b[0] * d[1] - b[1] * d[0])) /
                    6.0;
        if (is_degenerate(&idx[c])) {
            ++s.degenerate_triangles;
        } else {
            ++face_count[p];
        }
    }

    // Corners joined through the edges at their vertex: each set is one fan of triangles.
    DisjointSets fans(idx.size());
    const EdgeTable edges = build_edges(mesh);
    for (Index lo = 0; lo < mesh.vertex_count(); ++lo) {
        const auto first = edges.uses.begin() + edges.start[lo];
        const auto last = edges.uses.begin() + edges.start[lo + 1];
        for (auto g = first; g != last;) {
            auto e = g + 1;
            while (e != last && e->hi == g->hi) ++e;
            const Index p = pieces.of_vertex[lo];
            ++edge_count[p];
            const auto uses = e - g;
            if (uses == 1) {
                ++stats[p].boundary_edges;
            } else if (uses == 2) {
                if (g[0].forward == g[1].forward) ++stats[p].inconsistent_edges;
            } else {
                ++stats[p].nonmanifold_edges;
            }
            for (auto u = g + 1; u != e; ++u) {
                fans.unite(g->corner_lo, u->corner_lo);
                fans.unite(corner_hi(*g), corner_hi(*u));
            }
            g = e;
        }
    }
    // Fan count per vertex, saturated at 2: more than one fan is a non-manifold vertex.
    std::vector<std::uint8_t> fan_count(mesh.vertex_count(), 0);
    for (Index c = 0; c < idx.size(); ++c) {
        if (is_degenerate(&idx[c - c % 3])) continue;
        if (fans.find(c) == c && fan_count[idx[c]] < 2) ++fan_count[idx[c]];
    }
    for (Index v = 0; v < mesh.vertex_count(); ++v) {
        if (fan_count[v] > 1) ++stats[pieces.of_vertex[v]].nonmanifold_vertices;
    }

    for (std::size_t p = 0; p < stats.size(); ++p) {
        MeshStats& s = stats[p];
        s.pieces = 1;
        s.closed_pieces = s.boundary_edges == 0 && s.nonmanifold_edges == 0 ? 1 : 0;
        s.euler_characteristic = long(s.vertices) - edge_count[p] + face_count[p];
    }
    return stats;
}

}  // namespace
}  // namespace detail

bool MeshStats::is_closed_manifold() const {
    return boundary_edges == 0 && nonmanifold_edges == 0 && nonmanifold_vertices == 0 &&
           inconsistent_edges == 0 && degenerate_triangles == 0 && volume > 0.0;
}

MeshStats compute_stats(const Mesh& mesh) {
    MeshStats total;
    for (const MeshStats& s : detail::analyse_pieces(mesh)) {
        total.area += s.area;
        total.volume += s.volume;
        total.pieces += s.pieces;
        total.closed_pieces += s.closed_pieces;
        total.boundary_edges += s.boundary_edges;
        total.nonmanifold_edges += s.nonmanifold_edges;
        total.nonmanifold_vertices += s.nonmanifold_vertices;
        total.inconsistent_edges += s.inconsistent_edges;
        total.degenerate_triangles += s.degenerate_triangles;
        total.euler_characteristic += s.euler_characteristic;
    }
    // All vertices, referenced or not; the Euler characteristic above counts referenced ones.
    total.vertices = mesh.vertex_count();
    total.triangles = mesh.triangle_count();
    return total;
}

std::vector<MeshStats> piece_stats(const Mesh& mesh) {
    std::vector<MeshStats> pieces = detail::analyse_pieces(mesh);
    std::stable_sort(pieces.begin(), pieces.end(),
                     [](const MeshStats& a, const MeshStats& b) { return a.area > b.area; });
    return pieces;
}

}  // namespace fdmsurf
