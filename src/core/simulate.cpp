#include "massid/core/simulate.hpp"

#include <algorithm>
#include <random>

#include "core/argument_checks.hpp"
#include "massid/core/base_regressor.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/regressor.hpp"

namespace massid {

Eigen::MatrixXd simulate_wrenches(const Model& model, const Samples& plan,
                                  const SimulateOptions& options) {
  detail::check_size("simulate_wrenches", "plan.q columns", plan.q.cols(), model.num_joints(),
                     "the model's joints");
  detail::check_size("simulate_wrenches", "plan.gravity rows", plan.gravity.rows(), plan.q.rows(),
                     "one gravity vector per sample");
  const ParameterLayout layout =
      options.dynamic ? ParameterLayout::full() : ParameterLayout::first_moments();
  const Eigen::VectorXd pi = layout.nominal(model);
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_joints());
  const bool velocities = model.num_joints() > 0 && plan.qd.cols() == model.num_joints() &&
                          plan.qd.rows() == plan.size();
  KinematicsData kin(model);
  Eigen::MatrixXd Y(6, pi.size());
  const int repeat = std::max(1, options.repeat);
  Eigen::MatrixXd W(static_cast<Eigen::Index>(plan.size()) * repeat, 6);
  std::mt19937_64 rng(options.seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  for (int i = 0; i < plan.size(); ++i) {
    if (options.dynamic) {
      forward_kinematics(model, kin, plan.q.row(i).transpose(),
                         velocities ? Eigen::VectorXd(plan.qd.row(i).transpose()) : zero,
                         velocities ? Eigen::VectorXd(plan.qdd.row(i).transpose()) : zero,
                         plan.gravity.row(i).transpose(), sensor_motion(plan, i));
      motion_regressor(model, kin, Y);
    } else {
      forward_kinematics(model, kin, plan.q.row(i).transpose());
      standard_regressor(model, kin, plan.gravity.row(i).transpose(), Y);
    }
    const Wrench exact = Y * pi + options.offset;
    for (int r = 0; r < repeat; ++r) {
      Wrench w = exact;
      for (int k = 0; k < 6; ++k)
        w[k] += (k < 3 ? options.noise_force : options.noise_moment) * normal(rng);
      W.row(static_cast<Eigen::Index>(i) * repeat + r) = w.transpose();
    }
  }
  return W;
}

}  // namespace massid
