// Fewer triangles, and an order GPUs draw faster: mesh simplification (fdmsurf's own edge
// collapses or meshoptimizer's) and reordering through meshoptimizer (docs/mesh.md,
// "Simplification ... and reordering").
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/surface.hpp"

namespace fdmsurf {

// How the collapses are chosen (docs/mesh.md, "Simplification").
enum class Simplifier {
    // fdmsurf's own half-edge collapses in quadric-error order, each tested for the link
    // condition: the result has the input's topology (pieces, genus, no new non-manifold edge
    // or vertex) by construction.
    kCollapse,
    // meshoptimizer's meshopt_simplify, with a guard that finds the non-manifold edges and
    // vertices its collapses leave and simplifies again with the input kept around them.
    kMeshopt,
};

// "collapse" or "meshopt", as --simplifier spells them.
const char* to_string(Simplifier simplifier) noexcept;

struct SimplifyOptions {
    // Fraction of the triangles to keep, in (0, 1]; 1 keeps them all.
    double ratio = 1.0;
    // At most this many triangles (0: no cap). With ratio < 1 as well, the smaller target wins.
    std::size_t max_triangles = 0;
    // Largest deviation the simplifier may introduce, Å, by its own estimate (the root of the
    // collapsed vertex's mean squared distance to its planes; infinity: none, the target
    // decides). A finite bound can stop the simplifier above the target.
    double max_error = std::numeric_limits<double>::infinity();
    Simplifier simplifier = Simplifier::kCollapse;
    // Measure the Hausdorff distance and the RMSD to the input mesh (compare_meshes).
    bool measure_distance = true;
};

struct SimplifyReport {
    std::size_t triangles_in = 0, vertices_in = 0;    // after welding
    std::size_t target_triangles = 0;                 // from ratio and max_triangles
    std::size_t triangles_out = 0, vertices_out = 0;  // the result
    std::size_t welded = 0;   // input vertices merged into another at the same position
    std::size_t regions = 0;  // regions simplified (cells, over both passes)
    // kMeshopt only (0 with kCollapse, which needs neither): triangles kept as they were where
    // a collapse broke the topology, and regions whose defects outlived every retry.
    std::size_t frozen_triangles = 0;
    std::size_t regions_kept_whole = 0;
    int attempts = 0;    // simplifier runs over all regions (kMeshopt: with the guard's reruns)
    // The simplifier's estimate of the deviation, Å (largest per pass, summed).
    double error = 0.0;
    // compare_meshes(input, result): the input's vertices to the result's triangles, since the
    // result's vertices are input vertices (Å; NaN unless measure_distance).
    double hausdorff = std::numeric_limits<double>::quiet_NaN();
    double rmsd = std::numeric_limits<double>::quiet_NaN();
    // False when the result has boundary, non-manifold or inconsistently oriented edges,
    // non-manifold vertices or degenerate triangles that the input did not have, or lost its
    // positive volume; or, where the input's statistics were computed (stats_in_computed), has
    // other pieces or another Euler characteristic (a neck pinched, a tunnel closed).
    bool topology_kept = true;
    MeshStats stats_out;           // compute_stats of the result
    // compute_stats of the (welded) input, when computed: with kMeshopt (whose collapses may
    // pinch a neck), or when the result is not a closed manifold. kCollapse keeps the pieces
    // and the genus by construction, and a large mesh's statistics cost about a fifth of its
    // simplification: not computed then.
    MeshStats stats_in;
    bool stats_in_computed = false;
    std::vector<StageTime> times;  // "simplify", "simplify-compare" (host clock)
};

// A copy of `mesh` with about target = min(round(ratio · triangles), max_triangles) triangles
// (at least 1; 0 for an empty mesh), by half-edge collapses in quadric-error order (borders and non-manifold vertices
// locked: an open patch keeps its outline). Vertices at bit-identical positions are welded
// first. Meshes of more than 65,536 triangles are simplified in cells, in parallel on all
// hardware threads. With Simplifier::kCollapse every collapse is tested for the link condition,
// so the result has the input's topology (the same pieces and genus, no new boundary or
// non-manifold edge or vertex); it stops above the target only where no valid collapse is left,
// at max_error, or, in cells, up to 2% above it after its last pass. With kMeshopt, where
// meshopt_simplify's collapses leave non-manifold edges or vertices (meshoptimizer 0.18 does
// not prevent them), the input around them is kept as it was and the rest simplified again:
// the result has no defect the input did not have (it may still close a tunnel or pinch a neck
// narrower than its edges), and may keep more triangles than the target (docs/mesh.md,
// "Keeping the mesh closed"). The result's vertices are a subset of the
// input's, in the input's order, each with its normal, atom, colour and scalars. A target at or
// above the input's count returns the welded input, less unused vertices. Throws
// Error(InvalidArgument) for a ratio outside (0, 1], a negative or NaN max_error, or malformed
// arrays (as write_mesh does).
Mesh simplify_mesh(const Mesh& mesh, const SimplifyOptions& options,
                   SimplifyReport* report = nullptr);

// Reorders triangles for the post-transform vertex cache (meshopt_optimizeVertexCache) and then
// vertices by first use (meshopt_optimizeVertexFetchRemap), in place, carrying every per-vertex
// attribute. The same triangles, each with its corners in the same cyclic order; vertices no
// triangle uses are dropped. Throws Error(InvalidArgument) for malformed arrays.
void optimize_mesh(Mesh& mesh);

}  // namespace fdmsurf
