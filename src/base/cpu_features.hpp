// What the CPU running the program can do, for the code paths compiled for more than the
// baseline x86-64 the library is built for: functions cloned for AVX2 or POPCNT
// (target_clones, the CPU's choice made at load) or marked __attribute__((target("avx2"))).
#pragma once

// A function compiled twice where GCC can pick one at run time: for AVX2 (which does not enable
// fused multiply-adds, so every lane rounds as the portable version's) and the portable one.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define FDMSURF_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define FDMSURF_AVX2_CLONES
#endif

// A function compiled twice for the POPCNT instruction and without it: std::popcount is a call
// into libgcc on the baseline x86-64 (marching cubes' vertex lookups make hundreds of millions).
// The floating-point code is the same in both (no wider vectors, no fused multiply-adds).
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define FDMSURF_POPCNT_CLONES __attribute__((target_clones("popcnt", "default")))
#else
#define FDMSURF_POPCNT_CLONES
#endif

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
