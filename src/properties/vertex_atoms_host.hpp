// The vertex atoms on the host's threads (a CPU device's default): each vertex's atom of least
// power distance, in vertex_atoms.comp's float arithmetic and tie rule.
#pragma once

#include <cstddef>
#include <cstdint>

#include "fdmsurf/structure.hpp"

namespace fdmsurf::detail {

// Into out[v * stride] for each of the n vertices at `positions` (x, y, z each): the atom i of
// least float power ((p - c_i)² summed x, y, z) - (r_i + radius_add)², ties to the lower index,
// which is vertex_atoms.comp's atom; 0xffffffff for a vertex with a coordinate that is not
// finite (every power is then infinite or not a number, and the shader finds none).
void host_vertex_atoms(const Atoms& atoms, const float* positions, std::size_t n,
                       float radius_add, std::uint32_t* out, std::size_t stride);

}  // namespace fdmsurf::detail
