// The text of `fdmsurf --version`: the version, the git commit the program was built from and
// whether it is a release.
#pragma once

#include <string>

namespace fdmsurf::cli {

// Two lines: "fdmsurf VERSION" (what scripts parse), then the commit and whether the build is a
// release (made from the tag vVERSION with no local changes). Defined in the build folder's
// generated build_info.cpp (src/cli/version.cpp.in, cmake/FdmsurfBuildInfo.cmake), which is
// compiled into the program alone: a new commit relinks the program, not the libraries.
std::string version_text();

}  // namespace fdmsurf::cli
