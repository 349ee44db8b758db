// Every public function checks the sizes of its arguments: a q of the wrong
// length, a workspace or an output of the wrong shape is an ArgumentError
// naming the function, the argument and both sizes, never undefined behaviour.
#include <gtest/gtest.h>

#include <string>

#include "massid/base_parameters.hpp"
#include "massid/base_regressor.hpp"
#include "massid/errors.hpp"
#include "massid/kinematics.hpp"
#include "massid/model.hpp"
#include "massid/regressor.hpp"
#include "massid/samples.hpp"
#include "massid/simulate.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

const char* kPuma = MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf";

// Runs f, expects an ArgumentError whose message holds every piece.
template <class F>
void expect_argument_error(F&& f, std::initializer_list<std::string> pieces) {
  try {
    f();
    ADD_FAILURE() << "no ArgumentError";
  } catch (const ArgumentError& e) {
    const std::string m = e.what();
    for (const std::string& p : pieces) EXPECT_NE(m.find(p), std::string::npos) << m;
  }
}

TEST(ArgumentChecks, ForwardKinematicsChecksEveryVector) {
  const Model model = load_urdf(kPuma);  // 3 joints
  KinematicsData data(model);
  const Eigen::VectorXd q3 = Eigen::VectorXd::Zero(3), q2 = Eigen::VectorXd::Zero(2);
  EXPECT_NO_THROW(forward_kinematics(model, data, q3));
  expect_argument_error([&] { forward_kinematics(model, data, q2); },
                        {"massid::forward_kinematics", "q has 2 entries", "expected 3"});
  expect_argument_error(
      [&] { forward_kinematics(model, data, q3, q2, q3, Eigen::Vector3d(0, 0, -9.81)); },
      {"qd has 2 entries"});
  expect_argument_error(
      [&] { forward_kinematics(model, data, q3, q3, q2, Eigen::Vector3d(0, 0, -9.81)); },
      {"qdd has 2 entries"});
  // A workspace built for another model.
  const Model other = load_urdf(test::kUrLikeUrdf);
  KinematicsData wrong(other);
  expect_argument_error([&] { forward_kinematics(model, wrong, q3); }, {"data has"});
}

TEST(ArgumentChecks, RegressorsCheckTheirOutputs) {
  const Model model = load_urdf(kPuma);
  KinematicsData data(model);
  forward_kinematics(model, data, Eigen::VectorXd::Zero(3));
  Eigen::MatrixXd Y(6, 4 * model.num_links() - 1);
  expect_argument_error([&] { standard_regressor(model, data, Eigen::Vector3d(0, 0, -9.81), Y); },
                        {"massid::standard_regressor", "Y columns"});
  Eigen::MatrixXd Ym(5, 10 * model.num_links());
  expect_argument_error([&] { motion_regressor(model, data, Ym); },
                        {"massid::motion_regressor", "Y rows has 5 entries", "expected 6"});
}

TEST(ArgumentChecks, BaseRegressorChecksQAndTheSampleIndex) {
  const Model model = load_urdf(kPuma);
  const BaseParameters base = find_base_parameters(model);
  RegressorData data(model, base);
  expect_argument_error(
      [&] {
        base_regressor(model, base, data, Eigen::VectorXd::Zero(4), Eigen::Vector3d(0, 0, -9.81));
      },
      {"massid::base_regressor", "q has 4 entries", "expected 3"});
  Samples s;
  s.q = Eigen::MatrixXd::Zero(2, 3);
  s.gravity = Eigen::MatrixXd::Zero(2, 3);
  expect_argument_error([&] { base_regressor(model, base, data, s, 2); },
                        {"sample = 2 is outside [0, 2)"});
}

TEST(ArgumentChecks, SimulateChecksThePlan) {
  const Model model = load_urdf(kPuma);
  Samples plan;
  plan.q = Eigen::MatrixXd::Zero(4, 2);
  plan.gravity = Eigen::MatrixXd::Zero(4, 3);
  expect_argument_error([&] { simulate_wrenches(model, plan); },
                        {"massid::simulate_wrenches", "plan.q columns has 2 entries"});
  plan.q = Eigen::MatrixXd::Zero(4, 3);
  plan.gravity = Eigen::MatrixXd::Zero(3, 3);
  expect_argument_error([&] { simulate_wrenches(model, plan); }, {"plan.gravity rows"});
}

}  // namespace
}  // namespace massid
