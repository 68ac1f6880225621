// Checks of a file the CLI will write, made before any work so that a typo costs no device
// time: shared by fdmsurf's -o, --image and --areas and by fdmsurf msms's -of and -af.
#pragma once

#include <string>

namespace fdmsurf::cli {

// Whether a file at `path` is written through as it is (standard output "-", anything under /dev
// or /proc: AtomicFile neither replaces nor renames them), not checked by the functions below.
bool written_through(const std::string& path);

// Why a file cannot be created at `path`, or "" when nothing is known against it: its folder
// does not exist or is not a folder, `path` is a folder, or its name is longer than the folder's
// file system allows (NAME_MAX, 255 bytes on Linux's); all of the file a symbolic link at `path`
// leads to (detail::follow_links, as AtomicFile writes there), and a loop of links is the problem
// itself.
std::string output_path_problem(const std::string& path);

// The file `path` reaches, to tell whether two outputs are one: its symbolic links followed (a
// dangling one too), absolute, the links of its existing folders resolved.
std::string output_identity(const std::string& path);

}  // namespace fdmsurf::cli
