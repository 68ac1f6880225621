// Tests of the program's mesh formats and pipes: -o x.glb|.stl|.off, --output-format, -o - (the
// mesh on standard output, the summary on stderr), - as INPUT, a broken pipe, bad combinations.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "cli/cli_program.hpp"
#include "cli/json_check.hpp"
#include "cli/options.hpp"
#include "cli/parse_check.hpp"
#include "fdmsurf/fdmsurf.hpp"

namespace {

namespace fs = std::filesystem;
using fdmsurf_cli_test::CliProgram;
using fdmsurf_cli_test::CliRun;
using fdmsurf_cli_test::kCliPath;
using fdmsurf_cli_test::kDataDir;
using fdmsurf_cli_test::kTwoAtomsXyzr;
using fdmsurf_cli_test::lines_of;
using fdmsurf_cli_test::parse_json;
using fdmsurf_cli_test::read_text;
using fdmsurf_cli_test::shell_quote;

class CliFormats : public CliProgram {
protected:
    // Runs `pipeline` (a shell command line in which $FDMSURF is the program) under bash;
    // returns the exit status of the pipeline's first command, -1 when it did not exit.
    int run_pipeline(const std::string& pipeline, std::string& err) const {
        const std::string err_path = path("pipeline.err");
        const std::string script =
            "FDMSURF=" + shell_quote(kCliPath) + "; " + pipeline + "; exit ${PIPESTATUS[0]}";
        const int status =
            std::system(("bash -c " + shell_quote(script) + " 2>" + shell_quote(err_path)).c_str());
        err = read_text(err_path);
        fs::remove(err_path);
        return status != -1 && WIFEXITED(status) ? WEXITSTATUS(status) : -1;
    }

    std::string crambin() const { return (fs::path(kDataDir) / "1crn.pdb").string(); }
};

TEST(CliFormatOptions, OutputFormatAndStandardStreamsParse) {
    using fdmsurf::MeshFormat;
    using fdmsurf::cli::output_for;
    using fdmsurf::cli::parse_args;
    EXPECT_EQ(fdmsurf_cli_test::parse_with({}).output_format, MeshFormat::Auto);
    EXPECT_EQ(fdmsurf_cli_test::parse_with({"--output-format", "GLB"}).output_format,
              MeshFormat::Glb);
    EXPECT_EQ(fdmsurf_cli_test::parse_with({"--output-format=off"}).output_format, MeshFormat::Off);
    const auto o = parse_args({"-", "-o", "-", "--output-format", "stl"});
    EXPECT_EQ(o.inputs, std::vector<std::string>{"-"});
    EXPECT_EQ(o.output, "-");
    EXPECT_EQ(o.output_format, MeshFormat::Stl);
    EXPECT_FALSE(fdmsurf::cli::output_is_folder("-"));
    EXPECT_EQ(output_for("-", "-"), "-");
    EXPECT_EQ(output_for("-", "meshes/"), "meshes/stdin.ply");
    EXPECT_EQ(output_for("a/1crn.pdb.gz", "meshes/", MeshFormat::Glb), "meshes/1crn.glb");
    EXPECT_EQ(output_for("1d3z.pdb", "out/", 2, MeshFormat::Stl), "out/1d3z-m2.stl");
    EXPECT_EQ(output_for("1crn.pdb", "x.bin", MeshFormat::Stl), "x.bin");
    // Two inputs that would write the same file, in the format asked for.
    try {
        parse_args({"a.pdb", "a.cif", "-o", "out/", "--output-format", "glb"});
        ADD_FAILURE() << "no error";
    } catch (const fdmsurf::Error& e) {
        EXPECT_TRUE(fdmsurf_cli_test::contains(e.what(), "would both write 'out/a.glb'"))
            << e.what();
    }
    EXPECT_TRUE(
        fdmsurf_cli_test::contains(fdmsurf_cli_test::parse_error_with({"--output-format", "wrl"}),
                                   "ply, obj, glb, stl, off or png"));
}

TEST_F(CliFormats, EveryOutputExtensionWritesAClosedMeshThatReadsBack) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    for (const char* ext : {".glb", ".stl", ".off", ".ply", ".obj"}) {
        const std::string output = path(std::string("atoms") + ext);
        const CliRun r = run({input, "-o", output, "--stats", "json", "--color", "#ff8000"});
        ASSERT_EQ(r.exit_code, 0) << ext << ": " << r.err;
        const auto json = parse_json(lines_of(r.out).at(0));
        ASSERT_TRUE(json) << r.out;
        EXPECT_EQ(json->find("output")->string, output);
        EXPECT_EQ(json->find("output_format")->string, std::string(ext + 1));
        const fdmsurf::Mesh mesh = fdmsurf::read_mesh(output);
        const fdmsurf::MeshStats stats = fdmsurf::compute_stats(mesh);
        EXPECT_TRUE(stats.is_closed_manifold()) << ext;
        EXPECT_EQ(double(stats.triangles), json->find("triangles")->number) << ext;
        EXPECT_NEAR(stats.area, json->find("area")->number, 1e-3 * stats.area) << ext;
        if (std::string(ext) == ".glb") {
            EXPECT_EQ(mesh.atoms.size(), mesh.vertex_count());
            ASSERT_EQ(mesh.colors.size(), 3 * mesh.vertex_count());
            EXPECT_EQ(mesh.colors[0], 255);
            EXPECT_EQ(mesh.colors[1], 128);
            EXPECT_EQ(mesh.colors[2], 0);
        }
        if (std::string(ext) == ".off") {
            EXPECT_EQ(mesh.colors.size(), 3 * mesh.vertex_count());
        }
    }
}

