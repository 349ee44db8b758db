// sin and cos of several angles at once (the predictor's hot path): two lanes
// at a time in SSE2 (x86-64) or NEON (aarch64) registers (GCC/Clang vector
// extensions; four in AVX registers where the caller is compiled for AVX2),
// branch-free: Cody-Waite reduction by pi/2 in three parts, then fdlibm's
// minimax polynomials on [-pi/4, pi/4]. Within 1 ulp of std::sin/std::cos for
// |x| <= 2 pi, 2 ulp up to 1e5 rad (tests/test_sincos.cpp).
#pragma once

#include <cstring>

namespace massid::detail {

using Lanes = double __attribute__((vector_size(16)));   // two doubles (SSE2, NEON)
using Lanes4 = double __attribute__((vector_size(32)));  // four doubles (AVX)
// Their bit patterns, as 64-bit integers.
template <int Bytes>
struct BitsFor;
template <>
struct BitsFor<16> {
  using type = long long __attribute__((vector_size(16)));
};
template <>
struct BitsFor<32> {
  using type = long long __attribute__((vector_size(32)));
};

// Any lane width: the arithmetic is the same per lane (no fused multiply-add:
// -ffp-contract=off, CMakeLists.txt), so every width and architecture gives
// the same bits.
template <class V>
[[gnu::always_inline]] inline void sincos_lanes(const V& x, V& s, V& c) {
  using Bits = typename BitsFor<sizeof(V)>::type;
  const V round = V{} + 6755399441055744.0;  // 1.5 * 2^52: adding rounds
  const V kr = x * 0.63661977236758134308 + round;
  const V k = kr - round;                            // nearest integer to x 2/pi
  const V r = ((x - k * 1.57079632673412561417e+00)  // pi/2 in three parts
               - k * 6.07710050630396597660e-11) -
              k * 2.02226624871116645580e-21;
  // Polynomials by Estrin's scheme (pairs, then powers z^2, z^4): the
  // dependent chain is three multiply-adds deep rather than six (Horner).
  const V z = r * r, z2 = z * z, z4 = z2 * z2;
  const V sin_poly = ((-1.66666666666666324348e-01 + z * 8.33333333332248946124e-03) +
                      z2 * (-1.98412698298579493134e-04 + z * 2.75573137070700676789e-06)) +
                     z4 * (-2.50507602534068634195e-08 + z * 1.58969099521155010221e-10);
  const V sin_r = r + (r * z) * sin_poly;
  const V cos_poly = ((4.16666666666666019037e-02 + z * -1.38888888888741095749e-03) +
                      z2 * (2.48015872894767294178e-05 + z * -2.75573143513906633035e-07)) +
                     z4 * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11);
  // 1 - z/2 loses the low bits of z/2; fdlibm adds them back: (1 - w) - z/2.
  const V half_z = 0.5 * z, w = 1.0 - half_z;
  const V cos_r = w + (((1.0 - w) - half_z) + z2 * cos_poly);
  // Quadrant k mod 4 from the low bits of x 2/pi + 1.5 * 2^52, whose last
  // mantissa bits hold k: bit 0 swaps sin and cos, bit 1 of k (of k + 1) is
  // the sign of sin (of cos).
  // (Casts between vector types of one size keep the bits.)
  const Bits bits = (Bits)kr, sin_bits = (Bits)sin_r, cos_bits = (Bits)cos_r;
  const Bits swap = -(bits & 1);  // all ones where k is odd
  const Bits diff = (sin_bits ^ cos_bits) & swap;
  const Bits sign = Bits{} + static_cast<long long>(0x8000000000000000ULL);
  s = (V)(sin_bits ^ diff ^ ((bits << 62) & sign));
  c = (V)(cos_bits ^ diff ^ (((bits + 1) << 62) & sign));
}

// s[i], c[i] = sin(x[i]), cos(x[i]) for i < n; n a multiple of the lane
// count of V (pad the arrays).
template <class V = Lanes>
[[gnu::always_inline]] inline void sincos_many(const double* x, double* s, double* c, int n) {
  constexpr int kLanes = sizeof(V) / sizeof(double);
  for (int i = 0; i < n; i += kLanes) {
    V xs, ss, cs;
    std::memcpy(&xs, x + i, sizeof(V));
    sincos_lanes(xs, ss, cs);
    std::memcpy(s + i, &ss, sizeof(V));
    std::memcpy(c + i, &cs, sizeof(V));
  }
}

}  // namespace massid::detail
