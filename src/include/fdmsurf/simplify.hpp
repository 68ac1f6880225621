// Fewer triangles, and an order GPUs draw faster: mesh simplification and reordering through
// meshoptimizer (docs/mesh.md, "Simplification ... and reordering").
#pragma once

#include <cstddef>
#include <limits>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/surface.hpp"

namespace fdmsurf {

struct SimplifyOptions {
    // Fraction of the triangles to keep, in (0, 1]; 1 keeps them all.
    double ratio = 1.0;
    // At most this many triangles (0: no cap). With ratio < 1 as well, the smaller target wins.
    std::size_t max_triangles = 0;
    // Largest deviation meshoptimizer may introduce, Å, by its own estimate (infinity: none;
    // the target decides). A finite bound can stop the simplifier above the target.
    double max_error = std::numeric_limits<double>::infinity();
    // Measure the Hausdorff distance and the RMSD to the input mesh (compare_meshes).
    bool measure_distance = true;
};

struct SimplifyReport {
    std::size_t triangles_in = 0, vertices_in = 0;    // after welding
    std::size_t target_triangles = 0;                 // from ratio and max_triangles
    std::size_t triangles_out = 0, vertices_out = 0;  // the result
    std::size_t welded = 0;            // input vertices merged into another at the same position
    std::size_t regions = 0;           // regions meshopt_simplify ran on (cells, over both passes)
    std::size_t frozen_triangles = 0;  // kept as they were where a collapse broke the topology
    std::size_t regions_kept_whole = 0;  // regions whose defects outlived every retry
    int attempts = 0;                    // meshopt_simplify runs, over all regions
    double error = 0.0;  // meshoptimizer's estimate of the deviation, Å (largest per pass, summed)
    // compare_meshes(input, result): the input's vertices to the result's triangles, since the
    // result's vertices are input vertices (Å; NaN unless measure_distance).
    double hausdorff = std::numeric_limits<double>::quiet_NaN();
    double rmsd = std::numeric_limits<double>::quiet_NaN();
    // False when the result has boundary, non-manifold or inconsistently oriented edges,
    // non-manifold vertices or degenerate triangles that the input did not have, or lost its
    // positive volume.
    bool topology_kept = true;
    MeshStats stats_out;           // compute_stats of the result
    std::vector<StageTime> times;  // "simplify", "simplify-compare" (host clock)
};

// A copy of `mesh` with about target = min(round(ratio · triangles), max_triangles) triangles
// (at least 1), by meshoptimizer's edge collapses (meshopt_simplify, quadric error, borders
// locked: an open patch keeps its outline). Vertices at bit-identical positions are welded
// first. Meshes of more than 65,536 triangles are simplified in cells, in parallel on all
// hardware threads. Where collapses leave non-manifold edges or vertices (meshoptimizer 0.18
// does not prevent them), the input around them is kept as it was and the rest simplified
// again: the result has no defect the input did not have (it may still close a tunnel or pinch
// a neck narrower than its edges), and may keep more triangles than the target (docs/mesh.md,
// "Keeping the mesh closed"). Its vertices are a subset of the input's, in the input's order,
// each with its normal, atom, colour and scalars. A target at or above the input's count
// returns the welded input, less unused vertices. Throws Error(InvalidArgument) for a ratio
// outside (0, 1], a negative or NaN max_error, or malformed arrays (as write_mesh does).
Mesh simplify_mesh(const Mesh& mesh, const SimplifyOptions& options,
                   SimplifyReport* report = nullptr);

// Reorders triangles for the post-transform vertex cache (meshopt_optimizeVertexCache) and then
// vertices by first use (meshopt_optimizeVertexFetchRemap), in place, carrying every per-vertex
// attribute. The same triangles, each with its corners in the same cyclic order; vertices no
// triangle uses are dropped. Throws Error(InvalidArgument) for malformed arrays.
void optimize_mesh(Mesh& mesh);

}  // namespace fdmsurf
