// Test helper: running ../shared/tools/meshstat.py (FDMSURF_REQUIRE_TOOLS=1 turns its absence
// from a skip into a failure).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>

namespace fdmsurf::test {

inline bool tools_required() {
    const char* require = std::getenv("FDMSURF_REQUIRE_TOOLS");
    return require != nullptr && std::string(require) == "1";
}

// stdout of `command`; its exit status in `status` (-1 when it could not start).
inline std::string run_capture(const std::string& command, int& status) {
    std::string out;
    std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), &pclose);
    if (!pipe) {
        status = -1;
        return out;
    }
    char buffer[4096];
    std::size_t n;
    while ((n = std::fread(buffer, 1, sizeof buffer, pipe.get())) > 0) out.append(buffer, n);
    status = pclose(pipe.release());
    return out;
}

// Why meshstat.py at `meshstat` cannot run here, or "" when it can.
inline std::string meshstat_unavailable(const std::string& meshstat) {
    if (!std::filesystem::exists("/usr/bin/python3")) return "/usr/bin/python3 is missing";
    if (!std::filesystem::exists(meshstat)) return meshstat + " is missing";
    if (std::system("/usr/bin/python3 -c 'import numpy, scipy' >/dev/null 2>&1") != 0)
        return "python3-numpy or python3-scipy is missing";
    return "";
}

}  // namespace fdmsurf::test

// Skips the test (or fails it under FDMSURF_REQUIRE_TOOLS=1) when meshstat.py cannot run.
#define FDMSURF_REQUIRE_MESHSTAT(meshstat)                                                  \
    do {                                                                                   \
        const std::string why_ = ::fdmsurf::test::meshstat_unavailable(meshstat);          \
        if (!why_.empty()) {                                                               \
            if (::fdmsurf::test::tools_required()) FAIL() << why_ << " (FDMSURF_REQUIRE_TOOLS=1)"; \
            GTEST_SKIP() << why_;                                                          \
        }                                                                                  \
    } while (0)
