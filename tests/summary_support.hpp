// Shared checks of the identification tests: two summaries of the same fit
// (dense against streamed, or two orders of the same rows) agree.
#pragma once

#include <gtest/gtest.h>

#include <Eigen/Core>
#include <algorithm>
#include <cmath>
#include <string>

#include "massid/identify/estimation.hpp"

namespace massid::test {

// |a - b| <= rel * max(|a_i|, |b_i|), with a floor of rel * 1e-6 * max|a|
// for entries that are nearly zero (covariances between unrelated unknowns).
inline void expect_close(const Eigen::MatrixXd& a, const Eigen::MatrixXd& b, double rel,
                         const std::string& what) {
  ASSERT_EQ(a.rows(), b.rows()) << what;
  ASSERT_EQ(a.cols(), b.cols()) << what;
  const double floor = 1e-6 * a.cwiseAbs().maxCoeff();
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    const double x = a.data()[i], y = b.data()[i];
    EXPECT_LE(std::abs(x - y), rel * std::max({std::abs(x), std::abs(y), floor}))
        << what << "[" << i << "]: " << x << " vs " << y;
  }
}

// values_to_std: a value near zero is judged against its std rather than
// against the largest value (motion: inertias and first moments of very
// different sizes).
inline void expect_same_summary(const IdentifySummary& d, const IdentifySummary& s, double rel,
                                bool residual_max = true, bool values_to_std = false) {
  if (values_to_std) {
    ASSERT_EQ(d.value.size(), s.value.size());
    for (Eigen::Index i = 0; i < d.value.size(); ++i)
      EXPECT_LE(std::abs(d.value[i] - s.value[i]),
                rel * std::max({std::abs(d.value[i]), std::abs(s.value[i]), d.stddev[i]}))
          << "value[" << i << "]: " << d.value[i] << " vs " << s.value[i];
  } else {
    expect_close(d.value, s.value, rel, "value");
  }
  expect_close(d.stddev, s.stddev, rel, "stddev");
  // Covariances relative to sqrt(C_ii C_jj): entries between nearly
  // uncorrelated unknowns are round-off of that size.
  ASSERT_EQ(d.covariance.rows(), s.covariance.rows());
  for (Eigen::Index i = 0; i < d.covariance.rows(); ++i)
    for (Eigen::Index j = 0; j < d.covariance.cols(); ++j)
      EXPECT_LE(std::abs(d.covariance(i, j) - s.covariance(i, j)),
                rel * std::sqrt(d.covariance(i, i) * d.covariance(j, j)))
          << "covariance(" << i << "," << j << ")";
  expect_close(Eigen::VectorXd::Constant(1, d.condition_number),
               Eigen::VectorXd::Constant(1, s.condition_number), rel, "condition number");
  expect_close(d.residual_rms, s.residual_rms, rel, "residual_rms");
  if (residual_max) expect_close(d.residual_max, s.residual_max, rel, "residual_max");
  expect_close(d.sigma, s.sigma, rel, "sigma");
  expect_close(Eigen::VectorXd::Constant(1, d.chi2_per_dof),
               Eigen::VectorXd::Constant(1, s.chi2_per_dof), rel, "chi2_per_dof");
  EXPECT_EQ(d.samples, s.samples);
  EXPECT_EQ(d.sigma_estimated, s.sigma_estimated);
  EXPECT_EQ(d.gravity_from_force, s.gravity_from_force);
}

inline void expect_identical(const IdentifySummary& a, const IdentifySummary& b) {
  EXPECT_EQ(a.value, b.value);
  EXPECT_EQ(a.stddev, b.stddev);
  EXPECT_EQ(a.covariance, b.covariance);
  EXPECT_EQ(a.condition_number, b.condition_number);
  EXPECT_EQ(a.residual_rms, b.residual_rms);
  EXPECT_EQ(a.residual_max, b.residual_max);
  EXPECT_EQ(a.sigma, b.sigma);
  EXPECT_EQ(a.chi2_per_dof, b.chi2_per_dof);
  EXPECT_EQ(a.samples, b.samples);
}

}  // namespace massid::test
