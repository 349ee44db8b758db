// Every public function checks the sizes of its arguments: a q of the wrong
// length, a workspace or an output of the wrong shape is an ArgumentError
// naming the function, the argument and both sizes, never undefined behaviour.
#include <gtest/gtest.h>

#include <string>

#include "massid/core/base_parameters.hpp"
#include "massid/core/base_regressor.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"
#include "massid/core/motion_predictor.hpp"
#include "massid/core/predictor.hpp"
#include "massid/core/regressor.hpp"
#include "massid/core/samples.hpp"
#include "massid/core/simulate.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/io/urdf.hpp"
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

TEST(ArgumentChecks, PredictorChecksValuesQGravityAndOutputs) {
  const Model model = load_urdf(kPuma);  // 3 joints
  const BaseParameters base = find_base_parameters(model);
  const Eigen::VectorXd values = Eigen::VectorXd::Ones(base.num_unknowns());
  expect_argument_error(
      [&] { compile_predictor(model, base, Eigen::VectorXd::Ones(base.num_unknowns() + 6)); },
      {"massid::compile_predictor", "values has", "expected " + std::to_string(values.size())});
  const Predictor pred = compile_predictor(model, base, values);
  EXPECT_EQ(pred.num_joints, 3);
  PredictorData data(pred);
  const Eigen::Vector3d g(0, 0, -9.81);
  expect_argument_error([&] { predict(pred, data, Eigen::VectorXd::Zero(2), g); },
                        {"massid::predict", "q has 2 entries", "expected 3"});
  // Batch: every shape, and nothing written on a mismatch.
  Eigen::MatrixXd W = Eigen::MatrixXd::Constant(4, 6, 7.0);
  const Eigen::MatrixXd Q = Eigen::MatrixXd::Zero(4, 3), G = Eigen::MatrixXd::Zero(4, 3);
  expect_argument_error([&] { predict(pred, data, Eigen::MatrixXd::Zero(4, 2), G, W); },
                        {"q columns has 2 entries"});
  expect_argument_error([&] { predict(pred, data, Q, Eigen::MatrixXd::Zero(3, 3), W); },
                        {"gravity rows has 3 entries", "expected 4"});
  expect_argument_error([&] { predict(pred, data, Q, Eigen::MatrixXd::Zero(4, 2), W); },
                        {"gravity columns has 2 entries"});
  Eigen::MatrixXd W5 = Eigen::MatrixXd::Constant(4, 5, 7.0);
  expect_argument_error([&] { predict(pred, data, Q, G, W5); }, {"wrenches columns has 5"});
  EXPECT_TRUE((W.array() == 7.0).all() && (W5.array() == 7.0).all());
  // A workspace of another model; an empty predictor.
  const Model other = load_urdf(test::kUrLikeUrdf);
  PredictorData wrong(
      compile_predictor(other, find_base_parameters(other),
                        Eigen::VectorXd::Ones(find_base_parameters(other).num_unknowns())));
  expect_argument_error([&] { predict(pred, wrong, Eigen::VectorXd::Zero(3), g); },
                        {"massid::predict", "data."});
  expect_argument_error([&] { predict(Predictor{}, data, Eigen::VectorXd::Zero(3), g); },
                        {"massid::predict", "empty"});
  // A workspace serves every predictor of its model, to the bit.
  const Predictor twice = compile_predictor(model, base, 2.0 * values);
  PredictorData own(twice);
  const Eigen::Vector3d q(0.3, -1.2, 2.0);
  EXPECT_EQ(predict(twice, data, q, g), predict(twice, own, q, g));
}

