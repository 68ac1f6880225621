// Tests of --color, --properties and --patch: parsing, the refusals (exit 2 with the choices,
// exit 3 for a patch that selects nothing, nothing written) and a run whose PLY carries the atom,
// colours and scalars, read back.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli/options.hpp"
#include "cli/parse_check.hpp"
#include "fdmsurf/fdmsurf.hpp"

namespace {

namespace fs = std::filesystem;
using namespace fdmsurf;
using fdmsurf::cli::parse_args;

using fdmsurf_cli_test::contains;
using fdmsurf_cli_test::parse_error_with;
using fdmsurf_cli_test::parse_with;

TEST(CliProperties, ColourSchemesAndHexColours) {
    EXPECT_EQ(parse_with({}).surface.properties.color, ColorScheme::None);
    EXPECT_EQ(parse_with({"--color", "chain"}).surface.properties.color, ColorScheme::Chain);
    EXPECT_EQ(parse_with({"--colour=Coulombic"}).surface.properties.color, ColorScheme::Coulombic);
    const PropertyOptions p = parse_with({"--color", "#ff8000"}).surface.properties;
    EXPECT_EQ(p.color, ColorScheme::Uniform);
    EXPECT_EQ(p.rgb, (std::array<std::uint8_t, 3>{255, 128, 0}));
    const std::string e = parse_error_with({"--color", "rainbow"});
    EXPECT_TRUE(contains(e, "unknown colour scheme 'rainbow'")) << e;
    for (const char* scheme : {"chain", "element", "residue", "hydrophobicity", "bfactor",
                               "coulombic", "#RRGGBB"})
        EXPECT_TRUE(contains(e, scheme)) << e;
    EXPECT_TRUE(contains(parse_error_with({"--color", "#12345"}), "unknown colour scheme"));
}

TEST(CliProperties, PropertyListsInOrderOnce) {
    const std::vector<VertexProperty> p =
        parse_with({"--properties", "shape_index,coulombic,bfactor"}).surface.properties.scalars;
    EXPECT_EQ(p, (std::vector<VertexProperty>{VertexProperty::ShapeIndex, VertexProperty::Coulombic,
                                              VertexProperty::BFactor}));
    const std::string e = parse_error_with({"--properties", "coulombic,charge"});
    EXPECT_TRUE(contains(e, "unknown vertex property 'charge'")) << e;
    EXPECT_TRUE(contains(e, "mean_curvature")) << e;
    EXPECT_TRUE(contains(parse_error_with({"--properties", "bfactor,bfactor"}), "listed twice"));
    EXPECT_EQ(parse_with({"--patch", "A/1-20"}).patch, "A/1-20");
}

#if defined(FDMSURF_CLI_PATH) && defined(FDMSURF_TEST_DATA_DIR)

struct PropRun {
    int exit_code = -1;
    std::string err, out;
};

class CliPropertyRuns : public ::testing::Test {
protected:
    void SetUp() override {
        dir_ = fs::temp_directory_path() /
               ("fdmsurf-props-" + std::string(::testing::UnitTest::GetInstance()
                                                   ->current_test_info()
                                                   ->name()));
        fs::remove_all(dir_);
        fs::create_directories(dir_);
    }
    void TearDown() override { fs::remove_all(dir_); }

    PropRun run(const std::string& input, const std::string& args) {
        const fs::path err = dir_ / "stderr.txt", out = dir_ / "stdout.txt";
        const std::string command = std::string(FDMSURF_CLI_PATH) + " " + FDMSURF_TEST_DATA_DIR +
                                    "/" + input + " " + args + " --quiet 2> " + err.string() +
                                    " > " + out.string();
        const int status = std::system(command.c_str());
        PropRun r;
        if (WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
        const auto text_of = [](const fs::path& path) {
            std::ifstream in(path);
            std::ostringstream text;
            text << in.rdbuf();
            return text.str();
        };
        r.err = text_of(err);
        r.out = text_of(out);
        fs::remove(err);
        fs::remove(out);
        return r;
    }
    fs::path dir_;
};

TEST_F(CliPropertyRuns, BadSchemeOrEmptyPatchWritesNothing) {
    const fs::path out = dir_ / "x.ply";
    PropRun r = run("1crn.pdb", "-o " + out.string() + " --color rainbow");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "expected chain, element")) << r.err;
    r = run("1crn.pdb", "-o " + out.string() + " --patch Z");
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_TRUE(contains(r.err, "--patch 'Z' matches none of the 327 atoms")) << r.err;
    r = run("1crn.xyzr", "-o " + out.string() + " --color residue");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "not bare XYZR atoms")) << r.err;
    r = run("1crn.pdb", "-o " + out.string() + " --patch '('");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "--patch")) << r.err;
    EXPECT_FALSE(fs::exists(out));
    EXPECT_EQ(std::distance(fs::directory_iterator(dir_), fs::directory_iterator()), 0);
}

TEST_F(CliPropertyRuns, WarnsWhereAPropertyIsUniformOrAFormatDropsIt) {
    const fs::path ply = dir_ / "x.ply", obj = dir_ / "x.obj";
    PropRun r = run("1crn.xyzr", "-o " + ply.string() + " --color element");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "the atoms carry no elements")) << r.err;
    r = run("1crn.xyzrn", "-o " + ply.string() + " --properties bfactor");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "every atom's B-factor is 0")) << r.err;
    r = run("1crn.pdb", "-o " + obj.string() + " --properties coulombic");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "OBJ has no place for per-vertex atoms")) << r.err;
    // STL has no colours at all; the summary names one colour by its value.
    const fs::path stl = dir_ / "x.stl";
    r = run("1crn.pdb", "-o " + stl.string() + " --color '#123456' --stats json");
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_TRUE(contains(r.err, "STL has no place for colours")) << r.err;
    EXPECT_TRUE(contains(r.out, "\"color\":\"#123456\"")) << r.out;
    r = run("1crn.pdb", "-o " + ply.string() + " --color '#123456'");
    EXPECT_FALSE(contains(r.err, "no place for colours")) << r.err;
}

TEST_F(CliPropertyRuns, PatchOfOneChainIsOpenAndColoured) {
    const fs::path whole = dir_ / "whole.ply", patch = dir_ / "patch.ply";
    ASSERT_EQ(run("3al1.pdb", "-o " + whole.string() + " --color chain --properties "
                                  "coulombic,mean_curvature")
                  .exit_code,
              0);
    const PropRun r = run("3al1.pdb", "-o " + patch.string() + " --color chain --patch A");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    const Mesh w = read_mesh(whole.string()), p = read_mesh(patch.string());
    ASSERT_EQ(w.atoms.size(), w.vertex_count());
    ASSERT_EQ(w.colors.size(), 3 * w.vertex_count());
    ASSERT_EQ(w.scalars.size(), 2u);
    EXPECT_EQ(w.scalars[0].name, "coulombic");
    EXPECT_EQ(w.scalars[1].name, "mean_curvature");
    const Structure s = read_structure(std::string(FDMSURF_TEST_DATA_DIR) + "/3al1.pdb");
    ASSERT_LT(p.triangle_count(), w.triangle_count());
    ASSERT_GT(p.triangle_count(), 0u);
    for (std::uint32_t a : p.atoms) ASSERT_EQ(s.atoms.meta[a].chain, "A");
    EXPECT_GT(compute_stats(p).boundary_edges, 0u);  // open where chain B covered it
}

#endif

}  // namespace
