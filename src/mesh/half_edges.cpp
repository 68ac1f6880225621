// Half-edges grouped into undirected edges by a counting sort on the smaller vertex.
#include "mesh/half_edges.hpp"

#include <algorithm>

namespace fdmsurf::detail {

namespace {

bool degenerate_triangle(const std::vector<HalfEdgeIndex>& idx, HalfEdgeIndex h) {
    const HalfEdgeIndex* t = &idx[h - h % 3];
    return t[0] == t[1] || t[1] == t[2] || t[2] == t[0];
}

}  // namespace

HalfEdges build_half_edges(const Mesh& mesh) {
    using Index = HalfEdgeIndex;
    const std::vector<Index>& idx = mesh.indices;
    const std::size_t nv = mesh.vertex_count(), nh = idx.size();
    auto lo = [&](Index h) { return std::min(idx[h], idx[next_he(h)]); };
    auto hi = [&](Index h) { return std::max(idx[h], idx[next_he(h)]); };
    std::vector<Index> start(nv + 1, 0);
    for (Index h = 0; h < nh; ++h) ++start[lo(h) + 1];
    for (std::size_t v = 0; v < nv; ++v) start[v + 1] += start[v];
    std::vector<Index> order(nh);
    {
        std::vector<Index> fill(start.begin(), start.end() - 1);
        for (Index h = 0; h < nh; ++h) order[fill[lo(h)]++] = h;
    }
    HalfEdges he;
    he.twin.assign(nh, kNoHalfEdge);
    he.edge.assign(nh, kNoHalfEdge);
    he.first.reserve(nh / 2 + 16);
    he.kind.reserve(nh / 2 + 16);
    for (std::size_t v = 0; v < nv; ++v) {
        const auto b = order.begin() + start[v], e = order.begin() + start[v + 1];
        std::sort(b, e, [&](Index x, Index y) { return hi(x) != hi(y) ? hi(x) < hi(y) : x < y; });
        for (auto g = b; g != e;) {
            auto g_end = g + 1;
            while (g_end != e && hi(*g_end) == hi(*g)) ++g_end;
            const Index id = Index(he.first.size());
            bool degenerate = false;
            for (auto x = g; x != g_end; ++x) {
                he.edge[*x] = id;
                degenerate = degenerate || degenerate_triangle(idx, *x);
            }
            EdgeKind kind = EdgeKind::Singular;
            if (!degenerate && g_end - g == 1) {
                kind = EdgeKind::Boundary;
            } else if (!degenerate && g_end - g == 2 && idx[g[0]] != idx[g[1]]) {
                kind = EdgeKind::Interior;
                he.twin[g[0]] = g[1];
                he.twin[g[1]] = g[0];
            }
            he.first.push_back(*g);
            he.kind.push_back(kind);
            g = g_end;
        }
    }
    return he;
}

}  // namespace fdmsurf::detail