TEST(ArgumentChecks, MotionPredictorChecksValuesVectorsAndOutputs) {
  const Model model = load_urdf(kPuma);
  BaseParameterOptions o;
  o.layout = ParameterLayout::full();
  const BaseParameters base = find_base_parameters(model, o);
  expect_argument_error([&] { compile_motion_predictor(model, base, Eigen::VectorXd::Ones(3)); },
                        {"massid::compile_motion_predictor", "values has 3 entries"});
  const MotionPredictor pred =
      compile_motion_predictor(model, base, Eigen::VectorXd::Ones(base.num_unknowns()));
  MotionPredictorData data(pred);
  const Eigen::VectorXd v3 = Eigen::VectorXd::Zero(3), v4 = Eigen::VectorXd::Zero(4);
  const Eigen::Vector3d g(0, 0, -9.81);
  EXPECT_NO_THROW(predict_motion(pred, data, v3, v3, v3, g));
  expect_argument_error([&] { predict_motion(pred, data, v4, v3, v3, g); },
                        {"massid::predict_motion", "q has 4 entries", "expected 3"});
  expect_argument_error([&] { predict_motion(pred, data, v3, v4, v3, g); }, {"qd has 4"});
  expect_argument_error([&] { predict_motion(pred, data, v3, v3, v4, g); }, {"qdd has 4"});
  const Eigen::MatrixXd Q = Eigen::MatrixXd::Zero(5, 3), G = Eigen::MatrixXd::Zero(5, 3);
  Eigen::MatrixXd W = Eigen::MatrixXd::Constant(5, 6, 7.0);
  expect_argument_error(
      [&] { predict_motion(pred, data, Q, Eigen::MatrixXd::Zero(4, 3), Q, G, W); },
      {"qd rows has 4 entries", "expected 5"});
  expect_argument_error(
      [&] { predict_motion(pred, data, Q, Q, Eigen::MatrixXd::Zero(5, 2), G, W); },
      {"qdd columns has 2"});
  Eigen::MatrixXd W4 = Eigen::MatrixXd::Constant(4, 6, 7.0);
  expect_argument_error([&] { predict_motion(pred, data, Q, Q, Q, G, W4); },
                        {"wrenches rows has 4"});
  EXPECT_TRUE((W.array() == 7.0).all() && (W4.array() == 7.0).all());
  const Model other = load_urdf(test::kUrLikeUrdf);
  const BaseParameters other_base = find_base_parameters(other, o);
  MotionPredictorData wrong(compile_motion_predictor(
      other, other_base, Eigen::VectorXd::Ones(other_base.num_unknowns())));
  expect_argument_error([&] { predict_motion(pred, wrong, v3, v3, v3, g); },
                        {"massid::predict_motion", "data."});
  expect_argument_error([&] { predict_motion(MotionPredictor{}, data, v3, v3, v3, g); }, {"empty"});
}

TEST(ArgumentChecks, IdentifyChecksThatTheSamplesAgree) {
  const Model model = load_urdf(kPuma);
  const BaseParameters base = find_base_parameters(model);
  Samples s;
  s.source = "memory";
  s.q = Eigen::MatrixXd::Random(20, 3);
  s.gravity = Eigen::MatrixXd::Random(20, 3);
  s.wrench = Eigen::MatrixXd::Random(20, 6);
  EXPECT_NO_THROW(identify(model, base, s));
  Samples t = s;
  t.gravity = Eigen::MatrixXd::Random(19, 3);
  expect_argument_error([&] { identify(model, base, t); },
                        {"massid::identify", "gravity rows has 19 entries", "expected 20"});
  t = s;
  t.wrench = Eigen::MatrixXd::Random(20, 5);
  expect_argument_error([&] { identify(model, base, t); }, {"wrench columns has 5"});
  t = s;
  t.q = Eigen::MatrixXd::Random(20, 4);
  expect_argument_error([&] { identify(model, base, t); }, {"q columns has 4", "expected 3"});
  t = s;
  t.qd = Eigen::MatrixXd::Random(20, 2);
  expect_argument_error([&] { identify(model, base, t); }, {"qd columns has 2"});
  t = s;
  t.line = {1, 2, 3};
  expect_argument_error([&] { identify(model, base, t); }, {"line has 3 entries"});
  t = s;
  t.time = Eigen::VectorXd::LinSpaced(21, 0.0, 1.0);
  expect_argument_error([&] { identify(model, base, t); }, {"time has 21 entries"});
  t = s;
  t.wrench.resize(0, 0);  // no wrench at all: a user's input, not a programming error
  EXPECT_THROW(identify(model, base, t), InputError);
}

}  // namespace
}  // namespace massid
