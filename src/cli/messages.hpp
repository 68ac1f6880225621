// Errors and warnings of every fdmsurf command: "fdmsurf: error: ..." on stderr, one line each.
#pragma once

#include <cstdio>
#include <exception>
#include <new>
#include <string>

#include "cli/options.hpp"
#include "base/text.hpp"
#include "fdmsurf/error.hpp"

namespace fdmsurf::cli {

// Messages go to stderr one per line, whatever the library put in them.
// A message on one line: line breaks and tabs as spaces, other control characters as '?'
// (detail::printable), so that a name in it cannot end the line or reach the terminal as an
// escape sequence.
inline std::string one_line(std::string text) {
    for (char& c : text) {
        if (c == '\n' || c == '\r' || c == '\t') c = ' ';
    }
    return detail::printable(text);
}

// Adds the path to a message that does not name it already.
inline std::string naming(const std::string& path, const std::string& message) {
    if (message.find(path) != std::string::npos) return message;
    return "'" + path + "': " + message;
}

inline void print_error(const std::string& message) {
    std::fprintf(stderr, "fdmsurf: error: %s\n", one_line(message).c_str());
}

inline void print_warning(const std::string& message) {
    std::fprintf(stderr, "fdmsurf: warning: %s\n", one_line(message).c_str());
}

// Runs a command's body and turns what it throws into one error line and the exit code.
template <class Body>
int report_errors(Body&& body) {
    try {
        return body();
    } catch (const Error& e) {
        print_error(e.what());
        return exit_code_for(e);
    } catch (const std::bad_alloc&) {
        print_error("out of host memory; try a coarser --spacing");
        return kExitOutOfMemory;
    } catch (const std::exception& e) {
        print_error(e.what());
        return kExitFailure;
    } catch (...) {
        print_error("unknown exception");
        return kExitFailure;
    }
}

}  // namespace fdmsurf::cli
