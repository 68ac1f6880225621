// Errors and warnings of every fdmsurf command: "fdmsurf: error: ..." on stderr, one line each.
#pragma once

#include <cstdio>
#include <string>

namespace fdmsurf::cli {

// Messages go to stderr one per line, whatever the library put in them.
inline std::string one_line(std::string text) {
    for (char& c : text) {
        if (c == '\n' || c == '\r') c = ' ';
    }
    return text;
}

inline void print_error(const std::string& message) {
    std::fprintf(stderr, "fdmsurf: error: %s\n", one_line(message).c_str());
}

inline void print_warning(const std::string& message) {
    std::fprintf(stderr, "fdmsurf: warning: %s\n", one_line(message).c_str());
}

}  // namespace fdmsurf::cli
