// Mesh statistics: area, signed volume, connected pieces, and the edge and vertex topology checks,
// on all of the machine's threads (the sums are taken in a fixed order: the same figures for any
// number of threads).
#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <memory>
#include <numeric>
#include <vector>

#include "base/parallel.hpp"
#include "base/trace.hpp"
#include "fdmsurf/mesh.hpp"
#include "mesh/mesh_pieces.hpp"
#include "mesh/mesh_stats_detail.hpp"
#include "mesh/mesh_validate.hpp"

namespace fdmsurf {
namespace detail {
namespace {

using Index = std::uint32_t;

bool is_degenerate(const Index* t) { return t[0] == t[1] || t[1] == t[2] || t[2] == t[0]; }

std::array<double, 3> position(const Mesh& mesh, Index v) {
    const float* p = &mesh.positions[3 * std::size_t{v}];
    return {p[0], p[1], p[2]};
}

// The corners at each vertex of the triangles that are not degenerate: ends[start[v],
// start[v + 1]), in triangle order, each the corner's next and previous vertex (the triangle
// runs v -> next -> prev), so that the edges around a vertex are read in one run, not gathered
// from the triangles. Each thread owns a range of vertices and reads all triangles in order,
// counting and placing only its own corners: no atomic operations, which would stall on every
// cache miss of this scattered access.
struct CornerEnds {
    Index next, prev;
};
struct VertexCorners {
    std::vector<Index> start;
    std::unique_ptr<CornerEnds[]> ends;  // filled below, so not zeroed first
};

VertexCorners corners_by_vertex(const std::vector<Index>& idx, std::size_t n, unsigned threads) {
    VertexCorners vc;
    vc.start.assign(n + 1, 0);
    const std::size_t triangles = idx.size() / 3;
    const std::size_t parts = std::max<std::size_t>(1, std::min<std::size_t>(threads, n / 4096));
    const auto range = [&](std::size_t part) { return part * n / parts; };
    parallel_chunks(parts, threads, [&](std::size_t part) {
        const Index lo = Index(range(part)), hi = Index(range(part + 1));
        Index* count = vc.start.data() + 1;
        for (std::size_t t = 0; t < triangles; ++t) {
            const Index* tri = &idx[3 * t];
            if (is_degenerate(tri)) continue;
            for (int k = 0; k < 3; ++k)
                if (tri[k] >= lo && tri[k] < hi) ++count[tri[k]];
        }
    });
    for (std::size_t v = 1; v <= n; ++v) vc.start[v] += vc.start[v - 1];
    vc.ends.reset(new CornerEnds[vc.start[n]]);
    parallel_chunks(parts, threads, [&](std::size_t part) {
        const Index lo = Index(range(part)), hi = Index(range(part + 1));
        std::vector<Index> cursor(vc.start.begin() + lo, vc.start.begin() + hi);
        for (std::size_t t = 0; t < triangles; ++t) {
            const Index* tri = &idx[3 * t];
            if (is_degenerate(tri)) continue;
            for (int k = 0; k < 3; ++k)
                if (tri[k] >= lo && tri[k] < hi)
                    vc.ends[cursor[tri[k] - lo]++] = {tri[(k + 1) % 3], tri[(k + 2) % 3]};
        }
    });
    return vc;
}

using Pieces = VertexPieces;
constexpr Index no_piece = kNoPiece;

// One chunk's contribution to one piece (sum_by_piece adds them up in chunk order).
struct Partial {
    MeshStats stats;
    long edges = 0;
    long faces = 0;  // non-degenerate triangles
};
using Runs = PieceRuns<Partial>;

// Area, signed volume and triangle counts of the triangles in chunk k.
void triangle_chunk(const Mesh& mesh, const Pieces& pieces, std::size_t k, Runs& runs) {
    const auto& idx = mesh.indices;
    const std::size_t end = std::min(idx.size(), (k + 1) * 3 * kTriangleChunk);
    for (std::size_t c = k * 3 * kTriangleChunk; c < end; c += 3) {
        Partial& part = piece_sum(runs, pieces.of_vertex[idx[c]]);
        MeshStats& s = part.stats;
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
            ++part.faces;
        }
    }
}

// One use of an edge {v, other} by the triangle whose corner at v is `corner` (local number).
struct LocalUse {
    Index other;
    Index corner;
    bool forward;  // the triangle runs v -> other
};

// Whether the corners at v form one closed fan: each corner's next vertex is the previous
// vertex of exactly one other corner, and following that link visits every corner once. Then
// each edge at v is used by two triangles in opposite directions and the corners make one fan,
// which is what the general count below would find. At most 16 corners; otherwise false.
bool closed_fan(const VertexCorners& vc, std::size_t v) {
    const Index first = vc.start[v], count = vc.start[v + 1] - first;
    if (count < 3 || count > 16) return false;
    const CornerEnds* e = &vc.ends[first];
    std::uint8_t link[16];
    std::uint32_t taken = 0;
    for (Index i = 0; i < count; ++i) {
        int match = -1;
        for (Index j = 0; j < count; ++j) {
            if (e[j].prev != e[i].next) continue;
            if (match >= 0) return false;  // two corners end where this one starts
            match = int(j);
        }
        if (match < 0 || (taken >> match & 1u)) return false;
        taken |= 1u << match;
        link[i] = std::uint8_t(match);
    }
    Index at = 0, steps = 0;
    do {
        at = link[at];
        ++steps;
    } while (at != 0 && steps <= count);
    return at == 0 && steps == count;
}

// The edges and fans around the vertices of chunk k. Each edge {v, w} is seen from both ends
// and counted at its smaller end v; the corners at v that share an edge form one fan, and more
// than one fan makes v a non-manifold vertex.
void vertex_chunk(const Mesh& mesh, const Pieces& pieces, const VertexCorners& vc, std::size_t k,
                  Runs& runs) {
    const std::size_t n = mesh.vertex_count();
    std::vector<LocalUse> uses;
    std::vector<Index> parent;
    const auto find = [&](Index x) {
        while (parent[x] != x) x = parent[x] = parent[parent[x]];
        return x;
    };
    const std::size_t end = std::min(n, (k + 1) * kVertexChunk);
    for (std::size_t v = k * kVertexChunk; v < end; ++v) {
        if (pieces.of_vertex[v] == no_piece) continue;
        Partial& part = piece_sum(runs, pieces.of_vertex[v]);
        MeshStats& s = part.stats;
        ++s.vertices;
        if (closed_fan(vc, v)) {  // the usual vertex: every edge used twice, one way each
            for (Index i = vc.start[v]; i < vc.start[v + 1]; ++i)
                part.edges += vc.ends[i].next > v ? 1 : 0;
            continue;
        }
        uses.clear();
        Index local = 0;
        for (Index i = vc.start[v]; i < vc.start[v + 1]; ++i) {
            uses.push_back({vc.ends[i].next, local, true});
            uses.push_back({vc.ends[i].prev, local, false});
            ++local;
        }
        // By the other end (a dozen uses at a vertex of a closed mesh: an insertion sort, a
        // full sort for a crowded vertex; the order within a group does not matter below).
        if (uses.size() > 32)
            std::sort(uses.begin(), uses.end(),
                      [](const LocalUse& x, const LocalUse& y) { return x.other < y.other; });
        for (std::size_t i = 1; i < uses.size(); ++i) {
            const LocalUse u = uses[i];
            std::size_t j = i;
            for (; j > 0 && uses[j - 1].other > u.other; --j) uses[j] = uses[j - 1];
            uses[j] = u;
        }
        parent.resize(local);
        std::iota(parent.begin(), parent.end(), Index{0});
        Index fans = local;
        for (std::size_t g = 0; g < uses.size();) {
            std::size_t e = g + 1;
            while (e < uses.size() && uses[e].other == uses[g].other) ++e;
            if (uses[g].other > v) {
                ++part.edges;
                if (e - g == 1) {
                    ++s.boundary_edges;
                } else if (e - g == 2) {
                    if (uses[g].forward == uses[g + 1].forward) ++s.inconsistent_edges;
                } else {
                    ++s.nonmanifold_edges;
                }
            }
            for (std::size_t u = g + 1; u < e; ++u) {
                const Index a = find(uses[g].corner), b = find(uses[u].corner);
                if (a != b) {
                    parent[std::max(a, b)] = std::min(a, b);
                    --fans;
                }
            }
            g = e;
        }
        if (fans > 1) ++s.nonmanifold_vertices;
    }
}

// Statistics of every piece, in piece order; `vertices` counts referenced vertices only.
std::vector<MeshStats> analyse_pieces(const Mesh& mesh, unsigned requested_threads) {
    // Normals play no part in the statistics, so they are not checked.
    validate_mesh(mesh, "mesh statistics", false);
    const unsigned threads = thread_count(requested_threads);
    trace("mesh statistics: checked");
    const VertexCorners vc = corners_by_vertex(mesh.indices, mesh.vertex_count(), threads);
    trace("mesh statistics: corners by vertex");
    const Pieces pieces = vertex_pieces(mesh, threads);
    trace("mesh statistics: pieces");

    const std::size_t triangle_chunks = chunk_count(mesh.triangle_count(), kTriangleChunk);
    const std::size_t vertex_chunks = chunk_count(mesh.vertex_count(), kVertexChunk);
    std::vector<MeshStats> stats(pieces.count);
    std::vector<long> edge_count(pieces.count, 0);
    std::vector<long> face_count(pieces.count, 0);
    const auto add = [&](Index piece, const Partial& part) {
        MeshStats& s = stats[piece];
        const MeshStats& q = part.stats;
        s.vertices += q.vertices;
        s.triangles += q.triangles;
        s.area += q.area;
        s.volume += q.volume;
        s.boundary_edges += q.boundary_edges;
        s.nonmanifold_edges += q.nonmanifold_edges;
        s.nonmanifold_vertices += q.nonmanifold_vertices;
        s.inconsistent_edges += q.inconsistent_edges;
        s.degenerate_triangles += q.degenerate_triangles;
        edge_count[piece] += part.edges;
        face_count[piece] += part.faces;
    };
    // The triangles' sums, then the vertices' counts (integers: their order does not matter).
    sum_by_piece<Partial>(
        triangle_chunks, threads,
        [&](std::size_t k, Runs& runs) { triangle_chunk(mesh, pieces, k, runs); }, add);
    trace("mesh statistics: triangles");
    sum_by_piece<Partial>(
        vertex_chunks, threads,
        [&](std::size_t k, Runs& runs) { vertex_chunk(mesh, pieces, vc, k, runs); }, add);
    trace("mesh statistics: vertices");
    for (std::size_t p = 0; p < stats.size(); ++p) {
        MeshStats& s = stats[p];
        s.pieces = 1;
        s.closed_pieces = s.boundary_edges == 0 && s.nonmanifold_edges == 0 ? 1 : 0;
        s.euler_characteristic = long(s.vertices) - edge_count[p] + face_count[p];
    }
    return stats;
}

}  // namespace

MeshStats total_stats(const Mesh& mesh, unsigned threads) {
    MeshStats total;
    for (const MeshStats& s : analyse_pieces(mesh, threads)) {
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

}  // namespace detail

bool MeshStats::is_closed_manifold() const {
    return boundary_edges == 0 && nonmanifold_edges == 0 && nonmanifold_vertices == 0 &&
           inconsistent_edges == 0 && degenerate_triangles == 0 && volume > 0.0;
}

MeshStats compute_stats(const Mesh& mesh) { return detail::total_stats(mesh, 0); }

std::vector<MeshStats> piece_stats(const Mesh& mesh) {
    std::vector<MeshStats> pieces = detail::analyse_pieces(mesh, 0);
    std::stable_sort(pieces.begin(), pieces.end(),
                     [](const MeshStats& a, const MeshStats& b) { return a.area > b.area; });
    return pieces;
}

}  // namespace fdmsurf
