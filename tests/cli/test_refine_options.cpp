// Tests of the --refine option: parsing, the range and its messages, the help text.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cli/options.hpp"
#include "cli/usage.hpp"

namespace {

using fdmsurf::Error;
using fdmsurf::ErrorCode;
using fdmsurf::cli::parse_args;

std::string refine_error(const std::string& value) {
    try {
        parse_args({"in.pdb", "-o", "out.ply", "--refine", value});
    } catch (const Error& e) {
        EXPECT_EQ(e.code(), ErrorCode::InvalidArgument) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "no error for --refine " << value;
    return {};
}

bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

TEST(CliRefine, LevelsInBothSpellings) {
    EXPECT_EQ(parse_args({"in.pdb", "-o", "out.ply"}).surface.refine, 0);
    EXPECT_EQ(parse_args({"in.pdb", "-o", "out.ply", "--refine", "2"}).surface.refine, 2);
    EXPECT_EQ(parse_args({"in.pdb", "-o", "out.ply", "--refine=1"}).surface.refine, 1);
    EXPECT_EQ(parse_args({"in.pdb", "-o", "out.ply", "--refine", "+4"}).surface.refine, 4);
    EXPECT_EQ(parse_args({"in.pdb", "-o", "out.ply", "--refine", "0"}).surface.refine, 0);
    EXPECT_EQ(
        parse_args({"in.pdb", "-o", "out.ply", "--refine", "3", "--refine", "1"}).surface.refine,
        1);
}

TEST(CliRefine, NegativeTooLargeAndNonIntegerAreRejected) {
    for (const char* value : {"-1", "5", "64"}) {
        const std::string message = refine_error(value);
        EXPECT_TRUE(
            contains(message, "option --refine must be a whole number of levels from 0 to 4"))
            << message;
        EXPECT_TRUE(contains(message, std::string("(got ") + value + ")")) << message;
    }
    for (const char* value : {"1.5", "two", "1e1", "2x", " 1"}) {
        const std::string message = refine_error(value);
        EXPECT_TRUE(contains(message, "--refine")) << message;
        EXPECT_TRUE(contains(message, "not a whole number")) << message;
    }
    EXPECT_TRUE(contains(refine_error("99999999999"), "out of range"));
    try {
        parse_args({"in.pdb", "-o", "out.ply", "--refine"});
        ADD_FAILURE() << "no error for a missing value";
    } catch (const Error& e) {
        EXPECT_TRUE(contains(e.what(), "--refine needs a value")) << e.what();
    }
}

TEST(CliRefine, HelpDescribesIt) {
    const std::string help = fdmsurf::cli::usage_text();
    EXPECT_TRUE(contains(help, "--refine N")) << help;
    EXPECT_TRUE(contains(help, "0 to 4, default 0")) << help;
}

}  // namespace
