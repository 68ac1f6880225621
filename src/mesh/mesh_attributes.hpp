// Per-vertex attributes of a Mesh (atoms, colours, scalars): their checks, and the one way every
// operation that drops or reorders vertices carries them along with positions and normals.
#pragma once

#include <cstdint>
#include <string_view>
#include <vector>

#include "fdmsurf/mesh.hpp"

namespace fdmsurf::detail {

// A name write_mesh accepts for a scalar: 1 to 64 characters among A-Z a-z 0-9 _ - . (no
// spaces, which would break a PLY header line), and not one of the vertex properties fdmsurf
// writes itself (x y z nx ny nz atom red green blue).
bool valid_scalar_name(std::string_view name);

// Throws Error(InvalidArgument), naming `who`, unless atoms are empty or one per vertex, colors
// empty or three per vertex, and every scalar has a valid, unique name and one value per vertex.
void validate_attributes(const Mesh& mesh, const char* who);

// Keeps vertices kept[0], kept[1], ... (strictly increasing old indices) as vertices 0, 1, ...
// in every per-vertex array (positions, normals, atoms, colors, scalar values), in place; empty
// arrays stay empty. Indices are not touched: the caller re-points them. The arrays must have
// their sizes (validate_attributes).
void keep_vertices(Mesh& mesh, const std::vector<std::uint32_t>& kept);

// The same into another mesh `to` (its per-vertex arrays and scalar names replaced, indices
// untouched), `from` unchanged; `kept` may be in any order here.
void copy_vertices(const Mesh& from, Mesh& to, const std::vector<std::uint32_t>& kept);

// Empties atoms, colors and scalars: for operations that create vertices whose attributes they
// cannot know (refinement); a later stage computes them.
void clear_attributes(Mesh& mesh);

}  // namespace fdmsurf::detail
