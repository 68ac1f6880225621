// What the CPU running the program can do, for the code paths compiled for more than the
// baseline x86-64 the library is built for (functions with __attribute__((target("avx2")))).
#pragma once

namespace fdmsurf::detail {

// Whether the CPU has AVX2 (false off x86-64 and for other compilers): asked once.
inline bool has_avx2() {
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    static const bool avx2 = __builtin_cpu_supports("avx2");
    return avx2;
#else
    return false;
#endif
}

}  // namespace fdmsurf::detail
