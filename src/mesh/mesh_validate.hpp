// Shape checks on a Mesh's arrays, shared by the statistics and the writers.
#pragma once

#include "fdmsurf/mesh.hpp"

namespace fdmsurf::detail {

// Throws Error(InvalidArgument), naming `who`, unless positions and indices come in threes,
// every index names a vertex, counts fit 32 bits and, if `check_normals`, normals are empty or
// one per vertex.
void validate_mesh(const Mesh& mesh, const char* who, bool check_normals);

// The same without the indices' range, for callers that check it as they read them (and then
// call validate_mesh for the message).
void validate_mesh_arrays(const Mesh& mesh, const char* who, bool check_normals);

}  // namespace fdmsurf::detail
