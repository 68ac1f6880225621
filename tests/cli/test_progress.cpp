// The progress line: where each stage puts the bar, and a run that shows it on stderr (forced by
// FDMSURF_PROGRESS=always, since ctest's stderr is no terminal) while stdout keeps its JSON.
#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "cli/progress.hpp"

namespace {

using fdmsurf::cli::Progress;
namespace fs = std::filesystem;

TEST(Progress, StagesFillTheBarInPipelineOrder) {
    EXPECT_DOUBLE_EQ(Progress::fraction_after("parse"), 0.05);
    EXPECT_LT(Progress::fraction_after("bin-atoms"),
              Progress::fraction_after("density, filter, marching cubes"));
    // Slabs: field and marching cubes interleave, along z.
    EXPECT_DOUBLE_EQ(Progress::fraction_after("field slab 1/3"), 0.15 + 0.20);
    EXPECT_DOUBLE_EQ(Progress::fraction_after("field slab 3/3"), 0.75);
    EXPECT_DOUBLE_EQ(Progress::fraction_after("marching cubes, z 200/400"), 0.45);
    EXPECT_LT(Progress::fraction_after("cavities"), Progress::fraction_after("write"));
    EXPECT_DOUBLE_EQ(Progress::fraction_after("mesh-stats"), 1.0);
    EXPECT_DOUBLE_EQ(Progress::fraction_after("something else"), 0.0);
    Progress off(false);  // a disabled bar does nothing at all
    off.begin("x");
    off.stage("parse");
    off.end();
}

#if defined(FDMSURF_CLI_PATH) && defined(FDMSURF_TEST_DATA_DIR)

std::string slurp(const fs::path& p) {
    std::ifstream in(p);
    std::ostringstream s;
    s << in.rdbuf();
    return s.str();
}

TEST(Progress, ALongRunShowsItOnStderrOnly) {
    const fs::path dir = fs::temp_directory_path() / "fdmsurf-progress";
    fs::remove_all(dir);
    fs::create_directories(dir);
    // The line shows from the start (FDMSURF_PROGRESS_AFTER=0), and at each stage's end: on a
    // GPU the whole run takes a fraction of a second.
    const std::string run = std::string(FDMSURF_CLI_PATH) + " " + FDMSURF_TEST_DATA_DIR +
                            "/4hhb.pdb.gz -o " + (dir / "h.ply").string() +
                            " --method edt --stats json";
    const std::string cmd = "FDMSURF_PROGRESS=always FDMSURF_PROGRESS_AFTER=0 " + run + " > " + (dir / "out").string() +
                            " 2> " + (dir / "err").string();
    const int status = std::system(cmd.c_str());
    ASSERT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << slurp(dir / "err");
    const std::string out = slurp(dir / "out"), err = slurp(dir / "err");
    EXPECT_EQ(out.front(), '{');
    EXPECT_EQ(out.find("fdmsurf ["), std::string::npos);
    EXPECT_NE(err.find("fdmsurf ["), std::string::npos) << err;
    EXPECT_NE(err.find("ses-features"), std::string::npos) << err;
    ASSERT_GE(err.size(), 4u);
    EXPECT_EQ(err.substr(err.size() - 4), "\r\033[K");  // cleared before the summary
    // --quiet turns it off whatever the environment says.
    const std::string quiet = "FDMSURF_PROGRESS=always FDMSURF_PROGRESS_AFTER=0 " + run + " --quiet > /dev/null 2> " +
                              (dir / "err2").string();
    ASSERT_EQ(std::system(quiet.c_str()), 0);
    EXPECT_EQ(slurp(dir / "err2"), "");
    // With the mesh on standard output the JSON goes to stderr, alone: no progress there.
    const std::string piped = "FDMSURF_PROGRESS=always FDMSURF_PROGRESS_AFTER=0 " +
                              std::string(FDMSURF_CLI_PATH) + " " + FDMSURF_TEST_DATA_DIR +
                              "/4hhb.pdb.gz -o - --method edt --stats json > " +
                              (dir / "mesh").string() + " 2> " + (dir / "err3").string();
    ASSERT_EQ(std::system(piped.c_str()), 0);
    const std::string err3 = slurp(dir / "err3");
    ASSERT_FALSE(err3.empty());
    EXPECT_EQ(err3.front(), '{') << err3.substr(0, 200);
    EXPECT_EQ(err3.find('\r'), std::string::npos);
    EXPECT_EQ(err3.find("fdmsurf ["), std::string::npos);
    fs::remove_all(dir);
}

#endif

}  // namespace
