// Joining marching-cubes meshes of consecutive z-slabs of one field into one shared-vertex mesh.
#pragma once

#include <cstdint>
#include <functional>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "isosurface/marching_cubes_cpu.hpp"

namespace fdmsurf::detail {

// The planes of a field of nx × ny × nz points that the stitch reads: plane(z) returns plane z's
// nx * ny values (x fastest, rows of nx) for every z = starts[j + 1] and starts[j + 1] + 1 < nz.
struct SlabPlanes {
    std::uint32_t nx = 0, ny = 0, nz = 0;
    std::function<const float*(std::uint32_t z)> plane;
};

// parts[j] is the marching-cubes mesh of global planes [starts[j], starts[j+1]] of `field`
// (the last part ending at plane field.nz - 1), in the order of
// marching_cubes_cpu. Plane starts[j+1] is the top plane of part j and the bottom plane of part
// j+1: its x/y-edge vertices appear in both; part j's copies are dropped and its triangles
// re-pointed at part j+1's. `starts` has parts.size() + 1 entries.
Mesh stitch_slabs(std::vector<Mesh>& parts, const SlabPlanes& field, float iso,
                  const std::vector<std::uint32_t>& starts);

// The same stitch in place, one seam at a time, as the parts are appended to one mesh (by
// marching_cubes_host_append or MarchingCubesPass::read_back_append), so that no part is copied
// again. `mesh` ends with a part, from vertex first_vertex and index first_index on, whose top
// plane is a plane z of the field: `here` is its nx * ny values, `next` those of plane z + 1. The
// part's top-plane vertices (its last) are dropped and its triangles re-pointed at the next
// part's copies of them, which are that part's first vertices once it is appended after this
// call. stitch_slabs' mesh, vertex for vertex and index for index.
void stitch_top_plane(Mesh& mesh, std::size_t first_vertex, std::size_t first_index,
                      const float* here, const float* next, std::uint32_t nx, std::uint32_t ny,
                      float iso);

}  // namespace fdmsurf::detail
