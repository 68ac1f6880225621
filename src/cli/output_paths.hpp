// Checks of a file the CLI will write, made before any work so that a typo costs no device
// time: shared by fdmsurf's -o, --image and --areas and by fdmsurf msms's -of and -af.
#pragma once

#include <string>

namespace fdmsurf::cli {

// Why a file cannot be created at `path`, or "" when nothing is known against it: its folder
// does not exist or is not a folder, `path` is a folder, or its name is longer than the folder's
// file system allows (NAME_MAX, 255 bytes on Linux's). Standard input and output ("-") and
// paths under /dev and /proc are not checked.
std::string output_path_problem(const std::string& path);

}  // namespace fdmsurf::cli
