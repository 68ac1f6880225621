// Tests of the fdmsurf program as a user runs it: exit codes, one error line, no stray output.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "cli/cli_program.hpp"
#include "cli/json_check.hpp"
#include "fdmsurf/fdmsurf.hpp"

namespace {

namespace fs = std::filesystem;
using fdmsurf_cli_test::CliProgram;
using fdmsurf_cli_test::CliRun;
using fdmsurf_cli_test::JsonValue;
using fdmsurf_cli_test::kDataDir;
using fdmsurf_cli_test::kTwoAtomsXyzr;
using fdmsurf_cli_test::lines_of;
using fdmsurf_cli_test::parse_json;
using fdmsurf_cli_test::read_text;

TEST_F(CliProgram, HelpListsOptionsAndExitCodes) {
    const CliRun r = run({"--help"});
    EXPECT_EQ(r.exit_code, 0);
    EXPECT_NE(r.out.find("Usage: fdmsurf INPUT -o OUTPUT"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("--spacing H"), std::string::npos);
    EXPECT_NE(r.out.find("Exit codes"), std::string::npos);
    EXPECT_EQ(r.err, "");
}

TEST_F(CliProgram, VersionPrintsTheLibraryVersionTheCommitAndWhetherItIsARelease) {
    const CliRun r = run({"--version"});
    EXPECT_EQ(r.exit_code, 0);
    const std::vector<std::string> lines = lines_of(r.out);
    ASSERT_EQ(lines.size(), 2u) << r.out;
    EXPECT_EQ(lines[0], std::string("fdmsurf ") + fdmsurf::version());
    EXPECT_EQ(lines[1].rfind("git commit ", 0), 0u) << lines[1];
    const bool release = lines[1].ends_with(": a release");
    EXPECT_TRUE(release || lines[1].find("not a release") != std::string::npos) << lines[1];
    EXPECT_EQ(r.err, "");
}

TEST_F(CliProgram, NoArgumentsIsAUsageError) { expect_failure(run({}), 2, {"missing INPUT"}); }

TEST_F(CliProgram, UnknownOptionIsAUsageError) {
    write_file("atoms.xyzr", kTwoAtomsXyzr);
    expect_failure(run({path("atoms.xyzr"), "-o", path("out.ply"), "--bogus"}), 2,
                   {"--bogus", "--help"});
}

TEST_F(CliProgram, MissingInputFile) {
    expect_failure(run({path("missing.pdb"), "-o", path("out.ply")}), 3, {"missing.pdb"});
}

TEST_F(CliProgram, EmptyInputFile) {
    const std::string input = write_file("empty.pdb", "");
    expect_failure(run({input, "-o", path("out.ply")}), 3, {"empty.pdb"});
}

TEST_F(CliProgram, BinaryInputFile) {
    std::string bytes;
    for (int repeat = 0; repeat < 16; ++repeat) {
        for (int c = 0; c < 256; ++c) bytes += static_cast<char>((c * 7 + repeat) & 0xff);
    }
    const std::string input = write_file("binary.pdb", bytes);
    expect_failure(run({input, "-o", path("out.ply")}), 3, {"binary.pdb"});
}

TEST_F(CliProgram, UnknownInputFormat) {
    const std::string input = write_file("junk.xyz", "this is not\na structure file 1 2 3\n");
    expect_failure(run({input, "-o", path("out.ply")}), 3, {"junk.xyz"});
}

TEST_F(CliProgram, UnknownOutputExtension) {
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    expect_failure(run({input, "-o", path("out.wrl")}), 2,
                   {"out.wrl", ".ply, .obj, .glb, .stl or .off", ".png", "--output-format"});
}

TEST_F(CliProgram, OutputInNonexistentFolder) {
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    expect_failure(run({input, "-o", path("no_such_folder/out.ply")}), 3, {"no_such_folder"});
    EXPECT_FALSE(fs::exists(path("no_such_folder")));
}

// -o FOLDER/ is created when missing (several inputs); a missing parent is an error.
TEST_F(CliProgram, OutputFolderIsCreatedButNotItsParents) {
    const std::string a = write_file("a.xyzr", kTwoAtomsXyzr);
    const std::string b = write_file("b.xyzr", kTwoAtomsXyzr);
    expect_failure(run({a, b, "-o", path("missing/meshes") + "/"}), 3,
                   {"missing", "does not exist"});
    EXPECT_FALSE(fs::exists(path("missing")));
    FDMSURF_REQUIRE_CLI_DEVICE();
    const CliRun r = run({a, b, "-o", path("meshes") + "/", "--spacing", "1.0", "--quiet"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(fs::exists(path("meshes/a.ply")));
    EXPECT_TRUE(fs::exists(path("meshes/b.ply")));
}

// Atoms smaller than the default grid and the FDM filter (APBS's ions of radius 0.32 Å): with
// no --spacing, the exact SES at a spacing that finds them, with a warning; with --spacing, the
// empty surface the user asked for, with its warning.
TEST_F(CliProgram, TinyAtomsGetTheExactSesAtAFinerSpacing) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string input = std::string(kDataDir) + "/lenient/ions.pqr";
    const CliRun r = run({input, "-o", path("ions.ply"), "--stats", "json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("computed at spacing 0.16 Å as the exact SES"), std::string::npos) << r.err;
    EXPECT_NE(r.out.find("\"method\":\"edt\""), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\"closed_manifold\":true"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("\"spacing\":0.16"), std::string::npos) << r.out;
    const CliRun given = run({input, "-o", path("given.ply"), "--spacing", "0.5", "--stats", "json"});
    ASSERT_EQ(given.exit_code, 0) << given.err;
    EXPECT_NE(given.err.find("the surface is empty"), std::string::npos) << given.err;
    EXPECT_NE(given.out.find("\"triangles\":0"), std::string::npos) << given.out;
}

TEST_F(CliProgram, ZeroSpacing) {
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    expect_failure(run({input, "-o", path("out.ply"), "--spacing", "0"}), 2, {"--spacing"});
    expect_failure(run({input, "-o", path("out.ply"), "--spacing=0"}), 2, {"--spacing"});
}

TEST_F(CliProgram, NegativeProbe) {
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    expect_failure(run({input, "-o", path("out.ply"), "--probe", "-1"}), 2, {"--probe"});
}

TEST_F(CliProgram, NanCoordinateInXyzr) {
    const std::string input = write_file("nan.xyzr", "0.0 0.0 0.0 1.7\n1.5 nan 0.0 1.52\n");
    expect_failure(run({input, "-o", path("out.ply")}), 3, {"nan.xyzr"});
}

TEST_F(CliProgram, InfiniteCoordinateInXyzr) {
    const std::string input = write_file("inf.xyzr", "0.0 0.0 0.0 1.7\n1.5 inf 0.0 1.52\n");
    expect_failure(run({input, "-o", path("out.ply")}), 3, {"inf.xyzr"});
}

TEST_F(CliProgram, NonNumericCoordinateInPdb) {
    const std::string input = write_file(
        "bad.pdb",
        "ATOM      1  N   THR A   1      17.047  14.099   3.625  1.00 13.79           N\n"
        "ATOM      2  CA  THR A   1      16.967  1x.784   4.338  1.00 10.80           C\n");
    expect_failure(run({input, "-o", path("out.ply")}), 3, {"bad.pdb"});
}

TEST_F(CliProgram, TruncatedPdbRecord) {
    const std::string input = write_file(
        "cut.pdb",
        "ATOM      1  N   THR A   1      17.047  14.099   3.625  1.00 13.79           N\n"
        "ATOM      2  CA  THR A   1      16.967  12.7");
    expect_failure(run({input, "-o", path("out.ply")}), 3, {"cut.pdb", "truncated"});
}

TEST_F(CliProgram, NoAtomsLeftAfterSelection) {
    const std::string input = write_file(
        "water.pdb",
        "HETATM    1  O   HOH A 101      17.047  14.099   3.625  1.00 13.79           O\n"
        "HETATM    2  O   HOH A 102      19.047  14.099   3.625  1.00 13.79           O\n"
        "END\n");
    expect_failure(run({input, "-o", path("out.ply")}), 3, {"water.pdb"});
}

TEST_F(CliProgram, NoVulkanDriverNamesThePackageToInstall) {
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    // The loader finds no driver when both variables point at nothing.
    const std::string env =
        "VK_ICD_FILENAMES=" + path("none.json") + " VK_DRIVER_FILES=" + path("none.json");
    expect_failure(run({input, "-o", path("out.ply")}, env), 4, {"mesa-vulkan-drivers"});
}

TEST_F(CliProgram, CoarseSpacingWarnsButSucceeds) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    const CliRun r = run({input, "-o", path("out.ply"), "--spacing", "3.0", "--quiet"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("too coarse"), std::string::npos) << r.err;
    EXPECT_TRUE(fs::exists(path("out.ply")));
}

// A surface with no triangles (a grid far coarser than the atoms) and coordinates where single
// precision is coarse are said, not silent; a normal run says neither.
TEST_F(CliProgram, EmptySurfacesAndFarCoordinatesAreWarned) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    CliRun r = run({input, "-o", path("out.ply"), "--spacing", "20", "--quiet"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("the surface is empty"), std::string::npos) << r.err;
    r = run({input, "-o", path("out.png"), "--spacing", "20", "--quiet"});  // on the device
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("the surface is empty"), std::string::npos) << r.err;
    const std::string far = write_file("far.xyzr", "1000000 1000000 1000000 1.5\n"
                                                   "1000001.5 1000000 1000000 1.5\n");
    r = run({far, "-o", path("far.ply"), "--surface", "vdw", "--quiet"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.err.find("coordinates reach 1e+06 Å from the origin, where single precision "
                         "steps by 0.062 Å"),
              std::string::npos)
        << r.err;
    r = run({input, "-o", path("near.ply"), "--quiet"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.err.find("warning"), std::string::npos) << r.err;
}

TEST_F(CliProgram, ListDevicesNeedsNoInput) {
    const CliRun r = run({"--list-devices"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out, "");
    EXPECT_TRUE(r.error_lines().empty()) << r.err;
    expect_failure(run({"--list-devices", "extra"}), 2, {"--list-devices takes no INPUT", "extra"});
}

TEST_F(CliProgram, CrambinSurfaceAsJson) {
    const fs::path crambin = kDataDir == nullptr ? fs::path() : fs::path(kDataDir) / "1crn.pdb";
    if (crambin.empty() || !fs::exists(crambin)) {
        GTEST_SKIP() << "tests/data/1crn.pdb is absent";
    }
    FDMSURF_REQUIRE_CLI_DEVICE();

    const std::string output = path("1crn.ply");
    const CliRun r = run({crambin.string(), "-o", output, "--stats", "json"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(r.error_lines().empty()) << r.err;
    const std::vector<std::string> lines = lines_of(r.out);
    ASSERT_EQ(lines.size(), 1u) << r.out;
    const auto json = parse_json(lines[0]);
    ASSERT_TRUE(json) << "not JSON: " << lines[0];
    const auto number = [&](const char* key) {
        const JsonValue* v = json->find(key);
        EXPECT_TRUE(v != nullptr && v->type == JsonValue::Type::Number) << key;
        return v != nullptr ? v->number : -1.0;
    };
    EXPECT_GT(number("atoms_used"), 0);
    EXPECT_GT(number("vertices"), 0);
    EXPECT_GT(number("triangles"), 0);
    EXPECT_GE(number("pieces"), 1);
    EXPECT_EQ(number("closed_pieces"), number("pieces"));
    EXPECT_EQ(number("boundary_edges"), 0);
    EXPECT_EQ(number("nonmanifold_edges"), 0);
    EXPECT_GT(number("area"), 0);
    EXPECT_GT(number("volume"), 0);
    ASSERT_NE(json->find("output"), nullptr);
    EXPECT_EQ(json->find("output")->string, output);
    EXPECT_EQ(json->find("surface")->string, "ses");
    EXPECT_TRUE(fs::exists(output));
    EXPECT_GT(fs::file_size(output), 0u);
}

TEST_F(CliProgram, QuietRunPrintsNothingAndWritesObj) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    const std::string output = path("atoms.obj");
    const CliRun r = run({input, "-o", output, "--quiet", "--spacing=0.4"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_EQ(r.out, "");
    EXPECT_TRUE(r.error_lines().empty()) << r.err;
    const std::string obj = read_text(output);
    EXPECT_NE(obj.find("\nv "), std::string::npos);
    EXPECT_NE(obj.find("\nf "), std::string::npos);
}

TEST_F(CliProgram, ModelsAllWithAFileOutputAsksForAFolder) {
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    expect_failure(run({input, "--models", "all", "-o", path("out.ply")}), 2,
                   {"--models all", "folder", "out.ply"});
}

TEST_F(CliProgram, AssemblyOutOfRangeNamesHowManyThereAre) {
    if (kDataDir == nullptr) GTEST_SKIP() << "no test data folder";
    const std::string crambin = (fs::path(kDataDir) / "1crn.pdb").string();
    expect_failure(run({crambin, "--assembly", "2", "-o", path("out.ply")}), 2,
                   {"1crn.pdb", "assembly 2", "1 assembly"});
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    expect_failure(run({input, "--assembly", "1", "-o", path("out.ply")}), 2,
                   {"atoms.xyzr", "no assemblies"});
}

TEST_F(CliProgram, AssemblyIsReportedInJson) {
    if (kDataDir == nullptr) GTEST_SKIP() << "no test data folder";
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string crambin = (fs::path(kDataDir) / "1crn.cif").string();
    const CliRun r = run(
        {crambin, "--assembly", "1", "-o", path("a1.ply"), "--stats", "json", "--spacing", "1.0"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const std::vector<std::string> lines = lines_of(r.out);
    ASSERT_EQ(lines.size(), 1u) << r.out;
    const auto json = parse_json(lines[0]);
    ASSERT_TRUE(json) << lines[0];
    EXPECT_EQ(json->find("assembly")->number, 1);
    EXPECT_EQ(json->find("assembly_name")->string, "1");
    EXPECT_EQ(json->find("atoms_used")->number, 327);
    EXPECT_TRUE(json->find("closed_manifold")->boolean);
}

// --models all: the 10 NMR models of 1D3Z through one engine, one closed mesh each.
TEST_F(CliProgram, ModelsAllWritesOneClosedMeshPerModel) {
    const fs::path ensemble = kDataDir == nullptr ? fs::path() : fs::path(kDataDir) / "1d3z.pdb.gz";
    if (ensemble.empty() || !fs::exists(ensemble))
        GTEST_SKIP() << "tests/data/1d3z.pdb.gz is absent";
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string folder = path("meshes") + "/";
    fs::create_directories(folder);
    const CliRun r = run({ensemble.string(), "--models", "all", "-o", folder, "--stats", "json",
                          "--spacing", "1.0"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(r.error_lines().empty()) << r.err;
    const std::vector<std::string> lines = lines_of(r.out);
    ASSERT_EQ(lines.size(), 10u) << r.out;
    std::vector<double> first_dims;
    for (int m = 1; m <= 10; ++m) {
        SCOPED_TRACE("model " + std::to_string(m));
        const auto json = parse_json(lines[static_cast<std::size_t>(m - 1)]);
        ASSERT_TRUE(json) << lines[static_cast<std::size_t>(m - 1)];
        EXPECT_EQ(json->find("model")->number, m);
        // One grid size for the whole ensemble (the largest model's): one FFT plan.
        std::vector<double> dims;
        for (const JsonValue& d : json->find("grid")->find("dims")->array) dims.push_back(d.number);
        if (m == 1) first_dims = dims;
        EXPECT_EQ(dims, first_dims);
        EXPECT_EQ(json->find("models_in_file")->number, 10);
        EXPECT_EQ(json->find("atoms_used")->number, 602);
        EXPECT_TRUE(json->find("closed_manifold")->boolean);
        // The engine starts once and the file is parsed once: both with the first model.
        const JsonValue& times = *json->find("times");
        EXPECT_EQ(times.find("init") != nullptr, m == 1);
        EXPECT_EQ(times.find("parse") != nullptr, m == 1);
        const std::string output = folder + "1d3z-m" + std::to_string(m) + ".ply";
        EXPECT_EQ(json->find("output")->string, output);
        ASSERT_TRUE(fs::exists(output));
        // The file on disk, read back: closed and manifold.
        const fdmsurf::MeshStats stats = fdmsurf::compute_stats(fdmsurf::read_mesh(output));
        EXPECT_GT(stats.triangles, 0u);
        EXPECT_TRUE(stats.is_closed_manifold());
        EXPECT_EQ(stats.triangles, static_cast<std::size_t>(json->find("triangles")->number));
    }
    std::size_t files = 0;
    for ([[maybe_unused]] const auto& entry : fs::directory_iterator(folder)) ++files;
    EXPECT_EQ(files, 10u);
}

// Several inputs with --stats json: one line per input, in order, the one that failed included
// (JSON Lines), and the run's exit code that of the failure.
TEST_F(CliProgram, SeveralInputsGiveOneJsonLineEachFailuresIncluded) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string crambin = std::string(kDataDir) + "/1crn.xyzr";
    const std::string folder = path("meshes") + "/";
    const std::string peptide = std::string(kDataDir) + "/3al1.pdb";
    const CliRun r = run({crambin, path("missing.pdb"), peptide, "-o", folder, "--stats", "json",
                          "--spacing", "1.0"});
    EXPECT_EQ(r.exit_code, 3) << r.err;
    const std::vector<std::string> lines = lines_of(r.out);
    ASSERT_EQ(lines.size(), 3u) << r.out;
    const auto ok = parse_json(lines[0]);
    const auto failed = parse_json(lines[1]);
    const auto last = parse_json(lines[2]);
    ASSERT_TRUE(ok && failed && last) << r.out;
    EXPECT_EQ(ok->find("status")->string, "ok");
    EXPECT_EQ(last->find("status")->string, "ok");
    EXPECT_EQ(last->find("input")->string, peptide);
    EXPECT_EQ(failed->find("status")->string, "failed");
    EXPECT_EQ(failed->find("input")->string, path("missing.pdb"));
    EXPECT_EQ(failed->find("output")->string, folder + "missing.ply");
    EXPECT_EQ(failed->find("error_code")->string, "io");
    EXPECT_EQ(failed->find("exit_code")->number, 3);
    EXPECT_NE(failed->find("error")->string.find("missing.pdb"), std::string::npos);
    // A single input that cannot be read has its line too, with --models all as without.
    for (const bool all : {false, true}) {
        std::vector<std::string> args = {path("missing.pdb"), "-o", folder, "--stats", "json"};
        if (all) args.insert(args.end(), {"--models", "all"});
        const CliRun one = run(args);
        EXPECT_EQ(one.exit_code, 3) << one.err;
        const auto line = parse_json(one.out);
        ASSERT_TRUE(line) << one.out;
        EXPECT_EQ(line->find("status")->string, "failed");
        EXPECT_EQ(line->find("exit_code")->number, 3);
    }
}

}  // namespace

// --refine through the program: the stage appears in the JSON times, the mesh has four times
// the triangles, and a bad level is a usage error before any work.
TEST_F(CliProgram, RefineQuadruplesTheTrianglesAndIsTimed) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    double triangles[2] = {0, 0};
    for (int level = 0; level < 2; ++level) {
        const std::string output = path("atoms" + std::to_string(level) + ".ply");
        const CliRun r =
            run({input, "-o", output, "--stats", "json", "--refine", std::to_string(level)});
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_TRUE(r.error_lines().empty()) << r.err;
        const auto json = parse_json(lines_of(r.out).at(0));
        ASSERT_TRUE(json) << r.out;
        triangles[level] = json->find("triangles")->number;
        EXPECT_EQ(json->find("times")->find("refine") != nullptr, level > 0) << r.out;
        EXPECT_EQ(json->find("closed_manifold")->boolean, true) << r.out;
    }
    EXPECT_EQ(triangles[1], 4 * triangles[0]);
}

TEST_F(CliProgram, RefineOutOfRangeIsAUsageError) {
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    expect_failure(run({input, "-o", path("out.ply"), "--refine", "5"}), 2,
                   {"--refine", "from 0 to 4", "got 5"});
    expect_failure(run({input, "-o", path("out.ply"), "--refine=-1"}), 2, {"--refine", "got -1"});
    expect_failure(run({input, "-o", path("out.ply"), "--refine", "0.5"}), 2,
                   {"--refine", "not a whole number"});
}

TEST_F(CliProgram, SimplifiedMeshIsClosedAndItsDeviationReported) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    const std::string full = path("full.ply"), simplified = path("simplified.ply");
    const CliRun a = run({input, "-o", full, "--stats", "json"});
    ASSERT_EQ(a.exit_code, 0) << a.err;
    const auto whole = parse_json(lines_of(a.out).at(0));
    ASSERT_TRUE(whole) << a.out;
    EXPECT_EQ(whole->find("simplify")->type, JsonValue::Type::Null);
    EXPECT_EQ(whole->find("optimized")->boolean, false);
    const CliRun r =
        run({input, "-o", simplified, "--stats", "json", "--simplify", "0.2", "--optimize"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(r.error_lines().empty()) << r.err;
    const auto json = parse_json(lines_of(r.out).at(0));
    ASSERT_TRUE(json) << r.out;
    const JsonValue& s = *json->find("simplify");
    ASSERT_EQ(s.type, JsonValue::Type::Object) << r.out;
    EXPECT_EQ(s.find("ratio")->number, 0.2);
    EXPECT_EQ(s.find("triangles_in")->number, whole->find("triangles")->number);
    EXPECT_EQ(s.find("triangles_out")->number, json->find("triangles")->number);
    EXPECT_LE(json->find("triangles")->number, 0.25 * whole->find("triangles")->number);
    EXPECT_EQ(s.find("topology_kept")->boolean, true);
    EXPECT_GT(s.find("hausdorff")->number, 0.0);
    EXPECT_LT(s.find("hausdorff")->number, 0.5);
    EXPECT_GT(s.find("rmsd")->number, 0.0);
    EXPECT_EQ(json->find("closed_manifold")->boolean, true) << r.out;
    EXPECT_EQ(json->find("optimized")->boolean, true);
    for (const char* stage : {"simplify", "simplify-compare", "optimize"}) {
        EXPECT_NE(json->find("times")->find(stage), nullptr) << stage;
    }
    const fdmsurf::Mesh mesh = fdmsurf::read_mesh(simplified);
    EXPECT_EQ(double(mesh.triangle_count()), json->find("triangles")->number);
    EXPECT_EQ(mesh.atoms.size(), mesh.vertex_count());
    // The text summary: the counts, and the distance to the full mesh.
    const CliRun text = run({input, "-o", path("text.ply"), "--max-triangles", "100"});
    ASSERT_EQ(text.exit_code, 0) << text.err;
    EXPECT_NE(text.out.find("  simplified   "), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("target 100), topology kept"), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("  deviation    Hausdorff "), std::string::npos) << text.out;
    EXPECT_NE(text.out.find("the collapses' estimate"), std::string::npos) << text.out;
    EXPECT_EQ(text.err.find("warning"), std::string::npos) << text.err;
    // A target no collapse can reach (a closed surface of one triangle): met as far as it
    // goes (crambin's surface: 20 triangles), and the run says why it stopped above it.
    ASSERT_NE(kDataDir, nullptr);
    const std::string crambin = (fs::path(kDataDir) / "1crn.pdb").string();
    const CliRun one = run({crambin, "-o", path("one.ply"), "--max-triangles", "1"});
    ASSERT_EQ(one.exit_code, 0) << one.err;
    EXPECT_NE(one.err.find("fdmsurf: warning: the simplified mesh has "), std::string::npos)
        << one.err;
    EXPECT_NE(one.err.find("triangles for a target of 1: every collapse left would change its "
                           "topology or turn a triangle over"),
              std::string::npos)
        << one.err;
    // meshoptimizer's collapses instead: also closed, and said so.
    const CliRun m = run({input, "-o", path("meshopt.ply"), "--stats", "json", "--simplify", "0.2",
                          "--simplifier", "meshopt"});
    ASSERT_EQ(m.exit_code, 0) << m.err;
    const auto mj = parse_json(lines_of(m.out).at(0));
    ASSERT_TRUE(mj) << m.out;
    EXPECT_EQ(mj->find("simplify")->find("simplifier")->string, "meshopt");
    EXPECT_EQ(mj->find("closed_manifold")->boolean, true) << m.out;
    EXPECT_EQ(s.find("simplifier")->string, "collapse");
}

TEST_F(CliProgram, SimplifyRatioOutsideZeroOneIsAUsageError) {
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    for (const char* value : {"0", "1.5", "-0.1"}) {
        expect_failure(run({input, "-o", path("out.ply"), "--simplify", value}), 2,
                       {"--simplify", "(0, 1]", std::string("got ") + value});
    }
    expect_failure(run({input, "-o", path("out.ply"), "--simplify", "half"}), 2,
                   {"--simplify", "not a number"});
    expect_failure(run({input, "-o", path("out.ply"), "--max-triangles", "0"}), 2,
                   {"--max-triangles", "got 0"});
}

TEST_F(CliProgram, ExactSesIsReportedAsTheEdtMethod) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string input = write_file("atoms.xyzr", kTwoAtomsXyzr);
    const std::string output = path("edt.ply");
    const CliRun r = run({input, "-o", output, "--stats", "json", "--method", "edt"});
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(r.error_lines().empty()) << r.err;
    const auto json = parse_json(lines_of(r.out).at(0));
    ASSERT_TRUE(json) << r.out;
    EXPECT_EQ(json->find("method")->string, "edt");
    EXPECT_EQ(json->find("closed_manifold")->boolean, true) << r.out;
    // The field: the device's pass, or on a CPU device the host's (--host-ses auto).
    const bool host_ses = json->find("grid")->find("host_ses_distance")->boolean;
    EXPECT_NE(json->find("times")->find(host_ses ? "ses-host" : "ses-distance"), nullptr) << r.out;
    EXPECT_EQ(json->find("times")->find(host_ses ? "ses-distance" : "ses-host"), nullptr) << r.out;
    EXPECT_EQ(json->find("times")->find("fft-forward"), nullptr) << r.out;
    EXPECT_TRUE(fs::exists(output));
    // The text summary names the method; FDM-only options are refused before any work.
    const CliRun text = run({input, "-o", path("edt2.ply"), "--method", "edt"});
    ASSERT_EQ(text.exit_code, 0) << text.err;
    EXPECT_NE(text.out.find("ses surface (exact, edt)"), std::string::npos) << text.out;
    fs::remove(output);
    fs::remove(path("edt2.ply"));
    expect_failure(run({input, "-o", path("edt3.ply"), "--method", "edt", "--cutoff", "0.2"}), 2,
                   {"--cutoff", "FDM method"});
}