TEST_F(CliFormats, OutputFormatOverridesTheExtensionAndNamesFolderOutputs) {
    const std::string a = write_file("a.xyzr", kTwoAtomsXyzr);
    const std::string b = write_file("b.xyzr", kTwoAtomsXyzr);
    expect_failure(run({a, "-o", path("out.ply"), "--output-format", "vrml"}), 2,
                   {"--output-format", "vrml", "ply, obj, glb, stl, off or png"});
    FDMSURF_REQUIRE_CLI_DEVICE();
    CliRun r = run({a, "-o", path("mesh.bin"), "--output-format", "stl", "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::string stl = read_text(path("mesh.bin"));
    ASSERT_GE(stl.size(), 84u);
    EXPECT_EQ(stl.size(), 84 + 50 * std::size_t(std::uint8_t(stl[80]) | std::uint8_t(stl[81]) << 8 |
                                                std::uint8_t(stl[82]) << 16));
    r = run({a, b, "-o", path("meshes") + "/", "--output-format", "glb", "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fdmsurf::read_mesh(path("meshes/a.glb")).triangle_count() > 0);
    EXPECT_TRUE(fs::exists(path("meshes/b.glb")));
}

// -o -: the bytes on stdout are those of the file; the summary, text or JSON, goes to stderr.
TEST_F(CliFormats, MeshOnStandardOutputEqualsTheFileAndTheSummaryGoesToStderr) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    for (const char* format : {"ply", "glb", "stl", "off", "obj"}) {
        const std::string file = path(std::string("atoms.") + format);
        CliRun r = run({input, "-o", file, "--quiet", "--color", "element"});
        ASSERT_EQ(r.exit_code, 0) << r.err;
        r = run({input, "-o", "-", "--output-format", format, "--color", "element"});
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_TRUE(r.out == read_text(file)) << format << ": stdout differs from the file";
        EXPECT_NE(r.err.find("closed manifold: yes"), std::string::npos) << r.err;
        EXPECT_NE(r.err.find("output       -"), std::string::npos) << r.err;
    }
    // PLY by default; JSON on stderr, one line.
    const CliRun r = run({input, "-o", "-", "--stats", "json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(r.out.starts_with("ply\nformat binary_little_endian 1.0\n"));
    const std::vector<std::string> lines = lines_of(r.err);
    ASSERT_EQ(lines.size(), 1u) << r.err;
    const auto json = parse_json(lines[0]);
    ASSERT_TRUE(json) << lines[0];
    EXPECT_EQ(json->find("output")->string, "-");
    EXPECT_TRUE(json->find("closed_manifold")->boolean);
    std::vector<std::string> files = stray_files();
    std::sort(files.begin(), files.end());
    EXPECT_EQ(files, (std::vector<std::string>{"atoms.glb", "atoms.obj", "atoms.off", "atoms.ply",
                                               "atoms.stl"}));
}

// - reads standard input, from a redirect or a pipe, gzip or not; the format from the content.
TEST_F(CliFormats, StandardInputGivesTheSameMeshAsTheFile) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string from_file = path("file.ply");
    CliRun r = run({crambin(), "-o", from_file, "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    r = run({"-", "-o", path("stdin.ply"), "--stats", "json"}, "", crambin());
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(read_text(path("stdin.ply")) == read_text(from_file));
    const auto json = parse_json(lines_of(r.out).at(0));
    ASSERT_TRUE(json) << r.out;
    EXPECT_EQ(json->find("input")->string, "-");
    EXPECT_EQ(json->find("input_format")->string, "pdb");
    EXPECT_EQ(json->find("output_format")->string, "ply");

    std::string err;
    EXPECT_EQ(run_pipeline("gzip -c " + shell_quote(crambin()) +
                               " | \"$FDMSURF\" - -o - --quiet > " + shell_quote(path("piped.ply")),
                           err),
              0)
        << err;
    EXPECT_TRUE(read_text(path("piped.ply")) == read_text(from_file));
}

TEST_F(CliFormats, StandardInputFormatComesFromTheContent) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    // PQR: whitespace-separated, charge and radius last (not PDB's occupancy and B columns).
    const std::string pqr =
        "ATOM      1  N   ALA     1      -0.677  -1.230  -0.491  0.1414 1.8240\n"
        "ATOM      2  CA  ALA     1       0.700  -1.230  -0.491  0.0962 1.9080\n";
    const std::vector<std::pair<std::string, std::string>> inputs = {{"atoms.txt", kTwoAtomsXyzr},
                                                                     {"atoms.pqr.txt", pqr}};
    for (const auto& [name, content] : inputs) {
        const std::string input = write_file(name, content);
        const CliRun r = run({"-", "-o", path(name + ".ply"), "--stats", "json"}, "", input);
        ASSERT_EQ(r.exit_code, 0) << name << ": " << r.err;
        const auto json = parse_json(lines_of(r.out).at(0));
        ASSERT_TRUE(json) << r.out;
        EXPECT_EQ(json->find("input_format")->string, name == "atoms.txt" ? "xyzr" : "pqr");
        EXPECT_EQ(json->find("atoms_used")->number, 2);
        fs::remove(path(name + ".ply"));
    }
    // --format still decides when given.
    const std::string input = write_file("xyzr.txt", kTwoAtomsXyzr);
    expect_failure(run({"-", "-o", path("x.ply"), "--format", "pdb"}, "", input), 3,
                   {"standard input"});
}

// A reader that goes away: an error naming standard output and the broken pipe, exit 3, no crash.
TEST_F(CliFormats, BrokenPipeIsAnErrorNotACrash) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    std::string err;
    const int code = run_pipeline(
        "\"$FDMSURF\" " + shell_quote(crambin()) + " -o - --quiet | head -c 10 >/dev/null", err);
    EXPECT_EQ(code, 3) << err;
    EXPECT_NE(err.find("fdmsurf: error: cannot write standard output: Broken pipe"),
              std::string::npos)
        << err;
    EXPECT_EQ(lines_of(err).size(), 1u) << err;
}

// /dev/stdout is standard output by another name: the mesh alone on it, as with '-o -' (the
// summary on stderr), never a file put in its place.
TEST_F(CliFormats, DevStdoutIsStandardOutput) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    std::string err;
    const int code = run_pipeline("\"$FDMSURF\" " + shell_quote(crambin()) +
                                      " -o /dev/stdout | cat > " + shell_quote(path("out.ply")),
                                  err);
    EXPECT_EQ(code, 0) << err;
    const std::string mesh = read_text(path("out.ply"));
    EXPECT_EQ(mesh.rfind("ply\n", 0), 0u) << mesh.substr(0, 40);
    EXPECT_EQ(mesh.find("ses surface of"), std::string::npos);  // no summary inside
    EXPECT_NE(err.find("ses surface of"), std::string::npos) << err;
    EXPECT_TRUE(fs::is_symlink("/dev/stdout") || fs::exists("/dev/stdout"));
}

// The summary itself on a closed pipe or a full disk: the reason is the write's, not a
// generic input/output error.
TEST_F(CliFormats, ASummaryThatCannotBeWrittenSaysWhy) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    std::string err;
    int code = run_pipeline("\"$FDMSURF\" " + shell_quote(crambin()) + " -o " +
                                shell_quote(path("a.ply")) + " | true",
                            err);
    EXPECT_EQ(code, 3) << err;
    EXPECT_NE(err.find("cannot write standard output: Broken pipe"), std::string::npos) << err;
    code = run_pipeline("\"$FDMSURF\" " + shell_quote(crambin()) + " -o " +
                            shell_quote(path("b.ply")) + " > /dev/full",
                        err);
    EXPECT_EQ(code, 3) << err;
    EXPECT_NE(err.find("cannot write standard output: No space left on device"),
              std::string::npos)
        << err;
    // --help and --version into a full disk: the same reason.
    for (const char* option : {"--help", "--version"}) {
        code = run_pipeline(std::string("\"$FDMSURF\" ") + option + " > /dev/full", err);
        EXPECT_EQ(code, 3) << err;
        EXPECT_NE(err.find("cannot write standard output: No space left on device"),
                  std::string::npos)
            << option << ": " << err;
    }
    // A summary longer than the stream's buffer (both paths about 3,800 characters of "./"):
    // the write fails inside the print, not at the flush, and says why all the same.
    std::string dots;
    for (int i = 0; i < 1900; ++i) dots += "./";
    const fs::path input = crambin();
    code = run_pipeline("\"$FDMSURF\" " +
                            shell_quote(input.parent_path().string() + "/" + dots +
                                        input.filename().string()) +
                            " -o " + shell_quote(path(dots + "c.ply")) + " > /dev/full",
                        err);
    EXPECT_EQ(code, 3) << err.substr(0, 300);
    EXPECT_NE(err.find("cannot write standard output: No space left on device"),
              std::string::npos)
        << err.substr(0, 300);
}

// A file past the size limit (ulimit -f): an error that leaves nothing, not a signal that kills
// the run with its temporary file behind.
TEST_F(CliFormats, AFileTooLargeIsAnErrorThatLeavesNothing) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    fs::create_directory(path("limited"));
    std::string err;
    const int code = run_pipeline("ulimit -f 100; \"$FDMSURF\" " + shell_quote(crambin()) +
                                      " -o " + shell_quote(path("limited/a.ply")),
                                  err);
    EXPECT_EQ(code, 3) << err;
    EXPECT_NE(err.find("File too large"), std::string::npos) << err;
    EXPECT_TRUE(fs::is_empty(path("limited")));
}

// The mesh and the areas file appear together or not at all: here the areas file passes the
// size limit after the (simplified, small) mesh was complete.
TEST_F(CliFormats, TheMeshAndTheAreasFileAppearTogether) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    fs::create_directory(path("limited"));
    std::string err;
    const int code = run_pipeline("ulimit -f 20; \"$FDMSURF\" " + shell_quote(crambin()) +
                                      " -o " + shell_quote(path("limited/a.ply")) +
                                      " --max-triangles 100 --areas " +
                                      shell_quote(path("limited/a.csv")) + " --quiet",
                                  err);
    EXPECT_EQ(code, 3) << err;
    EXPECT_NE(err.find("a.csv: File too large"), std::string::npos) << err;
    EXPECT_TRUE(fs::is_empty(path("limited")));
}

