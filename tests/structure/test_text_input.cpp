// split_fields (structure/text_input.cpp), 16 bytes a step for ASCII lines, against its
// byte-at-a-time reference on lines of every length and kind of white space.
#include <gtest/gtest.h>

#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "structure/detail.hpp"

namespace fdmsurf::detail {
namespace {

TEST(SplitFields, AsTheByteAtATimeReference) {
    std::mt19937 random(17);
    // White space of every kind, printable bytes, a NUL, DEL and bytes from 0x80.
    const std::string bytes = std::string(" \t\v\f\r\n") + "  ATOMHETATM-1.25e+3_x" +
                              std::string(1, '\0') + "\x7f\x85\xa0\xc3\xa9";
    std::vector<std::string_view> fast, plain;
    for (int n = 0; n < 200000; ++n) {
        const std::size_t length = random() % 140;  // past the 128 bytes of the fast route
        std::string line;
        for (std::size_t i = 0; i < length; ++i) {
            // ASCII (the fast route), one line in 16 with any byte of the set.
            const std::size_t pick = random() % (n % 16 == 0 ? bytes.size() : bytes.size() - 4);
            line += bytes[pick];
        }
        split_fields(line, fast);
        split_fields_plain(line, plain);
        ASSERT_EQ(fast, plain) << "line of " << line.size() << " bytes";
        for (std::size_t k = 0; k < fast.size(); ++k)  // the same bytes of the line, not copies
            ASSERT_EQ(fast[k].data(), plain[k].data());
    }
    split_fields(std::string_view(), fast);
    EXPECT_TRUE(fast.empty());
    split_fields("  ATOM \t 1\r", fast);
    EXPECT_EQ(fast, (std::vector<std::string_view>{"ATOM", "1"}));
}

}  // namespace
}  // namespace fdmsurf::detail
