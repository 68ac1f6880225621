// Joining marching-cubes meshes of consecutive z-slabs of one field into one shared-vertex mesh.
#pragma once

#include <cstdint>
#include <vector>

#include "fdmsurf/mesh.hpp"
#include "isosurface/marching_cubes_cpu.hpp"

namespace fdmsurf::detail {

// parts[j] is the marching-cubes mesh of global planes [starts[j], starts[j+1]] of `field`
// (with starts.back() + 1 == ... the last part ending at plane field.nz - 1), in the order of
// marching_cubes_cpu. Plane starts[j+1] is the top plane of part j and the bottom plane of part
// j+1: its x/y-edge vertices appear in both; part j's copies are dropped and its triangles
// re-pointed at part j+1's. `starts` has parts.size() + 1 entries.
Mesh stitch_slabs(std::vector<Mesh>& parts, const FieldView& field, float iso,
                  const std::vector<std::uint32_t>& starts);

}  // namespace fdmsurf::detail
