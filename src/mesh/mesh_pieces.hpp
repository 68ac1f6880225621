// The connected pieces of a mesh (vertices joined through triangles), on several threads; shared
// by the statistics and the cavity removal.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "fdmsurf/mesh.hpp"

namespace fdmsurf::detail {

inline constexpr std::uint32_t kNoPiece = ~std::uint32_t{0};

struct VertexPieces {
    std::vector<std::uint32_t> of_vertex;  // piece of each vertex; kNoPiece when unreferenced
    std::size_t count = 0;
};

// Pieces numbered in the order of their smallest vertex, on `threads` threads (0: all): the
// same numbering for any number of threads. Indices must be in range (validate_mesh).
VertexPieces vertex_pieces(const Mesh& mesh, unsigned threads = 0);

// Fixed-size chunks for the parallel loops over triangles and vertices: the work split (and so
// any floating-point sum taken chunk by chunk) does not depend on the number of threads.
inline constexpr std::size_t kTriangleChunk = std::size_t{1} << 16;
inline constexpr std::size_t kVertexChunk = std::size_t{1} << 14;
inline std::size_t chunk_count(std::size_t count, std::size_t chunk) {
    return (count + chunk - 1) / chunk;
}

}  // namespace fdmsurf::detail
