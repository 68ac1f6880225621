// The connected pieces of a mesh (vertices joined through triangles), on several threads; shared
// by the statistics and the cavity removal.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "base/parallel.hpp"
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

// One chunk's running sums per piece: a new run when the piece is none of the last
// kRecentRuns runs' (the vertices and triangles of one piece mostly come together, and a chunk
// that alternates between a few pieces, as each plane's rows cross every copy of a capsid's
// shell, keeps a run per piece, not one per switch: those runs were 0.1 GB of fresh pages).
// Sums must therefore add the same in any order (counts, FixedSum).
template <class Sum>
struct PieceRun {
    std::uint32_t piece;
    Sum sum;
};
template <class Sum>
using PieceRuns = std::vector<PieceRun<Sum>>;

// The sum of `piece` in a chunk's `runs`: one of the last kRecentRuns runs', or a new run's
// (Sum{}).
inline constexpr std::size_t kRecentRuns = 8;
template <class Sum>
Sum& piece_sum_any_order(PieceRuns<Sum>& runs, std::uint32_t piece) {
    const std::size_t n = runs.size();
    for (std::size_t k = n; k > 0 && k + kRecentRuns > n; --k)
        if (runs[k - 1].piece == piece) return runs[k - 1].sum;
    runs.push_back({piece, Sum{}});
    return runs.back().sum;
}

// Runs chunk(k, runs) for k in [0, chunks) on `threads` threads, each chunk with runs of its own,
// then add(piece, sum) for every run, chunk after chunk: sums taken this way come out the same
// for any number of threads.
template <class Sum, class Chunk, class Add>
void sum_by_piece(std::size_t chunks, unsigned threads, Chunk&& chunk, Add&& add) {
    std::vector<PieceRuns<Sum>> runs(chunks);
    parallel_chunks(chunks, threads, [&](std::size_t k) { chunk(k, runs[k]); });
    for (const PieceRuns<Sum>& of_chunk : runs)
        for (const PieceRun<Sum>& run : of_chunk) add(run.piece, run.sum);
}

}  // namespace fdmsurf::detail
