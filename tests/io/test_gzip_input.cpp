// Tests of the one gzip reader (io/gzip_input): members, trailing bytes, and what goes wrong.
#include <gtest/gtest.h>
#include <zlib.h>

#include <string>

#include "io/gzip_input.hpp"

namespace fdmsurf::detail {
namespace {

// One gzip member holding `plain`.
std::string gzip_member(const std::string& plain) {
    z_stream zs{};
    EXPECT_EQ(deflateInit2(&zs, 9, Z_DEFLATED, 16 + MAX_WBITS, 8, Z_DEFAULT_STRATEGY), Z_OK);
    std::string out(deflateBound(&zs, uLong(plain.size())) + 32, '\0');
    zs.next_in = reinterpret_cast<Bytef*>(const_cast<char*>(plain.data()));
    zs.avail_in = uInt(plain.size());
    zs.next_out = reinterpret_cast<Bytef*>(out.data());
    zs.avail_out = uInt(out.size());
    EXPECT_EQ(deflate(&zs, Z_FINISH), Z_STREAM_END);
    out.resize(zs.total_out);
    deflateEnd(&zs);
    return out;
}

std::string text(std::size_t lines) {
    std::string s;
    for (std::size_t i = 0; i < lines; ++i) s += "ATOM " + std::to_string(i * 7919 % 1000) + "\n";
    return s;
}

TEST(GzipInput, MagicBytes) {
    EXPECT_TRUE(is_gzip(gzip_member("x")));
    EXPECT_FALSE(is_gzip(""));
    EXPECT_FALSE(is_gzip("\x1f"));
    EXPECT_FALSE(is_gzip("OFF\n"));
}

TEST(GzipInput, InflatesConcatenatedMembersAndIgnoresTrailingBytes) {
    const std::string a = text(20000), b = text(3);
    std::string out;
    GzipProblem problem;
    ASSERT_TRUE(gunzip(gzip_member(a), out, problem));
    EXPECT_EQ(out, a);
    out.clear();
    ASSERT_TRUE(gunzip(gzip_member(a) + gzip_member(b), out, problem));
    EXPECT_EQ(out, a + b);
    out.clear();
    ASSERT_TRUE(gunzip(gzip_member(b) + "garbage", out, problem));
    EXPECT_EQ(out, b);
    out.clear();
    ASSERT_TRUE(gunzip(gzip_member(b) + "\x1f", out, problem));
    EXPECT_EQ(out, b);
    out.clear();
    ASSERT_TRUE(gunzip(gzip_member(""), out, problem));
    EXPECT_EQ(out, "");
    EXPECT_EQ(problem.kind, GzipProblem::Kind::None);
}

TEST(GzipInput, TellsTruncatedFromCorrupt) {
    const std::string gz = gzip_member(text(500));
    std::string out;
    GzipProblem problem;
    for (const std::size_t keep : {std::size_t{2}, std::size_t{10}, gz.size() / 2, gz.size() - 1}) {
        EXPECT_FALSE(gunzip(gz.substr(0, keep), out, problem)) << keep;
        EXPECT_EQ(problem.kind, GzipProblem::Kind::Truncated) << keep;
    }
    // A member that starts after the first and stops short is truncated too.
    EXPECT_FALSE(gunzip(gz + gz.substr(0, 12), out, problem));
    EXPECT_EQ(problem.kind, GzipProblem::Kind::Truncated);

    std::string bad_method = gz;
    bad_method[2] = 7;  // compression method 7: not deflate
    EXPECT_FALSE(gunzip(bad_method, out, problem));
    EXPECT_EQ(problem.kind, GzipProblem::Kind::Corrupt);
    EXPECT_EQ(problem.zlib_message, "unknown compression method");

    std::string bad_crc = gz;
    bad_crc[gz.size() - 8] ^= 1;  // the trailer's CRC-32
    EXPECT_FALSE(gunzip(bad_crc, out, problem));
    EXPECT_EQ(problem.kind, GzipProblem::Kind::Corrupt);
    EXPECT_EQ(problem.zlib_message, "incorrect data check");
}

}  // namespace
}  // namespace fdmsurf::detail
