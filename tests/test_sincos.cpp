// The predictor's vectorised sin/cos (src/core/sincos.hpp) against libm, and the
// two-lane (SSE2) and four-lane (AVX2) forms against each other.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <random>
#include <vector>

#include "core/sincos.hpp"
#include "core/vector_paths.hpp"
#include "ulps.hpp"

#pragma GCC diagnostic ignored "-Wpsabi"  // four-lane vectors, inlined into the AVX2 function

namespace {

using massid::detail::Lanes;
using massid::test::ulps;

std::vector<double> test_angles() {
  std::vector<double> x;
  for (double v = -12.0; v <= 12.0; v += 1.0 / 1024) x.push_back(v);  // every quadrant, densely
  for (int k = -40; k <= 40; ++k) {                                   // near multiples of pi/4
    const double m = k * M_PI / 4;
    x.insert(x.end(), {m, std::nextafter(m, 1e9), std::nextafter(m, -1e9)});
  }
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> wide(-1e5, 1e5);
  for (int i = 0; i < 100000; ++i) x.push_back(wide(rng));
  x.insert(x.end(), {0.0, -0.0, 1e-300, -1e-300, 1e-8, M_PI, -M_PI, 2 * M_PI});  // zeros first
  while (x.size() % 4 != 0) x.push_back(0.5);
  return x;
}

#if MASSID_X86
[[gnu::target("avx2")]] void sincos_four_lanes(const std::vector<double>& x, double* s, double* c) {
  massid::detail::sincos_many<massid::detail::Lanes4>(x.data(), s, c, static_cast<int>(x.size()));
}
#endif

TEST(Sincos, WithinOneUlpOfLibm) {
  const std::vector<double> x = test_angles();
  std::vector<double> s(x.size()), c(x.size());
  massid::detail::sincos_many<Lanes>(x.data(), s.data(), c.data(), static_cast<int>(x.size()));
  // Largest error in ulps, and where, separately for |x| <= 2 pi and beyond.
  struct Worst {
    std::int64_t ulps = 0;
    double x = 0.0;
    void add(std::int64_t u, double at) {
      if (u > ulps) ulps = u, x = at;
    }
  } sin_near, cos_near, sin_far, cos_far;
  for (std::size_t i = 0; i < x.size(); ++i) {
    // Near a zero of sin or cos the result is tiny and a relative ulp bound is
    // too strict: compare there with an absolute bound of one ulp of 1.
    const double rs = std::sin(x[i]), rc = std::cos(x[i]);
    const bool near = std::abs(x[i]) <= 2 * M_PI;
    if (std::abs(rs) > 1e-3)
      (near ? sin_near : sin_far).add(ulps(s[i], rs), x[i]);
    else
      EXPECT_NEAR(s[i], rs, 0x1p-52 * std::max(1.0, std::abs(x[i]) * 0x1p-30)) << x[i];
    if (std::abs(rc) > 1e-3)
      (near ? cos_near : cos_far).add(ulps(c[i], rc), x[i]);
    else
      EXPECT_NEAR(c[i], rc, 0x1p-52 * std::max(1.0, std::abs(x[i]) * 0x1p-30)) << x[i];
  }
  EXPECT_LE(sin_near.ulps, 1) << "at x = " << sin_near.x;
  EXPECT_LE(cos_near.ulps, 1) << "at x = " << cos_near.x;
  EXPECT_LE(sin_far.ulps, 2) << "at x = " << sin_far.x;
  EXPECT_LE(cos_far.ulps, 2) << "at x = " << cos_far.x;
  for (std::size_t i = 0; i < x.size(); ++i)
    if (x[i] == 0.0) {
      EXPECT_EQ(s[i], 0.0) << "sin(" << x[i] << ") is exact";
    }
}

#if MASSID_X86
TEST(Sincos, FourLanesGiveTheSameBitsAsTwo) {
  if (!massid::detail::cpu_has_avx2()) GTEST_SKIP() << "this CPU has no AVX2";
  const std::vector<double> x = test_angles();
  std::vector<double> s2(x.size()), c2(x.size()), s4(x.size()), c4(x.size());
  massid::detail::sincos_many<Lanes>(x.data(), s2.data(), c2.data(), static_cast<int>(x.size()));
  sincos_four_lanes(x, s4.data(), c4.data());
  EXPECT_EQ(0, std::memcmp(s2.data(), s4.data(), x.size() * sizeof(double)));
  EXPECT_EQ(0, std::memcmp(c2.data(), c4.data(), x.size() * sizeof(double)));
}
#endif

}  // namespace
