// base/decimal.hpp: the readers' fast path gives from_chars's double, bit for bit, or declines.
#include "base/decimal.hpp"

#include <gtest/gtest.h>

#include <charconv>
#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "structure/detail.hpp"

namespace {

using fdmsurf::detail::NumberStatus;
using fdmsurf::detail::parse_decimal_fast;
using fdmsurf::detail::parse_number;

std::uint64_t bits(double v) {
    std::uint64_t b = 0;
    std::memcpy(&b, &v, sizeof b);
    return b;
}

// parse_number as it was before the fast path: from_chars alone.
NumberStatus parse_number_from_chars(std::string_view s, double& value) {
    if (s.size() > 1 && s[0] == '+' && s[1] != '-') s.remove_prefix(1);
    if (s.empty()) return NumberStatus::NotNumber;
    auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), value);
    if (end != s.data() + s.size()) return NumberStatus::NotNumber;
    if (ec == std::errc::result_out_of_range) return NumberStatus::OutOfRange;
    if (ec != std::errc()) return NumberStatus::NotNumber;
    if (!std::isfinite(value)) return NumberStatus::NotFinite;
    return std::isfinite(static_cast<float>(value)) ? NumberStatus::Ok : NumberStatus::OutOfRange;
}

// Where the fast path answers, from_chars reads the whole string to the same bits; and
// parse_number (fast path first) gives the status and bits it gave with from_chars alone.
// Returns whether the fast path answered.
bool check(const std::string& s) {
    double fast = 0.0;
    const bool answered = parse_decimal_fast(s, fast);
    if (answered) {
        double slow = 0.0;
        auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), slow);
        EXPECT_TRUE(ec == std::errc() && end == s.data() + s.size()) << "'" << s << "'";
        EXPECT_EQ(bits(fast), bits(slow)) << "'" << s << "'";
    }
    double now = -1.0, before = -1.0;
    const NumberStatus status_now = parse_number(s, now);
    const NumberStatus status_before = parse_number_from_chars(s, before);
    EXPECT_EQ(status_now, status_before) << "'" << s << "'";
    if (status_now == NumberStatus::Ok && status_before == NumberStatus::Ok) {
        EXPECT_EQ(bits(now), bits(before)) << "'" << s << "'";
        EXPECT_EQ(bits(double(float(now))), bits(double(float(before)))) << "'" << s << "'";
    }
    return answered;
}

TEST(Decimal, EdgeCasesMatchFromChars) {
    const char* const cases[] = {
        "0", "-0", "0.0", "-0.0", "+0", "+1.5", "+-1", "++1", "-+1", "+", "-", ".", "-.", "+.",
        ".5", "-.5", "+.5", "5.", "-5.", "5.e3", ".e3", "e3", "1e", "1e+", "1e-", "1E5", "1e+05",
        "1e-05", "1.5e22", "1.5e23", "1e-22", "1e-23", "1e0000", "1e00001", "12e-0022",
        "9007199254740992", "9007199254740993", "-9007199254740993", "900719925474099.3",
        "1234567890123456789", "12345678901234567890", "0.1234567890123456789",
        "00000000000000000001", "0000000000000000000.1", "1.7976931348623157e308", "1e309",
        "3.4028235e38", "3.4028236e38", "1e39", "1e-46", "1e-400", "4.9e-324", "inf", "-inf",
        "nan", "NaN", "infinity", "0x1p3", "1,5", "1.5 ", " 1.5", "1.5x", "1..5", "1.5.", "--1",
        "1e5.5", "12.345", "-1000.000", "999.999", "0.001", "-0.001", "1.85", "2.000",
        "123456.789", "0.5e-3", "7e22", "7e-22", "99999999999999999e5", "0.30000000000000004",
        "2.2250738585072014e-308", "1e+0", "1E-0"};
    for (const char* s : cases) check(s);
}

TEST(Decimal, TypicalCoordinatesTakeTheFastPath) {
    for (const char* s : {"12.345", "-1000.000", "0.5", "1.85", "-0.004", "17", "1e-3", ".5"})
        EXPECT_TRUE(check(s)) << s;
}

// Random decimals of every shape the files hold and more: 1 to 21 digits with the point
// anywhere or nowhere, signs, exponents of 0 to 3 digits with and without signs.
TEST(Decimal, RandomDecimalsMatchFromChars) {
    std::mt19937_64 rng(36);
    auto pick = [&](int n) { return int(rng() % std::uint64_t(n)); };
    std::size_t answered = 0, total = 0;
    for (int i = 0; i < 400000; ++i) {
        std::string s;
        const int sign = pick(5);
        if (sign == 0) s += '-';
        if (sign == 1) s += '+';
        const int digits = 1 + pick(21);
        const int point = pick(digits + 2) - 1;  // -1: no point; digits: point at the end
        for (int d = 0; d < digits; ++d) {
            if (d == point) s += '.';
            s += char('0' + (pick(4) == 0 ? 0 : pick(10)));
        }
        if (point == digits) s += '.';
        if (pick(3) == 0) {
            s += pick(2) ? 'e' : 'E';
            const int esign = pick(3);
            if (esign == 1) s += '-';
            if (esign == 2) s += '+';
            const int edigits = pick(4);
            for (int d = 0; d < edigits; ++d) s += char('0' + pick(10));
        }
        answered += check(s);
        ++total;
        if (::testing::Test::HasFailure()) break;
    }
    // Most of them take the fast path: the test is of it, not only of the fallback.
    EXPECT_GT(answered, total / 3);
}

// Every coordinate of a %8.3f file within +-10000 A, and radii with 1 to 6 decimals.
TEST(Decimal, FixedPointValuesMatchFromChars) {
    std::mt19937_64 rng(7);
    char text[64];
    for (int i = 0; i < 200000; ++i) {
        const double v = (double(rng() % 20000001) - 10000000.0) / 1000.0;
        std::snprintf(text, sizeof text, "%.3f", v);
        EXPECT_TRUE(check(text)) << text;
        std::snprintf(text, sizeof text, "%.*f", 1 + int(rng() % 6), double(rng() % 4000) / 997.0);
        EXPECT_TRUE(check(text)) << text;
        if (::testing::Test::HasFailure()) break;
    }
}

}  // namespace
