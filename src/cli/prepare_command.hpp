// `fdmsurf prepare`: builds the FFT plans of the canonical grid sizes ahead of the first run
// (Engine::prepare), so that a small structure's first surface compiles nothing.
#pragma once

#include <string>
#include <vector>

namespace fdmsurf::cli {

std::string prepare_usage_text();

// Runs the command: one line per plan and a summary on stdout (nothing with --quiet), errors as
// one "fdmsurf: error: ..." line on stderr. Returns the exit code (0; 2 for usage errors; 1 for
// validation messages under --validation; the device's codes when there is no usable device).
int prepare_command(const std::vector<std::string>& args);

}  // namespace fdmsurf::cli
