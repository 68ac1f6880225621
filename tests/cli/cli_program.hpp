// Test helper: the fdmsurf program run as a user runs it (a fixture with its own folder, stdout
// and stderr captured, standard input from a file), shared by the CLI test files.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <optional>
#include <set>
#include <sstream>
#include <string>
#include <vector>

namespace fdmsurf_cli_test {

namespace fs = std::filesystem;

#ifdef FDMSURF_CLI_PATH
inline constexpr const char* kCliPath = FDMSURF_CLI_PATH;
#else
inline constexpr const char* kCliPath = nullptr;
#endif

#ifdef FDMSURF_TEST_DATA_DIR
inline constexpr const char* kDataDir = FDMSURF_TEST_DATA_DIR;
#else
inline constexpr const char* kDataDir = nullptr;
#endif

// Two atoms 1.5 Å apart: enough for a surface, fast on any device.
inline constexpr const char* kTwoAtomsXyzr = "0.0 0.0 0.0 1.7\n1.5 0.0 0.0 1.52\n";

inline std::string shell_quote(const std::string& text) {
    std::string out = "'";
    for (char c : text) {
        if (c == '\'') {
            out += "'\\''";
        } else {
            out += c;
        }
    }
    return out + "'";
}

inline std::string read_text(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

inline std::vector<std::string> lines_of(const std::string& text) {
    std::vector<std::string> lines;
    std::istringstream in(text);
    for (std::string line; std::getline(in, line);) lines.push_back(line);
    return lines;
}

struct CliRun {
    int exit_code = -1;  // -1 when the program did not exit normally (a crash)
    std::string out;
    std::string err;

    std::vector<std::string> error_lines() const {
        std::vector<std::string> found;
        for (const std::string& line : lines_of(err)) {
            if (line.rfind("fdmsurf: error:", 0) == 0) found.push_back(line);
        }
        return found;
    }
};

// Each test gets its own folder, so that tests may run in parallel.
class CliProgram : public ::testing::Test {
protected:
    void SetUp() override {
        if (kCliPath == nullptr) {
            GTEST_SKIP() << "the fdmsurf program is not built (FDMSURF_BUILD_CLI=OFF)";
        }
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               ("fdmsurf_cli_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
        capture_ = fs::temp_directory_path() /
                   ("fdmsurf_cli_capture_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(capture_);
        fs::create_directories(capture_);
    }

    void TearDown() override {
        std::error_code ec;
        if (!dir_.empty()) fs::remove_all(dir_, ec);
        if (!capture_.empty()) fs::remove_all(capture_, ec);
    }

    std::string path(const std::string& name) const { return (dir_ / name).string(); }

    std::string write_file(const std::string& name, const std::string& content) {
        std::ofstream(dir_ / name, std::ios::binary) << content;
        inputs_.insert(name);
        return path(name);
    }

    // Runs the program with stdout and stderr captured to files outside the test's folder,
    // standard input from `stdin_path`.
    CliRun run(const std::vector<std::string>& args, const std::string& env = "",
               const std::string& stdin_path = "/dev/null") const {
        const fs::path out = capture_ / "stdout";
        const fs::path err = capture_ / "stderr";
        std::string command = env.empty() ? "" : "env " + env + " ";
        command += shell_quote(kCliPath);
        for (const std::string& arg : args) command.append(" ").append(shell_quote(arg));
        command.append(" <").append(shell_quote(stdin_path));
        command.append(" >").append(shell_quote(out.string()));
        command.append(" 2>").append(shell_quote(err.string()));
        const int status = std::system(command.c_str());
        CliRun result;
        if (status != -1 && WIFEXITED(status)) result.exit_code = WEXITSTATUS(status);
        result.out = read_text(out);
        result.err = read_text(err);
        return result;
    }

    // The files in the test's folder that the test did not write itself.
    std::vector<std::string> stray_files() const {
        std::vector<std::string> stray;
        for (const auto& entry : fs::recursive_directory_iterator(dir_)) {
            const std::string name = fs::relative(entry.path(), dir_).string();
            if (!inputs_.contains(name)) stray.push_back(name);
        }
        return stray;
    }

    // A failed run: the exit code, exactly one error line naming every one of `mentions`,
    // nothing on stdout and no output file left behind.
    void expect_failure(const CliRun& r, int exit_code, const std::vector<std::string>& mentions) {
        EXPECT_EQ(r.exit_code, exit_code) << "stderr:\n" << r.err;
        const std::vector<std::string> errors = r.error_lines();
        ASSERT_EQ(errors.size(), 1u) << "stderr:\n" << r.err;
        for (const std::string& mention : mentions) {
            EXPECT_NE(errors[0].find(mention), std::string::npos)
                << "'" << mention << "' not in: " << errors[0];
        }
        EXPECT_EQ(r.out, "");
        EXPECT_EQ(stray_files(), std::vector<std::string>{});
    }

    // Why the end-to-end tests cannot run: no usable device in `fdmsurf --list-devices`.
    std::optional<std::string> no_usable_device() const {
        const CliRun r = run({"--list-devices"});
        if (r.exit_code == 0) {
            for (std::string line : lines_of(r.out)) {
                line.erase(0, line.find_first_not_of(' '));
                if (line.rfind("usable", 0) != 0) continue;
                line.erase(0, 6);
                line.erase(0, line.find_first_not_of(' '));
                if (line == "yes") return std::nullopt;
            }
        }
        return "no usable Vulkan device; fdmsurf --list-devices says:\n" + r.out + r.err;
    }

    // FDMSURF_REQUIRE_DEVICE=1 (CI with lavapipe) turns the skip into a failure.
    static bool device_required() {
        const char* require = std::getenv("FDMSURF_REQUIRE_DEVICE");
        return require != nullptr && std::string(require) == "1";
    }

    fs::path dir_;
    fs::path capture_;
    std::set<std::string> inputs_;
};

}  // namespace fdmsurf_cli_test

// In a CliProgram test: skips the end-to-end test when no device is usable, or fails it under
// FDMSURF_REQUIRE_DEVICE=1.
#define FDMSURF_REQUIRE_CLI_DEVICE()                                               \
    do {                                                                           \
        if (const auto why = no_usable_device()) {                                 \
            if (device_required()) FAIL() << *why << "(FDMSURF_REQUIRE_DEVICE=1)"; \
            GTEST_SKIP() << *why;                                                  \
        }                                                                          \
    } while (0)
