// The vertex-property stage: after the mesh is final, the atom of every vertex and the colours
// and scalars that SurfaceOptions::properties asks for (docs/properties.md).
#pragma once

#include <string>
#include <vector>

#include "fdmsurf/surface.hpp"

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

// The radius added to each atom's for its power distance: the probe for sas, else 0.
float vertex_radius_add(const SurfaceOptions& options);

}  // namespace fdmsurf::detail
