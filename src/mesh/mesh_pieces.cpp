// Connected pieces of a mesh on all threads (mesh_pieces.hpp).
#include "mesh/mesh_pieces.hpp"

#include <algorithm>
#include <atomic>

#include "base/parallel.hpp"
#include "mesh/union_find.hpp"

namespace fdmsurf::detail {

VertexPieces vertex_pieces(const Mesh& mesh, unsigned threads) {
    threads = thread_count(threads);
    const std::size_t n = mesh.vertex_count();
    const auto& idx = mesh.indices;
    ConcurrentSets sets(n);
    std::vector<std::uint8_t> referenced(n, 0);
    parallel_chunks(chunk_count(mesh.triangle_count(), kTriangleChunk), threads, [&](std::size_t k) {
        const std::size_t end = std::min(idx.size(), (k + 1) * 3 * kTriangleChunk);
        for (std::size_t c = k * 3 * kTriangleChunk; c < end; c += 3) {
            sets.unite(idx[c], idx[c + 1]);
            sets.unite(idx[c], idx[c + 2]);
            for (int j = 0; j < 3; ++j)
                std::atomic_ref<std::uint8_t>(referenced[idx[c + j]]).store(1, std::memory_order_relaxed);
        }
    });
    VertexPieces pieces;
    pieces.of_vertex.assign(n, kNoPiece);
    parallel_chunks(chunk_count(n, kVertexChunk), threads, [&](std::size_t k) {
        const std::size_t end = std::min(n, (k + 1) * kVertexChunk);
        for (std::size_t v = k * kVertexChunk; v < end; ++v)
            if (referenced[v]) pieces.of_vertex[v] = sets.find(std::uint32_t(v));
    });
    // Roots are smallest members, so a root is met before the rest of its set.
    for (std::uint32_t v = 0; v < n; ++v) {
        const std::uint32_t root = pieces.of_vertex[v];
        if (root == kNoPiece) continue;
        pieces.of_vertex[v] = root == v ? std::uint32_t(pieces.count++) : pieces.of_vertex[root];
    }
    return pieces;
}

}  // namespace fdmsurf::detail