// Names up to the file system's 255 bytes are written (the temporary file's name is cut short
// to fit); a longer one is refused before any work, with the reason.
TEST_F(CliFormats, LongFileNamesUpToTheLimitAreWritten) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string too_long = std::string(252, 'c') + ".ply";  // 256 bytes
    expect_failure(run({crambin(), "-o", path(too_long), "--device", "no-such-device"}), 3,
                   {"its name is 256 bytes long; the file system allows 255"});
    expect_failure(run({crambin(), "-o", path("x.ply"), "--surface", "sas", "--areas",
                        path(std::string(252, 'a') + ".csv"), "--device", "no-such-device"}),
                   3, {"its name is 256 bytes long"});
    EXPECT_FALSE(fs::exists(path("x.ply")));
    const std::string longest = std::string(251, 'b') + ".ply";  // 255 bytes
    CliRun r = run({crambin(), "-o", path(longest), "--spacing", "1", "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_GT(fs::file_size(path(longest)), 1000u);
}

TEST_F(CliFormats, BadPipeCombinationsAndInputsAreClearErrors) {
    const std::string a = write_file("a.xyzr", kTwoAtomsXyzr);
    expect_failure(run({"-", "-", "-o", path("out/")}), 2, {"'-' (standard input)", "once"});
    expect_failure(run({a, a, "-o", "-"}), 2, {"-o -", "one INPUT"});
    expect_failure(run({"-", "--models", "all", "-o", "-"}), 2, {"--models all", "folder"});
    expect_failure(run({"-", "-o", path("x.ply")}), 3, {"standard input", "empty"});
    const std::string junk = write_file("junk", "hello\nworld\n");
    expect_failure(run({"-", "-o", path("x.ply")}, "", junk), 3,
                   {"standard input", "unknown format"});
    std::string binary;
    for (int c = 0; c < 4096; ++c) binary += char((c * 7) & 0xff);
    const std::string noise = write_file("noise", binary);
    expect_failure(run({"-", "-o", "-"}, "", noise), 3, {"standard input", "binary data"});
}

}  // namespace
