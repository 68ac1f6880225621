// Tests of the input options --chains, --select and --format xyzrn: parsing, help, and runs
// whose input is refused before any device starts.
#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "cli/options.hpp"
#include "cli/usage.hpp"
#include "cli/parse_check.hpp"

namespace {

using fdmsurf::Error;
using fdmsurf::ErrorCode;
using fdmsurf::StructureFormat;
using fdmsurf::cli::CliOptions;
using fdmsurf::cli::parse_args;

using fdmsurf_cli_test::contains;
using fdmsurf_cli_test::parse_error_with;
using fdmsurf_cli_test::parse_with;

TEST(CliInput, ChainsAreACommaSeparatedList) {
    EXPECT_TRUE(parse_with({}).read.chains.empty());
    EXPECT_EQ(parse_with({"--chains", "A"}).read.chains, (std::vector<std::string>{"A"}));
    EXPECT_EQ(parse_with({"--chains=A,B,a"}).read.chains,
              (std::vector<std::string>{"A", "B", "a"}));
    EXPECT_EQ(parse_with({"--chains", "A1,A1,B2"}).read.chains,
              (std::vector<std::string>{"A1", "B2"}));  // repeats dropped
    for (const char* bad : {"A,,B", ",A", "A,", ",", "A B"}) {
        SCOPED_TRACE(bad);
        EXPECT_TRUE(contains(parse_error_with({"--chains", bad}),
                             "option --chains: '" + std::string(bad) +
                                 "' is not a comma-separated list of chain ids"));
    }
    EXPECT_TRUE(contains(parse_error_with({"--chains"}), "option --chains needs a value"));
}

TEST(CliInput, SelectIsPassedAsGiven) {
    EXPECT_TRUE(parse_with({}).read.select.empty());
    EXPECT_EQ(parse_with({"--select", "A/10-50/CA[C]"}).read.select, "A/10-50/CA[C]");
    EXPECT_EQ(parse_with({"--select=;b>20"}).read.select, ";b>20");
    // Syntax is the library's to check (when the file is read).
    EXPECT_EQ(parse_with({"--select", "CA[Qq]"}).read.select, "CA[Qq]");
}

TEST(CliInput, XyzrnFormat) {
    EXPECT_EQ(parse_with({"--format", "xyzrn"}).read.format, StructureFormat::Xyzrn);
    EXPECT_EQ(parse_with({"--format=XYZRN"}).read.format, StructureFormat::Xyzrn);
    EXPECT_TRUE(
        contains(parse_error_with({"--format", "xyz"}), "expected pdb, cif, pqr, xyzr or xyzrn"));
}

TEST(CliInput, HelpDescribesTheInputOptions) {
    const std::string help = fdmsurf::cli::usage_text();
    for (const char* text :
         {"--chains A,B", "--select EXPR", "pdb|cif|pqr|xyzr|xyzrn", "XYZRN", "A/10-50", ";b>20"})
        EXPECT_TRUE(contains(help, text)) << text;
}

#if defined(FDMSURF_CLI_PATH) && defined(FDMSURF_TEST_DATA_DIR)

struct CliResult {
    int exit_code = -1;
    std::string out, err;
};

std::string slurp(const std::filesystem::path& path) {
    std::ifstream in(path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
}

// Runs fdmsurf on a file of tests/data with `args`; the output goes to a temporary folder.
CliResult run_cli(const std::string& input, const std::string& args) {
    namespace fs = std::filesystem;
    const fs::path dir = fs::temp_directory_path() /
                         ("fdmsurf_cli_input_" + std::to_string(::getpid()) + "_" +
                          ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir);
    const std::string command = std::string(FDMSURF_CLI_PATH) + " " + FDMSURF_TEST_DATA_DIR + "/" +
                                input + " -o " + (dir / "out.ply").string() + " " + args + " >" +
                                (dir / "stdout").string() + " 2>" + (dir / "stderr").string() +
                                " </dev/null";
    const int status = std::system(command.c_str());
    CliResult r;
    if (status != -1 && WIFEXITED(status)) r.exit_code = WEXITSTATUS(status);
    r.out = slurp(dir / "stdout");
    r.err = slurp(dir / "stderr");
    EXPECT_FALSE(fs::exists(dir / "out.ply")) << "a failed run left its output";
    std::error_code ec;
    fs::remove_all(dir, ec);
    return r;
}

TEST(CliInput, UnknownChainFailsWithTheChainsPresent) {
    const CliResult r = run_cli("3al1.pdb", "--chains A,Q");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "fdmsurf: error:")) << r.err;
    EXPECT_TRUE(contains(r.err, "chain Q is not in model 1; chains present: A, B, (blank)"))
        << r.err;
    EXPECT_TRUE(r.out.empty()) << r.out;
}

TEST(CliInput, BadSelectionFailsAsAUsageError) {
    const CliResult r = run_cli("1crn.pdb", "--select 'CA[Qq]'");
    EXPECT_EQ(r.exit_code, 2) << r.err;
    EXPECT_TRUE(contains(r.err, "bad selection 'CA[Qq]'")) << r.err;
}

TEST(CliInput, EmptySelectionIsAnInputError) {
    const CliResult r = run_cli("1crn.pdb", "--select '(HOH)'");
    EXPECT_EQ(r.exit_code, 3) << r.err;
    EXPECT_TRUE(contains(r.err, "no atoms left after selection")) << r.err;
}

#endif

}  // namespace
