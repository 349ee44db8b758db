// Private: which vector paths the predictors have. On x86-64 (MASSID_X86) the
// two-lane path runs in SSE2 registers and a four-lane copy, compiled for
// AVX2, is taken at run time where cpu_has_avx2(); elsewhere (aarch64: NEON)
// the two-lane path alone, chosen at compile time. Both are GCC/Clang vector
// extensions doing the same operations per lane, and the tree is compiled with
// -ffp-contract=off (and, on aarch64, -U__ARM_FEATURE_FMA for Eigen:
// CMakeLists.txt), so every path gives the same bits, on either architecture
// (docs/embedding-arm.md, tests/test_predictor_reference.cpp).
#pragma once

#include <cstring>
#include <memory>
#include <type_traits>

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

// A copy of a compiled predictor (Predictor, MotionPredictor; the plan's
// definition, *_plan.hpp, included) that takes the four-lane path (only where
// cpu_has_avx2()) or the two-lane path: for the tests that compare the two.
template <class Predictor>
Predictor with_four_lanes(const Predictor& predictor, bool four_lanes) {
  Predictor out = predictor;
  auto plan = std::make_shared<std::remove_cvref_t<decltype(*predictor.plan)>>(*predictor.plan);
  plan->four_lanes = four_lanes && cpu_has_avx2();
  out.plan = std::move(plan);
  return out;
}

// A double, or a vector of lanes of doubles, loaded from and stored to
// (possibly unaligned) memory. Always inlined, the AVX2 copies' four-lane
// vectors included, so GCC's note that passing those by value depends on
// -mavx concerns no real call.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wpsabi"
template <class V>
[[gnu::always_inline]] inline V load(const double* p) {
  V v;
  std::memcpy(&v, p, sizeof v);
  return v;
}
template <class V>
[[gnu::always_inline]] inline void store(double* p, const V& v) {
  std::memcpy(p, &v, sizeof v);
}
// v in every lane of V (written lane by lane: V{} + v would add 0, not free).
template <class V>
[[gnu::always_inline]] inline V splat(double v) {
  V r;
  for (int l = 0; l < static_cast<int>(sizeof(V) / sizeof(double)); ++l) r[l] = v;
  return r;
}
#pragma GCC diagnostic pop

}  // namespace massid::detail
