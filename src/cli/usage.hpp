// The --help text of the fdmsurf program (src/cli/usage.cpp).
#pragma once

#include <string>

namespace fdmsurf::cli {

// The --help text: usage, every option with its unit and default, the exit codes.
std::string usage_text();

}  // namespace fdmsurf::cli
