// Internals shared by the mesh readers and writers.
#pragma once

#include <optional>
#include <string>
#include <string_view>

#include "fdmsurf/mesh.hpp"

namespace fdmsurf::detail {

// The extension of the path's file name, lower-cased, with its dot (".ply"); "" if none.
std::string lowercase_extension(const std::string& path);

// Parsers of a whole file's bytes; `path` is for messages. Throw Error(Format).
Mesh parse_ply(std::string_view data, const std::string& path);
Mesh parse_obj(std::string_view data, const std::string& path);
Mesh parse_off(std::string_view text, const std::string& path);
// MSMS's .vert and .face files together.
Mesh parse_msms(std::string_view vert_text, const std::string& vert_path,
                std::string_view face_text, const std::string& face_path);

// The mesh in a file's bytes, for read_mesh and read_mesh_any: PLY and GLB by their magic,
// then OBJ, STL, OFF and GLB by `extension` (lower case, with its dot, as lowercase_extension
// gives it), then OFF by its first word and STL by its size or its "solid ... facet" text.
// nullopt when nothing matches; Error(Format) from the parser chosen.
std::optional<Mesh> parse_mesh_data(std::string_view data, const std::string& path,
                                    const std::string& extension);

}  // namespace fdmsurf::detail
