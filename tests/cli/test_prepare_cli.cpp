// Tests of `fdmsurf prepare` (src/cli/prepare_command.cpp): its usage errors, and on a device the
// plans it builds into the plan cache and reads back on a second run.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "cli/cli_program.hpp"

namespace {

using fdmsurf_cli_test::CliProgram;
using fdmsurf_cli_test::CliRun;
using fdmsurf_cli_test::lines_of;

class PrepareCli : public CliProgram {};

TEST_F(PrepareCli, HelpDescribesTheCommand) {
    const CliRun r = run({"prepare", "--help"});
    EXPECT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("usage: fdmsurf prepare"), std::string::npos) << r.out;
    EXPECT_NE(r.out.find("--natural-grid"), std::string::npos) << r.out;
    EXPECT_EQ(r.err, "");
    // The main usage lists the command.
    EXPECT_NE(run({"--help"}).out.find("fdmsurf prepare"), std::string::npos);
}

TEST_F(PrepareCli, BadArgumentsAreUsageErrors) {
    expect_failure(run({"prepare", "--frobnicate"}), 2, {"prepare", "--frobnicate"});
    expect_failure(run({"prepare", "1crn.pdb"}), 2, {"prepare", "1crn.pdb"});
    expect_failure(run({"prepare", "--device"}), 2, {"--device", "needs a value"});
    expect_failure(run({"prepare", "--device", "--quiet"}), 2, {"--device", "needs a value"});
    expect_failure(run({"prepare", "--device="}), 2, {"--device", "needs a value"});
}

TEST_F(PrepareCli, BuildsEveryPlanIntoThePlanCacheThenReadsThem) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string env = "FDMSURF_CACHE_DIR=" + path("plans");
    const CliRun first = run({"prepare"}, env);
    ASSERT_EQ(first.exit_code, 0) << first.err;
    int built = 0;
    for (const std::string& line : lines_of(first.out)) {
        if (line.rfind("FFT ", 0) == 0) {
            EXPECT_NE(line.find("plan built and cached"), std::string::npos) << line;
            ++built;
        }
    }
    EXPECT_EQ(built, 7) << first.out;
    EXPECT_NE(first.out.find("FFT 112x112x112"), std::string::npos) << first.out;
    std::size_t entries = 0;
    for (const auto& e : std::filesystem::directory_iterator(path("plans")))
        entries += e.is_regular_file();
    EXPECT_GE(entries, 7u);

    // Again, under the validation layer (its messages would be errors): every plan from the cache.
    const CliRun second = run({"prepare", "--validation"}, env);
    ASSERT_EQ(second.exit_code, 0) << second.err;
    int read = 0;
    for (const std::string& line : lines_of(second.out))
        read += line.rfind("FFT ", 0) == 0 &&
                line.find("read from the plan cache") != std::string::npos;
    EXPECT_EQ(read, 7) << second.out;
    EXPECT_EQ(run({"prepare", "--quiet"}, env).out, "");
}

TEST_F(PrepareCli, ACacheThatCannotBeWrittenIsSaid) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    // A file where the cache's parent folder would be: nothing can be stored.
    std::ofstream(path("file")) << "x";
    const CliRun r = run({"prepare"}, "FDMSURF_CACHE_DIR=" + path("file") + "/plans");
    ASSERT_EQ(r.exit_code, 0) << r.err;  // the cache is an optimisation
    EXPECT_NE(r.err.find("warning: the plan cache " + path("file") + "/plans cannot be written"),
              std::string::npos)
        << r.err;
    int not_cached = 0;
    for (const std::string& line : lines_of(r.out)) {
        if (line.rfind("FFT ", 0) != 0) continue;
        not_cached += line.find("not cached (the cache cannot be written)") != std::string::npos;
        EXPECT_EQ(line.find("plan built and cached"), std::string::npos) << line;
        EXPECT_EQ(line.find(" ms  "), 23u) << line;  // one column, 112x112x112 too
    }
    EXPECT_EQ(not_cached, 7) << r.out;
}

}  // namespace
