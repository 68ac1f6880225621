// The pieces of a mesh and each piece's statistics (mesh_stats.cpp), found once for the cavity
// removal and the statistics together, and kept up to date when pieces are removed; and
// compute_stats with a chosen number of threads, for the tests that check the figures do not
// depend on it (compute_stats uses all of the machine's threads).
#pragma once

#include <cstdint>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "mesh/mesh_pieces.hpp"

namespace fdmsurf::detail {

// A run of triangles of one piece within one chunk of kTriangleChunk triangles, in triangle
// order: the pieces' sums are taken run by run, so the runs also say where each piece's
// triangles lie.
struct TriangleRun {
    std::uint32_t piece;
    std::uint32_t triangles;
};

struct MeshAnalysis {
    VertexPieces pieces;
    // Each piece's statistics, in piece order (as piece_stats gives them, before its sort):
    // triangles and volume (the cavity test's signed volume) always; with `topology` (the
    // statistics) also vertices (referenced ones), area, degenerate triangles and the edge and
    // vertex checks (closed_pieces, boundary, non-manifold and inconsistent edges, non-manifold
    // vertices, Euler characteristic), zero without.
    std::vector<MeshStats> stats;
    bool topology = false;
    std::vector<TriangleRun> runs;  // every chunk's runs, chunk after chunk
};

// The analysis of `mesh` on `threads` threads (0: all), the same for any number: the pieces
// (with `topology`, from a pass over each vertex's corners that also checks its edges and fans),
// then one pass over the triangles for their sums. Throws Error(InvalidArgument) naming `who` on
// a malformed mesh (validate_mesh).
MeshAnalysis analyse_mesh(const Mesh& mesh, bool topology, const char* who, unsigned threads = 0);

// Removes the pieces q with drop[q] of `analysis` (of `mesh`): their triangles and vertices
// (unreferenced vertices stay), keeping the order of the rest, on all threads. With `update`
// the analysis is brought up to date: the kept pieces renumbered in order, their statistics
// kept (their sums do not depend on where their triangles lie, so they are analyse_mesh's on
// the mesh after, bit for bit) and the runs found again; without, it no longer describes the
// mesh. The per-vertex arrays must have their sizes (validate_attributes).
void keep_pieces(Mesh& mesh, MeshAnalysis& analysis, const std::vector<char>& drop, bool update);
// The same, plainly: the kept vertices and triangles copied one by one, and (`update`) the
// analysis found again on the mesh after. The reference of keep_pieces' tests.
void keep_pieces_plain(Mesh& mesh, MeshAnalysis& analysis, const std::vector<char>& drop,
                       bool update);

// The statistics of the whole mesh from its analysis (with topology): compute_stats, bit for bit.
MeshStats total_stats(const MeshAnalysis& analysis, const Mesh& mesh);

// compute_stats on `threads` threads (0: the machine's).
MeshStats total_stats(const Mesh& mesh, unsigned threads);

}  // namespace fdmsurf::detail
