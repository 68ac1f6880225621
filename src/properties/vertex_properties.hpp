// The vertex-property stage: after the mesh is final, the atom of every vertex and the colours
// and scalars that SurfaceOptions::properties asks for (docs/properties.md).
#pragma once

#include <string>
#include <vector>

#include "fdmsurf/surface.hpp"
#include "isosurface/marching_cubes_gpu.hpp"
#include "vulkan/buffer.hpp"

namespace fdmsurf::detail {

class Commands;
class VertexPropertiesPass;

// What the properties asked for need of the atoms, checked before any work: throws
// Error(InvalidArgument) when they need atom records the input lacks (bare XYZR); returns the
// warnings for properties that will be uniform (no elements, every B-factor 0).
std::vector<std::string> check_property_inputs(const Atoms& atoms, const PropertyOptions& po);

// Fills result.mesh.atoms (always), colors and scalars; adds the stage times and, once, a
// warning naming the charge model when the atoms carry no charges of their own.
void add_vertex_properties(VertexPropertiesPass& pass, Commands& cmds, const Atoms& atoms,
                           const SurfaceOptions& options, SurfaceResult& result);

// For make_device_surface: the attribute buffer of `mesh` (per vertex its atom and its colour
// under options.properties.color, packed R8G8B8A8 with alpha 255), computed on the device from
// the mesh's own vertex buffer, which lies in `grid`'s box. Throws Error(InvalidArgument) for
// Coulombic (which needs the host mesh); adds the stage times to `times`.
Buffer device_mesh_attributes(VertexPropertiesPass& pass, Commands& cmds, const Atoms& atoms,
                              const SurfaceOptions& options, const GpuMesh& mesh,
                              const GridInfo& grid, std::vector<StageTime>& times);

// R8G8B8A8 with alpha 255: red in the low byte.
std::uint32_t pack_rgba(const std::array<std::uint8_t, 3>& rgb);

// The radius added to each atom's for its power distance: the probe for sas, else 0.
float vertex_radius_add(const SurfaceOptions& options);

}  // namespace fdmsurf::detail
