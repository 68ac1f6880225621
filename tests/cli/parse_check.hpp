// Test helper: parse_args on the arguments of a normal run plus some options, and the message
// of the InvalidArgument error it throws.
#pragma once

#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "cli/options.hpp"

namespace fdmsurf_cli_test {

// The arguments of a normal run ("in.pdb -o out.ply") followed by `extra`.
inline fdmsurf::cli::CliOptions parse_with(std::vector<std::string> extra) {
    std::vector<std::string> args{"in.pdb", "-o", "out.ply"};
    args.insert(args.end(), extra.begin(), extra.end());
    return fdmsurf::cli::parse_args(args);
}

// The message of the InvalidArgument error parse_with(extra) throws, or a test failure.
inline std::string parse_error_with(std::vector<std::string> extra) {
    try {
        parse_with(std::move(extra));
    } catch (const fdmsurf::Error& e) {
        EXPECT_EQ(e.code(), fdmsurf::ErrorCode::InvalidArgument) << e.what();
        return e.what();
    }
    ADD_FAILURE() << "no error thrown";
    return {};
}

inline bool contains(const std::string& text, const std::string& part) {
    return text.find(part) != std::string::npos;
}

}  // namespace fdmsurf_cli_test
