#include "identify/householder_fold.hpp"

#include <cmath>
#include <cstddef>
#include <cstring>

#include "core/simd_clones.hpp"

namespace massid::detail {
namespace {

// Dot product in eight partial sums (lane i mod 8 while eight remain, then
// i mod 4, the last few in lane 0), added as (s0 + s1) + (s2 + s3) after
// folding lanes 4..7 onto 0..3: a fixed order, deterministic, no -ffast-math.
// Two accumulators hide the latency of the additions.
[[gnu::always_inline]] inline double dot(const double* a, const double* b, int m) {
  V4 s = {0.0, 0.0, 0.0, 0.0}, u = {0.0, 0.0, 0.0, 0.0};
  int i = 0;
  for (; i + 8 <= m; i += 8) {
    V4 x, y, z, w;
    load4(x, a + i);
    load4(y, b + i);
    load4(z, a + i + 4);
    load4(w, b + i + 4);
    s += x * y;
    u += z * w;
  }
  s += u;
  for (; i + 4 <= m; i += 4) {
    V4 x, y;
    load4(x, a + i);
    load4(y, b + i);
    s += x * y;
  }
  double s0 = s[0];
  for (; i < m; ++i) s0 += a[i] * b[i];
  return (s0 + s[1]) + (s[2] + s[3]);
}

// dot(v, b0, m) and dot(v, b1, m) in one sweep (v loaded once), with the
// same partial sums as dot().
[[gnu::always_inline]] inline void dot2(const double* v, const double* b0, const double* b1, int m,
                                        double& d0, double& d1) {
  V4 s = {0.0, 0.0, 0.0, 0.0}, t = {0.0, 0.0, 0.0, 0.0};
  V4 su = {0.0, 0.0, 0.0, 0.0}, tu = {0.0, 0.0, 0.0, 0.0};
  int i = 0;
  for (; i + 8 <= m; i += 8) {
    V4 x, x4, y, y4, z, z4;
    load4(x, v + i);
    load4(x4, v + i + 4);
    load4(y, b0 + i);
    load4(y4, b0 + i + 4);
    load4(z, b1 + i);
    load4(z4, b1 + i + 4);
    s += x * y;
    su += x4 * y4;
    t += x * z;
    tu += x4 * z4;
  }
  s += su;
  t += tu;
  for (; i + 4 <= m; i += 4) {
    V4 x, y, z;
    load4(x, v + i);
    load4(y, b0 + i);
    load4(z, b1 + i);
    s += x * y;
    t += x * z;
  }
  double s0 = s[0], t0 = t[0];
  for (; i < m; ++i) {
    s0 += v[i] * b0[i];
    t0 += v[i] * b1[i];
  }
  d0 = (s0 + s[1]) + (s[2] + s[3]);
  d1 = (t0 + t[1]) + (t[2] + t[3]);
}

// b -= w v, elementwise (the same operations whatever the vector width).
[[gnu::always_inline]] inline void axpy(double* b, double w, const double* v, int m) {
  int i = 0;
  for (; i + 4 <= m; i += 4) {
    V4 x, y;
    load4(x, v + i);
    load4(y, b + i);
    store4(b + i, y - w * x);
  }
  for (; i < m; ++i) b[i] -= w * v[i];
}

}  // namespace

// An AVX2 copy where the CPU has it (same bits).
MASSID_AVX2_CLONES
void fold_rows(double* R, int n, double* B, int m, int ldb) {
  if (m == 0) return;
  for (int k = 0; k < n; ++k) {
    double* v = B + static_cast<std::ptrdiff_t>(k) * ldb;
    const double s = dot(v, v, m);
    if (s == 0.0) continue;  // nothing below the diagonal: H = I
    const double x0 = R[k + k * n];
    const double norm = std::sqrt(x0 * x0 + s);
    const double beta = x0 >= 0 ? -norm : norm;
    const double tau = (beta - x0) / beta;
    const double inv = 1.0 / (x0 - beta);
    for (int i = 0; i < m; ++i) v[i] *= inv;
    R[k + k * n] = beta;
    // Apply H = I - tau [1; v][1; v]^T to the columns on the right, two at a time.
    int j = k + 1;
    for (; j + 1 < n; j += 2) {
      double* b0 = B + static_cast<std::ptrdiff_t>(j) * ldb;
      double* b1 = b0 + ldb;
      double d0, d1;
      dot2(v, b0, b1, m, d0, d1);
      const double w0 = tau * (R[k + j * n] + d0);
      const double w1 = tau * (R[k + (j + 1) * n] + d1);
      R[k + j * n] -= w0;
      R[k + (j + 1) * n] -= w1;
      axpy(b0, w0, v, m);
      axpy(b1, w1, v, m);
    }
    if (j < n) {
      double* b = B + static_cast<std::ptrdiff_t>(j) * ldb;
      const double w = tau * (R[k + j * n] + dot(v, b, m));
      R[k + j * n] -= w;
      axpy(b, w, v, m);
    }
  }
}

void FoldedRows::add(const Eigen::RowVectorXd& z) {
  B.row(pending) = z;
  if (++pending == B.rows()) flush();
}

void FoldedRows::fold(int m) {
  fold_rows(R.data(), static_cast<int>(R.rows()), B.data(), m, static_cast<int>(B.rows()));
}

void FoldedRows::flush() {
  if (pending > 0) fold(pending);
  pending = 0;
}

void FoldedRows::merge(FoldedRows& later) {
  flush();
  later.flush();
  Eigen::MatrixXd T = later.R;
  fold_rows(R.data(), static_cast<int>(R.rows()), T.data(), static_cast<int>(T.rows()),
            static_cast<int>(T.rows()));
}

}  // namespace massid::detail
