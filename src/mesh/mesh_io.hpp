// Internals shared by the mesh readers and writers.
#pragma once

#include <string>
#include <string_view>

#include "fdmsurf/mesh.hpp"

namespace fdmsurf::detail {

// The extension of the path's file name, lower-cased, with its dot (".ply"); "" if none.
std::string lowercase_extension(const std::string& path);

// Parsers of a whole file's bytes; `path` is for messages. Throw Error(Format).
Mesh parse_ply(std::string_view data, const std::string& path);
Mesh parse_obj(std::string_view data, const std::string& path);

}  // namespace fdmsurf::detail
