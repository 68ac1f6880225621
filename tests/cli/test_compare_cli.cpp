// Tests of `fdmsurf compare`: its parser, its output, and the program's exit codes and errors.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli/compare_command.hpp"
#include "cli/json_check.hpp"
#include "fdmsurf/compare.hpp"
#include "fdmsurf/error.hpp"
#include "mesh/mesh_shapes.hpp"

namespace {

namespace fs = std::filesystem;
using fdmsurf::ErrorCode;
using fdmsurf::cli::parse_compare_args;

#ifdef FDMSURF_CLI_PATH
const char* const kCliPath = FDMSURF_CLI_PATH;
#else
const char* const kCliPath = nullptr;
#endif
#ifdef FDMSURF_TEST_DATA_DIR
const std::string kDataDir = FDMSURF_TEST_DATA_DIR;
#else
const std::string kDataDir = "tests/data";
#endif

ErrorCode parse_error(const std::vector<std::string>& args) {
    try {
        parse_compare_args(args);
    } catch (const fdmsurf::Error& e) {
        return e.code();
    }
    ADD_FAILURE() << "accepted";
    return ErrorCode::Internal;
}

TEST(CompareArgs, ParsesOptionsInEitherForm) {
    const auto a = parse_compare_args({"ref.ply", "--spacing", "0.25", "test.off", "--outer"});
    EXPECT_EQ(a.reference, "ref.ply");
    EXPECT_EQ(a.tested, "test.off");
    EXPECT_EQ(a.compare.spacing, 0.25);
    EXPECT_TRUE(a.compare.outer_only);
    EXPECT_FALSE(a.json);
    const auto b =
        parse_compare_args({"--spacing=1", "--stats=json", "--weld-tol", "0", "--", "-r", "t"});
    EXPECT_EQ(b.reference, "-r");
    EXPECT_EQ(b.compare.spacing, 1.0);
    EXPECT_EQ(b.compare.weld_tolerance, 0.0);
    EXPECT_TRUE(b.json);
    EXPECT_TRUE(parse_compare_args({"--help"}).help);
}

TEST(CompareArgs, RejectsBadArguments) {
    EXPECT_EQ(parse_error({"a", "b"}), ErrorCode::InvalidArgument);  // no --spacing
    EXPECT_EQ(parse_error({"a", "--spacing", "0.5"}), ErrorCode::InvalidArgument);
    EXPECT_EQ(parse_error({"a", "b", "c", "--spacing", "0.5"}), ErrorCode::InvalidArgument);
    for (const char* bad : {"0", "-0.5", "abc", "0.5x", "nan", "inf", ""}) {
        EXPECT_EQ(parse_error({"a", "b", "--spacing", bad}), ErrorCode::InvalidArgument) << bad;
    }
    EXPECT_EQ(parse_error({"a", "b", "--spacing"}), ErrorCode::InvalidArgument);
    EXPECT_EQ(parse_error({"a", "b", "--spacing", "1", "--stats", "xml"}),
              ErrorCode::InvalidArgument);
    EXPECT_EQ(parse_error({"a", "b", "--spacing", "1", "--bogus"}), ErrorCode::InvalidArgument);
    EXPECT_EQ(parse_error({"a", "b", "--spacing", "1", "--outer=yes"}), ErrorCode::InvalidArgument);
}

TEST(CompareReportText, ShowsEveryFigure) {
    fdmsurf::cli::CompareReport report;
    report.reference = "ref.ply";
    report.tested = "test.ply";
    report.result.rmsd_weighted = 0.1234;
    report.result.share_beyond_spacing = 0.0456;
    report.result.area_rel_error = -0.0123;
    report.result.volume_rel_error = 0.0045;
    const std::string text = fdmsurf::cli::compare_text(report);
    for (const char* part : {"RMSD_w          0.1234 Å", "4.56 % of reference area has d > 0.5 Å",
                             "-1.23 %", "+0.45 %", "Hausdorff", "mean signed d", "time (ms)"}) {
        EXPECT_NE(text.find(part), std::string::npos) << part << " not in:\n" << text;
    }
    const auto json = fdmsurf_cli_test::parse_json(fdmsurf::cli::compare_json(report));
    ASSERT_TRUE(json.has_value());
    EXPECT_DOUBLE_EQ(json->find("pct_area_beyond_spacing")->number, 4.56);
    EXPECT_DOUBLE_EQ(json->find("rmsd")->number, 0.1234);
}

// ---------------------------------------------------------------------------------------------
// The program

struct ProgramRun {
    int exit_code = -1;
    std::string out, err;
};

std::string slurp(const fs::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

std::string quote(const std::string& text) {
    std::string out = "'";
    for (char c : text) out += c == '\'' ? std::string("'\\''") : std::string(1, c);
    return out + "'";
}

class CompareProgram : public ::testing::Test {
protected:
    void SetUp() override {
        if (kCliPath == nullptr) GTEST_SKIP() << "the fdmsurf program is not built";
        const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
        dir_ = fs::temp_directory_path() /
               ("fdmsurf_compare_cli_" + std::to_string(::getpid()) + "_" + info->name());
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override {
        std::error_code ec;
        if (!dir_.empty()) fs::remove_all(dir_, ec);
    }

    std::string path(const std::string& name) const { return (dir_ / name).string(); }
    std::string write_file(const std::string& name, const std::string& content) const {
        std::ofstream(path(name), std::ios::binary) << content;
        return path(name);
    }

    std::string write_sphere(const std::string& name) const {
        fdmsurf::write_mesh(fdmsurf::test::icosphere(2.0, 2), path(name));
        return path(name);
    }

    ProgramRun run(const std::vector<std::string>& args) const {
        std::string command = quote(kCliPath);
        command.append(" compare");
        for (const std::string& a : args) command.append(" ").append(quote(a));
        command.append(" </dev/null >").append(quote(path("stdout")));
        command.append(" 2>").append(quote(path("stderr")));
        const int status = std::system(command.c_str());
        ProgramRun r;
        if (status != -1 && WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
        r.out = slurp(path("stdout"));
        r.err = slurp(path("stderr"));
        return r;
    }

    // The exit code, one "fdmsurf: error:" line on stderr mentioning `mention`, empty stdout.
    static void expect_failure(const ProgramRun& r, int code, const std::string& mention) {
        EXPECT_EQ(r.exit_code, code) << r.err;
        EXPECT_EQ(r.out, "");
        EXPECT_EQ(r.err.rfind("fdmsurf: error: ", 0), 0u) << r.err;
        EXPECT_EQ(r.err.find('\n'), r.err.size() - 1) << "not one line: " << r.err;
        EXPECT_NE(r.err.find(mention), std::string::npos) << mention << " not in: " << r.err;
    }

    fs::path dir_;
};

TEST_F(CompareProgram, ComparesTheShipped1crnPair) {
    const std::string reference = kDataDir + "/1crn-ses-nanoshaper.ply.gz";
    const std::string tested = kDataDir + "/1crn-fdm-0.5.ply";
    const ProgramRun text = run({reference, tested, "--spacing", "0.5"});
    ASSERT_EQ(text.exit_code, 0) << text.err;
    EXPECT_EQ(text.err, "");
    EXPECT_NE(text.out.find("RMSD_w"), std::string::npos) << text.out;

    const ProgramRun json = run({reference, tested, "--spacing", "0.5", "--stats", "json"});
    ASSERT_EQ(json.exit_code, 0) << json.err;
    const auto value = fdmsurf_cli_test::parse_json(json.out);
    ASSERT_TRUE(value.has_value()) << json.out;
    fdmsurf::CompareOptions options;
    const fdmsurf::CompareResult r = fdmsurf::compare_meshes(
        fdmsurf::read_mesh_any(reference), fdmsurf::read_mesh_any(tested), options);
    EXPECT_EQ(value->find("rmsd")->number, r.rmsd_weighted);
    EXPECT_EQ(value->find("pct_area_beyond_spacing")->number, 100 * r.share_beyond_spacing);
    EXPECT_EQ(value->find("area_rel_err")->number, r.area_rel_error);
    EXPECT_EQ(value->find("ref_vertices")->number, double(r.ref_vertices));
    EXPECT_NE(value->find("compare_ms"), nullptr);
    EXPECT_EQ(value->find("outer")->type, fdmsurf_cli_test::JsonValue::Type::Bool);
}

TEST_F(CompareProgram, HelpNeedsNoFiles) {
    const ProgramRun r = run({"--help"});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("Usage: fdmsurf compare REFERENCE TESTED --spacing H"), std::string::npos);
    EXPECT_EQ(r.err, "");
}

TEST_F(CompareProgram, MissingFileIsAnInputError) {
    const std::string sphere = write_sphere("s.ply");
    expect_failure(run({path("nowhere.ply"), sphere, "--spacing", "0.5"}), 3, "nowhere.ply");
    expect_failure(run({sphere, path("gone.off"), "--spacing", "0.5"}), 3, "gone.off");
}

TEST_F(CompareProgram, UnreadableMeshIsAnInputError) {
    const std::string sphere = write_sphere("s.ply");
    const std::string junk = write_file("junk.ply", "ply\nformat ascii 1.0\nelement vertex 3\n");
    expect_failure(run({sphere, junk, "--spacing", "0.5"}), 3, "junk.ply");
    const std::string text = write_file("notes.txt", "hello\n");
    expect_failure(run({text, sphere, "--spacing", "0.5"}), 3, "notes.txt");
    const std::string flat = write_file("flat.off", "OFF\n3 1 0\n0 0 0\n1 0 0\n2 0 0\n3 0 1 2\n");
    expect_failure(run({flat, sphere, "--spacing", "0.5"}), 3, "reference");
}

// A mesh of no volume (two triangles back to back) has no relative volume error: "n/a", not
// "nan %"; a name with control characters is shown with '?' for them.
TEST_F(CompareProgram, NoVolumeAndOddNamesReadWell) {
    const std::string pillow =
        write_file("a\x1b[31mb.off", "OFF\n3 2 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n3 0 2 1\n");
    const ProgramRun r = run({pillow, pillow, "--spacing", "0.5"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("tested, n/a\n"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find("nan"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("a?[31mb.off against"), std::string::npos) << r.out;
    EXPECT_EQ(r.out.find('\x1b'), std::string::npos);
}

TEST_F(CompareProgram, BadSpacingIsAUsageError) {
    const std::string sphere = write_sphere("s.ply");
    expect_failure(run({sphere, sphere, "--spacing", "0"}), 2, "--spacing");
    expect_failure(run({sphere, sphere, "--spacing", "-1"}), 2, "--spacing");
    expect_failure(run({sphere, sphere, "--spacing", "half"}), 2, "--spacing");
    expect_failure(run({sphere, sphere}), 2, "--spacing");
    expect_failure(run({sphere, "--spacing", "1"}), 2, "TESTED");
    expect_failure(run({sphere, sphere, "--spacing", "1", "--nope"}), 2, "--nope");
}

}  // namespace
