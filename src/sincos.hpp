// sin and cos of several angles at once (the predictor's hot path), without
// branches or calls: Cody-Waite reduction by pi/2 in three parts, then fdlibm's
// minimax polynomials on [-pi/4, pi/4]. Within 1 ulp of std::sin/std::cos for
// |x| < 1e5 rad (joint angles are far inside); about as fast as libm per
// angle, but inlined and free of the call and the slow-path branches.
#pragma once

namespace massid::detail {

inline void sincos_many(const double* x, double* s, double* c, int n) {
  constexpr double kTwoOverPi = 0.63661977236758134308;
  constexpr double kPio2_1 = 1.57079632673412561417e+00;  // first 33 bits of pi/2
  constexpr double kPio2_2 = 6.07710050630396597660e-11;  // next 33 bits
  constexpr double kPio2_3 = 2.02226624871116645580e-21;  // the rest
  constexpr double kRound = 6755399441055744.0;           // 1.5 * 2^52: adding rounds to integer
  for (int i = 0; i < n; ++i) {
    const double k = (x[i] * kTwoOverPi + kRound) - kRound;  // nearest integer
    const double r = ((x[i] - k * kPio2_1) - k * kPio2_2) - k * kPio2_3;
    const double z = r * r;
    const double sin_r =
        r +
        r * z *
            (-1.66666666666666324348e-01 +
             z * (8.33333333332248946124e-03 +
                  z * (-1.98412698298579493134e-04 +
                       z * (2.75573137070700676789e-06 +
                            z * (-2.50507602534068634195e-08 + z * 1.58969099521155010221e-10)))));
    const double cos_r =
        1.0 - 0.5 * z +
        z * z *
            (4.16666666666666019037e-02 +
             z * (-1.38888888888741095749e-03 +
                  z * (2.48015872894767294178e-05 +
                       z * (-2.75573143513906633035e-07 +
                            z * (2.08757232129817482790e-09 + z * -1.13596475577881948265e-11)))));
    // Quadrant q = k mod 4, in doubles: floor(k / 4) = round(k / 4 - 0.375).
    const double q = k - 4.0 * ((k * 0.25 - 0.375 + kRound) - kRound);
    const bool odd = q == 1.0 || q == 3.0;
    const double sin_sign = q >= 2.0 ? -1.0 : 1.0;
    const double cos_sign = (q == 1.0 || q == 2.0) ? -1.0 : 1.0;
    s[i] = sin_sign * (odd ? cos_r : sin_r);
    c[i] = cos_sign * (odd ? sin_r : cos_r);
  }
}

}  // namespace massid::detail
