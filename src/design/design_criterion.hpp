// The criterion an experiment design minimises, one implementation for the
// static plans (design.cpp) and the exciting trajectories (excitation_*.cpp).
// Internal to design.
//
// The rows of one sample that enter the criterion, R (each weighted), and the
// criterion on the information matrix I = sum over samples of R^T R:
//
//   cond, at rest   lambda_max / lambda_min of I over the moment rows and the
//                   moment unknowns, unweighted: the square of the paper's
//                   eq. 36 number, as static identify reports it;
//   cond, in motion lambda_max / lambda_min of D I D, D = diag(I_cc)^-1/2,
//                   all rows over their noise sigma: the square of the
//                   condition number of the column-scaled, noise-weighted
//                   base regressor (estimation.hpp scaled_condition_number);
//   d-opt           -log det I, all rows over their noise sigma.
//
// +inf when I is singular. Smaller is better in every case.
#pragma once

#include <Eigen/Core>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/base_regressor.hpp"
#include "massid/core/model.hpp"
#include "massid/design/design.hpp"

namespace massid {

class CriterionRows {
 public:
  CriterionRows(const Model& model, const BaseParameters& base, Criterion criterion,
                double noise_force, double noise_moment);
  int size() const { return static_cast<int>(cols_.size()); }
  int num_rows() const { return static_cast<int>(rows_.size()); }
  Criterion criterion() const { return criterion_; }

  // The weighted rows [num_rows x size] of a static pose ...
  void rows(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Vector3d& gravity,
            Eigen::Ref<Eigen::MatrixXd> out);
  // ... and of a sample in motion (`sensor`: the sensor frame's own motion).
  void rows(const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Ref<const Eigen::VectorXd>& qd,
            const Eigen::Ref<const Eigen::VectorXd>& qdd, const Eigen::Vector3d& gravity,
            const FrameMotion& sensor, Eigen::Ref<Eigen::MatrixXd> out);

  // The criterion of an information matrix [size x size] (see above).
  double value(const Eigen::MatrixXd& info) const;
  // The figure a user reads from value(): the condition number for cond
  // (sqrt of the eigenvalue ratio), log det I for d-opt.
  double figure(double value) const;

 private:
  void weigh(Eigen::Ref<Eigen::MatrixXd> out) const;

  const Model& model_;
  const BaseParameters& base_;
  RegressorData reg_;
  Criterion criterion_;
  bool scale_columns_;
  std::vector<int> cols_, rows_;
  std::vector<double> weight_;
};

}  // namespace massid
