// Tests of --simplify, --max-triangles, --simplifier and --optimize: parsing, ranges and messages,
// help text.
#include <gtest/gtest.h>

#include <limits>
#include <string>
#include <vector>

#include "cli/options.hpp"
#include "cli/usage.hpp"
#include "cli/parse_check.hpp"
#include "simplify/simplify_detail.hpp"

namespace {

using fdmsurf_cli_test::contains;
using fdmsurf_cli_test::parse_error_with;
using fdmsurf_cli_test::parse_with;

TEST(CliSimplify, OffUnlessAsked) {
    const auto o = parse_with({});
    EXPECT_FALSE(o.simplify_requested);
    EXPECT_FALSE(o.optimize);
    EXPECT_EQ(o.simplify.ratio, 1.0);
    EXPECT_EQ(o.simplify.max_triangles, 0u);
}

TEST(CliSimplify, RatioAndCountInBothSpellings) {
    auto o = parse_with({"--simplify", "0.1"});
    EXPECT_TRUE(o.simplify_requested);
    EXPECT_EQ(o.simplify.ratio, 0.1);  // parsed as a double: exactly the decimal's double
    o = parse_with({"--simplify=1"});
    EXPECT_TRUE(o.simplify_requested);
    EXPECT_EQ(o.simplify.ratio, 1.0);
    o = parse_with({"--simplify", "+2.5e-1"});
    EXPECT_EQ(o.simplify.ratio, 0.25);
    o = parse_with({"--max-triangles", "50000"});
    EXPECT_TRUE(o.simplify_requested);
    EXPECT_EQ(o.simplify.max_triangles, 50000u);
    EXPECT_EQ(o.simplify.ratio, 1.0);
    o = parse_with({"--max-triangles=7", "--optimize"});
    EXPECT_EQ(o.simplify.max_triangles, 7u);
    EXPECT_TRUE(o.optimize);
    o = parse_with({"--optimize"});
    EXPECT_TRUE(o.optimize);
    EXPECT_FALSE(o.simplify_requested);
}

TEST(CliSimplify, BothGivenTheSmallerTargetWins) {
    const auto o = parse_with({"--simplify", "0.5", "--max-triangles", "1000"});
    EXPECT_EQ(o.simplify.ratio, 0.5);
    EXPECT_EQ(o.simplify.max_triangles, 1000u);
    EXPECT_EQ(fdmsurf::detail::simplify_target(10000, o.simplify), 1000u);
    EXPECT_EQ(fdmsurf::detail::simplify_target(1500, o.simplify), 750u);
}

TEST(CliSimplify, RatioOutsideZeroOneIsRejectedNamingTheOption) {
    for (const char* value : {"0", "-0.5", "1.5", "2", "-0"}) {
        const std::string message = parse_error_with({"--simplify", value});
        EXPECT_TRUE(contains(message,
                             "option --simplify must be the fraction of the triangles to keep, "
                             "in (0, 1]"))
            << message;
        EXPECT_TRUE(contains(message, std::string("(got ") + value + ")")) << message;
    }
    for (const char* value : {"abc", "0.1x", "10%", "1/2", " 0.5"}) {
        const std::string message = parse_error_with({"--simplify", value});
        EXPECT_TRUE(contains(message, "option --simplify: '")) << message;
        EXPECT_TRUE(contains(message, "is not a number")) << message;
    }
    for (const char* value : {"nan", "inf"}) {
        const std::string message = parse_error_with({"--simplify", value});
        EXPECT_TRUE(contains(message, "--simplify")) << message;
        EXPECT_TRUE(contains(message, "not a finite number")) << message;
    }
    EXPECT_TRUE(contains(parse_error_with({"--simplify"}), "--simplify needs a value"));
    EXPECT_TRUE(
        contains(parse_error_with({"--simplify", "--optimize"}), "--simplify needs a value"));
    EXPECT_TRUE(contains(parse_error_with({"--optimize=1"}), "--optimize takes no value"));
}

TEST(CliSimplify, MaxTrianglesMustBeAPositiveWholeNumber) {
    for (const char* value : {"0", "-5", "-0", "-99999999999", "-999999999999999999999999"}) {
        const std::string message = parse_error_with({"--max-triangles", value});
        EXPECT_TRUE(
            contains(message, "option --max-triangles must be a whole number of triangles >= 1"))
            << message;
        EXPECT_TRUE(contains(message, std::string("(got ") + value + ")")) << message;
    }
    for (const char* value : {"2.5", "1e6", "many"}) {
        const std::string message = parse_error_with({"--max-triangles", value});
        EXPECT_TRUE(contains(message, "--max-triangles")) << message;
        EXPECT_TRUE(contains(message, "not a whole number")) << message;
    }
    // An upper bound: any count, however large (beyond 2^64, none).
    EXPECT_EQ(parse_with({"--max-triangles", "99999999999"}).simplify.max_triangles,
              99999999999u);
    EXPECT_EQ(parse_with({"--max-triangles", "999999999999999999999999"}).simplify.max_triangles,
              std::numeric_limits<std::size_t>::max());
    for (const char* value : {"-x", "-", "-5x", "-+5"}) {
        EXPECT_TRUE(contains(parse_error_with({"--max-triangles", value}), "not a whole number"))
            << value;
    }
}

TEST(CliSimplify, SimplifierIsCollapseUnlessMeshoptIsAsked) {
    EXPECT_EQ(parse_with({"--simplify", "0.1"}).simplify.simplifier,
              fdmsurf::Simplifier::kCollapse);
    EXPECT_EQ(parse_with({"--simplify", "0.1", "--simplifier", "meshopt"}).simplify.simplifier,
              fdmsurf::Simplifier::kMeshopt);
    EXPECT_EQ(parse_with({"--max-triangles", "10", "--simplifier=collapse"}).simplify.simplifier,
              fdmsurf::Simplifier::kCollapse);
    std::string message = parse_error_with({"--simplify", "0.1", "--simplifier", "qem"});
    EXPECT_TRUE(contains(message, "--simplifier")) << message;
    EXPECT_TRUE(contains(message, "collapse or meshopt")) << message;
    EXPECT_TRUE(contains(parse_error_with({"--simplify", "0.1", "--simplifier"}),
                         "--simplifier needs a value"));
    message = parse_error_with({"--simplifier", "meshopt"});
    EXPECT_TRUE(contains(message,
                         "--simplifier chooses how --simplify or --max-triangles "
                         "simplify"))
        << message;
}

TEST(CliSimplify, HelpDescribesTheOptions) {
    const std::string help = fdmsurf::cli::usage_text();
    for (const char* part : {"--simplify RATIO", "0 < RATIO <= 1", "--max-triangles N",
                             "the smaller of the two targets", "--optimize", "Hausdorff",
                             "--simplifier NAME", "collapse (default", "meshopt"}) {
        EXPECT_TRUE(contains(help, part)) << part;
    }
    EXPECT_TRUE(contains(parse_error_with({"--simplfy", "0.5"}), "did you mean --simplify?"));
}

}  // namespace
