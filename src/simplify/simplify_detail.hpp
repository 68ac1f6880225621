// Internals of simplify_mesh, exposed for the tests: the target, exact welding, the topology test.
#pragma once

#include <cstddef>

#include "fdmsurf/mesh.hpp"
#include "fdmsurf/simplify.hpp"

namespace fdmsurf::detail {

// The triangle count simplify_mesh aims at for an input of `triangles`: round(ratio ·
// triangles), at least 1, capped at max_triangles when that is set. Throws
// Error(InvalidArgument) for a ratio outside (0, 1] or a max_error that is negative or NaN.
std::size_t simplify_target(std::size_t triangles, const SimplifyOptions& options);

// Vertices at bit-identical positions merged into the lowest-numbered one (its attributes
// kept), triangles that merging collapses dropped, unused vertices dropped; the rest in order.
// `welded` (may be null) gets the number of vertices merged into another.
Mesh weld_exact(const Mesh& mesh, std::size_t* welded);

// False when `out` has more boundary, non-manifold or inconsistently oriented edges,
// non-manifold vertices or degenerate triangles than `in`, or lost its positive volume.
bool topology_kept(const MeshStats& in, const MeshStats& out);

}  // namespace fdmsurf::detail
