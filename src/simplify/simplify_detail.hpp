// Internals of simplify_mesh, exposed for the tests: the target, exact welding, the guarded
// simplification of one region, and the passes over cells that run regions in parallel.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/simplify.hpp"
#include "mesh/mesh_pieces.hpp"

namespace fdmsurf::detail {

// The triangle count simplify_mesh aims at for an input of `triangles`: round(ratio ·
// triangles), at least 1 (0 for an empty mesh), capped at max_triangles when that is set. Throws
// Error(InvalidArgument) for a ratio outside (0, 1] or a max_error that is negative or NaN.
std::size_t simplify_target(std::size_t triangles, const SimplifyOptions& options);

// Vertices at bit-identical positions merged into the lowest-numbered one (its attributes
// kept), triangles that merging collapses (or that repeat a vertex) dropped, unused vertices
// dropped; the rest in order, into `welded`. Returns false, leaving `welded` alone, when no
// two vertices share a position and no triangle repeats a vertex (unused vertices are then
// left in: simplify_mesh drops them at the end anyway). `merged` (may be null) gets the number
// of vertices merged into another.
bool weld_exact(const Mesh& mesh, Mesh& welded, std::size_t* merged);

// The Hausdorff distance and the area-weighted RMSD (Å) of compare_meshes(full, simplified)
// for a simplified mesh whose vertices are vertices of `full` (simplified's vertex i is full's
// vertex kept[i]): the distances from full's vertices to simplified's triangles (the other way
// they are 0; so are those of the kept vertices, which are not queried).
void measure_distance(const Mesh& full, const Mesh& simplified,
                      const std::vector<std::uint32_t>& kept, double& hausdorff, double& rmsd);

// False when `out` has other pieces or another Euler characteristic than `in`, more boundary,
// non-manifold or inconsistently oriented edges, non-manifold vertices or degenerate triangles,
// or lost its positive volume.
bool topology_kept(const MeshStats& in, const MeshStats& out);

// The vertices around the topological defects that `out` has and `in` has not (both index
// triangles into the same `vertex_count` vertices): both ends of, and the third corner of every
// triangle on, an edge whose uses (count in each direction) differ from the input's and are
// not one each way; the vertices whose triangles form more fans than in `in`; the corners of
// two triangles on the same three vertices (a piece folded flat); and every vertex of a piece
// of `in` that has no vertex left in `out`. Sorted, unique; empty when `out` kept the input's
// topology everywhere.
std::vector<std::uint32_t> new_defects(const std::vector<std::uint32_t>& in,
                                       const std::vector<std::uint32_t>& out,
                                       std::size_t vertex_count);
// The same with `in_pieces` = piece_labels(in, vertex_count), for callers that check several
// outputs against one input. When the last `context` triangles of `in` and of `out` are the
// same triangles (kept as they were), a vertex that only those use in both keeps the input's
// edges and fans and is not examined.
std::vector<std::uint32_t> new_defects(const std::vector<std::uint32_t>& in,
                                       const std::vector<std::uint32_t>& in_pieces,
                                       const std::vector<std::uint32_t>& out,
                                       std::size_t vertex_count, std::size_t context = 0);
// Per vertex, a label shared by the vertices of one piece of `indices` (joined through
// triangles): one of the piece's vertices; kNoPiece (mesh/mesh_pieces.hpp) for vertices no
// triangle uses.
std::vector<std::uint32_t> piece_labels(const std::vector<std::uint32_t>& indices,
                                        std::size_t vertex_count);

// Half-edge collapses of `indices` (into `positions`: 3 floats per vertex, Å) in order of
// quadric error towards `target` triangles, each tested for the link condition and for
// triangles turned over, so that the result has the input's topology: no collapse pinches a
// neck, folds a piece flat or turns a triangle by more than 75 degrees. Only vertices inside the
// surface (one closed fan) move, into a neighbour that is inside or on a border with one open
// fan: borders and non-manifold vertices stay. Stops at the target, when no valid collapse is
// left, or before a collapse whose error (root of the quadric error over its area) exceeds
// `max_error` (Å; infinity for none). `error` (may be null): the largest error of a collapse
// made, Å. Returns the triangles left, in input order, with their vertices moved.
std::vector<std::uint32_t> collapse_edges(const std::vector<float>& positions,
                                          const std::vector<std::uint32_t>& indices,
                                          const std::vector<std::uint32_t>& fixed,
                                          std::size_t target, double max_error, double* error);

struct RegionResult {
    std::vector<std::uint32_t> indices;  // the simplified region, into the region's vertices
    double error = 0.0;                  // the simplifier's estimate, Å
    std::size_t frozen = 0;              // input triangles kept as they were for the topology
    int attempts = 0;                    // simplifier runs
    bool gave_up = false;                // defects remained: the region was kept whole
};

// One region (positions: 3 floats per vertex, Å; indices: 3 per triangle) simplified towards
// `target` triangles. With Simplifier::kCollapse by collapse_edges, with `context` and the kept
// triangles fixed (one run, no guard needed). With kMeshopt by meshopt_simplify with its border
// locked, then checked by new_defects together with `context`, triangles around the region
// that stay as they are (their corners are locked as the region's border, and they are checked
// with it, not returned). While a run
// leaves a defect, the input triangles within a growing distance of the defects are frozen
// (kept as they are) and the rest simplified again at the same ratio; after kMaxRegionAttempts
// runs the region is kept whole. `max_error`: Å, infinity for none. `keep` (may be null; one
// flag per triangle): triangles frozen from the first run on, counted in `target`. The frozen
// triangles are the last `frozen` of the result.
inline constexpr int kMaxRegionAttempts = 8;
RegionResult simplify_region(const std::vector<float>& positions,
                             const std::vector<std::uint32_t>& indices,
                             const std::vector<std::uint32_t>& context, std::size_t target,
                             double max_error, const std::vector<std::uint8_t>* keep = nullptr,
                             Simplifier simplifier = Simplifier::kCollapse);

struct CellPassStats {
    std::size_t regions = 0;  // regions (cells) run, over both passes
    std::size_t frozen = 0;   // triangles of the result kept as they were for the topology
    std::size_t gave_up = 0;  // regions kept whole
    int attempts = 0;         // simplifier runs, over all regions
    double error = 0.0;       // the largest estimate of each pass, summed over passes (Å)
};

// Triangles per cell the passes aim at; meshes up to twice this are one region.
inline constexpr std::size_t kCellTriangles = 32768;

// Simplifies `indices` (into `positions`) towards `target` triangles: a mesh of up to
// 2 kCellTriangles triangles as one region; a larger one in two or more passes over grids of
// cubic cells, in parallel on `threads` threads (0: all). In each pass the triangles at a vertex
// shared by two cells (the band along the cell faces) stay as they are and are every adjacent
// cell's context, so that no two cells share a vertex they may move or an edge they may
// create: defects cannot arise between cells. The first pass's cells hold about
// kCellTriangles triangles each and go to the ratio, leaving their band and the triangles at
// their locked outline (fans: with kCollapse only the fan's corners on the band stay) for the
// second; the second pass's cells are twice as wide, its faces half a first cell away from the
// first's, and all its cells go to the one ratio that meets the target. With kCollapse, while
// the count is more than 2% above the target, up to two more passes over cells twice as wide
// each time. Returns the indices into `positions`; the same whatever the thread count.
std::vector<std::uint32_t> simplify_in_cells(const std::vector<float>& positions,
                                             const std::vector<std::uint32_t>& indices,
                                             std::size_t target, double max_error, unsigned threads,
                                             CellPassStats* stats,
                                             Simplifier simplifier = Simplifier::kCollapse);

}  // namespace fdmsurf::detail
