// Tests of the program's restart with transparent huge pages (src/cli/huge_pages.cpp): when it
// restarts, that it restarts once with the tunable added to the user's, that the user's choice
// and FDMSURF_HUGE_PAGES=0 keep it from restarting, and that the surface is the same either way.
#include <gtest/gtest.h>

#include <sys/resource.h>

#include <cstdio>
#include <string>

#include "cli/cli_program.hpp"
#include "cli/huge_pages.hpp"

namespace {

using fdmsurf_cli_test::CliProgram;
using fdmsurf_cli_test::CliRun;
using fdmsurf_cli_test::lines_of;
using fdmsurf_cli_test::read_text;

// Whether the program restarts on this host (the program's own test of the host and the build,
// which tests and program share).
bool host_restarts() { return fdmsurf::cli::huge_pages_on_request(); }

int count_lines(const std::string& text, const std::string& part) {
    int n = 0;
    for (const std::string& line : lines_of(text)) n += line.find(part) != std::string::npos;
    return n;
}

class HugePages : public CliProgram {};

TEST_F(HugePages, RestartsOnceWithTheTunableAddedToTheUsers) {
    const CliRun r = run({"--version"}, "FDMSURF_TRACE=1 GLIBC_TUNABLES=glibc.malloc.perturb=0");
    ASSERT_EQ(r.exit_code, 0) << r.err;
    EXPECT_NE(r.out.find("fdmsurf"), std::string::npos) << r.out;
    if (!host_restarts()) {
        // glibc < 2.35, THP mode not madvise, or a sanitizer build: no restart, none tried.
        // (Not a skip: the sanitized CI run counts skipped tests as not run.)
        std::printf("  no restart on this host: checked that none is tried\n");
        EXPECT_EQ(count_lines(r.err, "huge pages"), 0) << r.err;
        return;
    }
    // Once: the restarted program finds the tunable set and goes on.
    EXPECT_EQ(count_lines(r.err,
                          "huge pages: restarting with "
                          "GLIBC_TUNABLES=glibc.malloc.perturb=0:glibc.malloc.hugetlb=1"),
              1)
        << r.err;
    EXPECT_EQ(count_lines(r.err, "huge pages"), 1) << r.err;
}

TEST_F(HugePages, TheUsersChoiceAndTheOptOutKeepItFromRestarting) {
    for (const std::string env : {"FDMSURF_TRACE=1 GLIBC_TUNABLES=glibc.malloc.hugetlb=0",
                                  "FDMSURF_TRACE=1 FDMSURF_HUGE_PAGES=0"}) {
        const CliRun r = run({"--version"}, env);
        ASSERT_EQ(r.exit_code, 0) << r.err;
        EXPECT_EQ(count_lines(r.err, "huge pages"), 0) << env << "\n" << r.err;
    }
}

// Minor page faults of the children run since the last call.
long child_faults() {
    static long last = 0;
    rusage u{};
    getrusage(RUSAGE_CHILDREN, &u);
    const long delta = u.ru_minflt - last;
    last = u.ru_minflt;
    return delta;
}

// The same mesh either way, and where the program restarts, the effect it is for: far fewer
// first-touch page faults (1CRN on the 2-core VM: about 6,500 against 12,600).
TEST_F(HugePages, TheSurfaceIsTheSameWithAndWithout) {
    FDMSURF_REQUIRE_CLI_DEVICE();
    const std::string input = std::string(fdmsurf_cli_test::kDataDir) + "/1crn.pdb";
    child_faults();
    const CliRun with = run({input, "-o", path("with.ply"), "--quiet"});
    ASSERT_EQ(with.exit_code, 0) << with.err;
    const long faults_with = child_faults();
    const CliRun without =
        run({input, "-o", path("without.ply"), "--quiet"}, "FDMSURF_HUGE_PAGES=0");
    ASSERT_EQ(without.exit_code, 0) << without.err;
    const long faults_without = child_faults();
    std::printf("  minor page faults: %ld with huge pages, %ld without\n", faults_with,
                faults_without);
    if (host_restarts()) {
        EXPECT_LT(double(faults_with), 0.8 * double(faults_without));
    }
    const std::string a = read_text(path("with.ply")), b = read_text(path("without.ply"));
    EXPECT_GT(a.size(), 100000u);
    EXPECT_TRUE(a == b) << "the two runs' PLY files differ";
}

}  // namespace
