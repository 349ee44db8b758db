// Private: MASSID_AVX2_CLONES before a function definition compiles it twice,
// for AVX2 and for plain x86-64, the copy chosen at load time (GCC/Clang
// target_clones, an ifunc). Meant for loops over arrays of doubles with no
// fused multiply-add (AVX2 does not include FMA): both copies do the same
// operations in the same order, so they give the same bits. Empty off x86-64
// Linux, under AddressSanitizer (ifunc resolvers run before its runtime), and
// with -DMASSID_NO_CLONES (to compare the plain copy's bits). V4, load4 and
// store4 below are the lanes such loops work in.
#pragma once

#include <cstring>

#if defined(__x86_64__) && defined(__linux__) && defined(__has_attribute) && \
    !defined(__SANITIZE_ADDRESS__) && !defined(MASSID_NO_CLONES)
#if __has_attribute(target_clones)
#if defined(__has_feature)
#if !__has_feature(address_sanitizer)
#define MASSID_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#endif
#else
#define MASSID_AVX2_CLONES __attribute__((target_clones("avx2", "default")))
#endif
#endif
#endif
#ifndef MASSID_AVX2_CLONES
#define MASSID_AVX2_CLONES
#endif

namespace massid::detail {

// Four doubles: one AVX register, or two SSE2 registers where AVX is absent
// (GCC/Clang vector extensions); lane-wise, so the sums are the same either way.
using V4 = double __attribute__((vector_size(32)));

// (Loads through references: a function returning a V4 would have a
// different ABI with and without AVX.)
[[gnu::always_inline]] inline void load4(V4& x, const double* p) { std::memcpy(&x, p, sizeof x); }
[[gnu::always_inline]] inline void store4(double* p, const V4& x) { std::memcpy(p, &x, sizeof x); }

}  // namespace massid::detail
