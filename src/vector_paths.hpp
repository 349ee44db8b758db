// Private: which vector paths the predictors have. On x86-64 (MASSID_X86) the
// two-lane path runs in SSE2 registers and a four-lane copy, compiled for
// AVX2, is taken at run time where cpu_has_avx2(); elsewhere (aarch64: NEON)
// the two-lane path alone, chosen at compile time. Both are GCC/Clang vector
// extensions doing the same operations per lane, and the tree is compiled with
// -ffp-contract=off (CMakeLists.txt), so every path gives the same bits from
// the same compiled predictor (docs/embedding-arm.md: the constants compiled on
// aarch64 may still differ in the last bits).
#pragma once

#if defined(__x86_64__)
#define MASSID_X86 1
#else
#define MASSID_X86 0
#endif

namespace massid::detail {

// Whether this CPU runs the four-lane (AVX2) paths; false off x86-64.
inline bool cpu_has_avx2() {
#if MASSID_X86
  return __builtin_cpu_supports("avx2");
#else
  return false;
#endif
}

}  // namespace massid::detail
