// Decimal numbers as structure files write them ("12.345", "-0.5", "1e-3"), read to the same
// double as std::from_chars but without its general machinery: the readers' hot loop.
//
// Clinger's fast path (W. D. Clinger, "How to read floating point numbers accurately", PLDI
// 1990): a decimal m x 10^e whose integer m fits in 53 bits and whose |e| <= 22 is m times or
// divided by 10^|e|, both exact doubles, so one IEEE operation rounds it once, correctly, to the
// double that from_chars gives. Everything else is left to from_chars.
#pragma once

#include <cstdint>
#include <string_view>

namespace fdmsurf::detail {

// `s` whole as [-]digits[.digits][(e|E)[+|-]digits] (digits on at least one side of the point,
// as from_chars takes them) into `value`, and true; false, `value` untouched, where the fast
// path cannot be sure: another shape, more than 19 digits, a mantissa above 2^53, an exponent
// beyond +-22. No leading '+' (from_chars takes none either).
inline bool parse_decimal_fast(std::string_view s, double& value) {
    static constexpr double kPow10[] = {1e0,  1e1,  1e2,  1e3,  1e4,  1e5,  1e6,  1e7,
                                        1e8,  1e9,  1e10, 1e11, 1e12, 1e13, 1e14, 1e15,
                                        1e16, 1e17, 1e18, 1e19, 1e20, 1e21, 1e22};
    const char* p = s.data();
    const char* const end = p + s.size();
    const bool negative = p != end && *p == '-';
    if (negative) ++p;
    std::uint64_t m = 0;
    const char* const first = p;
    while (p != end && static_cast<unsigned char>(*p - '0') < 10)
        m = 10 * m + std::uint64_t(*p++ - '0');
    // All digits, leading zeros too: at most 19 keeps m below 10^19 < 2^64.
    int digits = int(p - first);
    int exponent = 0;
    if (p != end && *p == '.') {
        const char* const fraction = ++p;
        while (p != end && static_cast<unsigned char>(*p - '0') < 10)
            m = 10 * m + std::uint64_t(*p++ - '0');
        exponent = -int(p - fraction);
        digits -= exponent;
    }
    if (digits == 0 || digits > 19) return false;
    if (p != end && (*p == 'e' || *p == 'E')) {
        ++p;
        const bool minus = p != end && *p == '-';
        if (p != end && (*p == '-' || *p == '+')) ++p;
        const char* const start = p;
        int e = 0;
        while (p != end && static_cast<unsigned char>(*p - '0') < 10 && p - start < 4)
            e = 10 * e + (*p++ - '0');
        if (p == start) return false;  // "1e", "1e+": from_chars stops before the 'e'
        exponent += minus ? -e : e;
    }
    if (p != end || m > (std::uint64_t{1} << 53) || exponent < -22 || exponent > 22) return false;
    double v = static_cast<double>(m);  // exact: m <= 2^53
    v = exponent < 0 ? v / kPow10[-exponent] : v * kPow10[exponent];
    value = negative ? -v : v;
    return true;
}

}  // namespace fdmsurf::detail
