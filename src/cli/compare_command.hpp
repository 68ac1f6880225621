// `fdmsurf compare REFERENCE TESTED --spacing H`: accuracy of a mesh against a reference mesh.
#pragma once

#include <string>
#include <vector>

#include "fdmsurf/compare.hpp"

namespace fdmsurf::cli {

struct CompareCliOptions {
    std::string reference;
    std::string tested;
    fdmsurf::CompareOptions compare;
    bool json = false;  // --stats json
    bool help = false;
};

// Parses the arguments after "compare". `--name value` and `--name=value` are both accepted;
// `--` ends the options. --spacing is required. Throws Error(InvalidArgument).
CompareCliOptions parse_compare_args(const std::vector<std::string>& args);

std::string compare_usage_text();

// What the command prints, gathered in one value so that the printers are testable.
struct CompareReport {
    std::string reference;
    std::string tested;
    fdmsurf::CompareOptions options;
    fdmsurf::CompareResult result;
    double read_ms = 0;     // reading both files
    double compare_ms = 0;  // compare_meshes
};

std::string compare_text(const CompareReport& report);
std::string compare_json(const CompareReport& report);  // one object, one line, no newline

// Runs the command: the report on stdout, errors as one "fdmsurf: error: ..." line on stderr.
// Returns the exit code (0; 2 for usage errors; 3 for unreadable input).
int compare_command(const std::vector<std::string>& args);

}  // namespace fdmsurf::cli
