// Test helper: running ../shared/tools/meshstat.py (FDMSURF_REQUIRE_TOOLS=1 turns its absence
// from a skip into a failure).
#pragma once

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <initializer_list>
#include <memory>
#include <optional>
#include <string>

#include "cli/json_check.hpp"

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

// The development checkout's folder of tools and data, beside the repository (not part of it).
inline std::string shared_dir() {
#ifdef FDMSURF_SHARED_DIR
    return FDMSURF_SHARED_DIR;
#else
    return "../shared";
#endif
}

inline std::string meshstat_path() { return shared_dir() + "/tools/meshstat.py"; }

// stdout of `meshstat.py --json ARGS...` run by /usr/bin/python3, each argument in single quotes
// (none may hold one); its exit status in `status`.
inline std::string run_meshstat(std::initializer_list<std::string> args, int& status) {
    std::string command = "/usr/bin/python3 '" + meshstat_path() + "' --json";
    for (const std::string& arg : args) command += " '" + arg + "'";
    return run_capture(command, status);
}

// The statistics of the mesh file at `path` by `meshstat.py --json stats` (an object; the first
// when it gives a list, one per mesh), or nullopt when meshstat fails or prints no JSON. `text`
// gets what it printed.
inline std::optional<fdmsurf_cli_test::JsonValue> meshstat_stats(const std::string& path,
                                                                 std::string& text) {
    int status = 0;
    text = run_meshstat({"stats", path}, status);
    auto json = fdmsurf_cli_test::parse_json(text);
    if (status != 0 || !json) return std::nullopt;
    if (json->type == fdmsurf_cli_test::JsonValue::Type::Array && !json->array.empty())
        return json->array[0];
    return json;
}

// Why meshstat.py cannot run here, or "" when it can.
inline std::string meshstat_unavailable() {
    const std::string meshstat = meshstat_path();
    if (!std::filesystem::exists("/usr/bin/python3")) return "/usr/bin/python3 is missing";
    if (!std::filesystem::exists(meshstat)) return meshstat + " is missing";
    if (std::system("/usr/bin/python3 -c 'import numpy, scipy' >/dev/null 2>&1") != 0)
        return "python3-numpy or python3-scipy is missing";
    return "";
}

}  // namespace fdmsurf::test

// Skips the test (or fails it under FDMSURF_REQUIRE_TOOLS=1) when meshstat.py cannot run.
#define FDMSURF_REQUIRE_MESHSTAT()                                                                 \
    do {                                                                                           \
        const std::string why_ = ::fdmsurf::test::meshstat_unavailable();                          \
        if (!why_.empty()) {                                                                       \
            if (::fdmsurf::test::tools_required()) FAIL() << why_ << " (FDMSURF_REQUIRE_TOOLS=1)"; \
            GTEST_SKIP() << why_;                                                                  \
        }                                                                                          \
    } while (0)
