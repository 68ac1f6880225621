// Half-edges of a triangle mesh grouped into undirected edges (refinement, crease recovery).
#pragma once

#include <cstdint>
#include <vector>

#include "fdmsurf/mesh.hpp"

namespace fdmsurf::detail {

using HalfEdgeIndex = std::uint32_t;
inline constexpr HalfEdgeIndex kNoHalfEdge = ~HalfEdgeIndex{0};

// Half-edge h = 3 t + k runs from corner k of triangle t to corner k + 1.
inline HalfEdgeIndex next_he(HalfEdgeIndex h) { return h % 3 == 2 ? h - 2 : h + 1; }
inline HalfEdgeIndex prev_he(HalfEdgeIndex h) { return h % 3 == 0 ? h + 2 : h - 1; }

enum class EdgeKind : std::uint8_t {
    Interior,  // two triangles, opposite directions: twins
    Boundary,  // one triangle
    Singular,  // more than two triangles, two in the same direction, or a degenerate triangle
};

struct HalfEdges {
    std::vector<HalfEdgeIndex> twin;   // per half-edge: the other half of an Interior edge, else
                                       // kNoHalfEdge
    std::vector<HalfEdgeIndex> edge;   // per half-edge: its undirected edge, shared by all uses
    std::vector<HalfEdgeIndex> first;  // per edge: one of its half-edges (the lowest)
    std::vector<EdgeKind> kind;        // per edge
};

// Half-edges grouped by undirected edge without a hash map: bucketed by their smaller vertex (a
// counting sort), each bucket (a handful) sorted by the larger one. Edge numbers follow
// (smaller, larger) vertex order. The mesh's indices must be below its vertex count.
HalfEdges build_half_edges(const Mesh& mesh);

}  // namespace fdmsurf::detail
