// The compiled motion predictor against the motion base regressor
// (w = Y_b pi_b + offset) for arbitrary parameter values and motions, against
// the standard regressor for the URDF's inertials, and at rest against the
// static gravity predictor.
#include <gtest/gtest.h>

#include <random>

#include "core/motion_predictor_plan.hpp"
#include "core/vector_paths.hpp"
#include "massid/core/base_parameters.hpp"
#include "massid/core/base_regressor.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/motion_predictor.hpp"
#include "massid/core/predictor.hpp"
#include "massid/core/regressor.hpp"
#include "massid/io/urdf.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

// A random motion sample: joints within their generic range, rates and
// accelerations, a tilted gravity and (when `moving`) the sensor frame's motion.
struct Motion {
  Eigen::VectorXd q, qd, qdd;
  Eigen::Vector3d g;
  FrameMotion sensor;
};

Motion random_motion(const Model& model, std::mt19937_64& rng, bool moving) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> n;
  const int nj = model.num_joints();
  Motion m{Eigen::VectorXd(nj), Eigen::VectorXd(nj), Eigen::VectorXd(nj), {}, {}};
  for (int j = 0; j < nj; ++j) {
    m.q[j] = model.joints[j].generic_position(u(rng));
    m.qd[j] = 2.0 * n(rng);
    m.qdd[j] = 5.0 * n(rng);
  }
  m.g = kStandardGravity * Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
  if (moving)
    for (int k = 0; k < 3; ++k) {
      m.sensor.omega[k] = n(rng);
      m.sensor.omega_dot[k] = 3.0 * n(rng);
      m.sensor.accel[k] = 3.0 * n(rng);
    }
  return m;
}

Wrench predict(const MotionPredictor& p, MotionPredictorData& d, const Motion& m) {
  return predict_motion(p, d, m.q.data(), m.qd.data(), m.qdd.data(), m.g, m.sensor);
}

BaseParameters motion_base(const Model& model, bool offset, bool moving, bool fixed_gravity) {
  BaseParameterOptions o;
  o.layout = ParameterLayout::full();
  o.offset = offset;
  o.sensor_moving = moving;
  o.fixed_gravity = fixed_gravity;
  return find_base_parameters(model, o);
}

struct MotionCase {
  test::Example example;
  bool offset, moving;
};

std::vector<MotionCase> motion_cases() {
  std::vector<MotionCase> out;
  for (const test::Example& e : test::examples())
    for (bool offset : {false, true})
      for (bool moving : {false, true}) out.push_back({e, offset, moving});
  return out;
}

class MotionPredictorTest : public ::testing::TestWithParam<MotionCase> {};

// Y_b values (+ offsets) for random values of every unknown, and for values
// K pi of random standard parameters, at random motions.
TEST_P(MotionPredictorTest, EqualsTheBaseRegressor) {
  const MotionCase& c = GetParam();
  const Model model = load_urdf(c.example.urdf);
  const BaseParameters base = motion_base(model, c.offset, c.moving, false);
  std::mt19937_64 rng(11);
  std::normal_distribution<double> n;
  RegressorData reg(model, base);
  for (int trial = 0; trial < 12; ++trial) {
    Eigen::VectorXd values(base.num_unknowns());
    if (trial % 2 == 0) {
      for (int i = 0; i < values.size(); ++i) values[i] = n(rng);
    } else {
      Eigen::VectorXd pi(base.layout.size(model));
      for (int i = 0; i < pi.size(); ++i) pi[i] = n(rng);
      values.head(base.num_mass()) = base.K * pi;
      for (int i = base.num_mass(); i < values.size(); ++i) values[i] = n(rng);
    }
    const MotionPredictor pred = compile_motion_predictor(model, base, values);
    MotionPredictorData data(pred);
    for (int k = 0; k < 20; ++k) {
      const Motion m = random_motion(model, rng, c.moving);
      base_regressor(model, base, reg, m.q, m.qd, m.qdd, m.g, m.sensor);
      const Wrench expected = reg.base * values;
      const Wrench got = predict(pred, data, m) + pred.offset;
      EXPECT_LE((got - expected).norm(), 1e-10 * expected.norm())
          << "trial " << trial << " sample " << k << "\n"
          << got.transpose() << "\n"
          << expected.transpose();
    }
  }
}

// Y_b K pi = Y pi: the URDF's inertials through the base parameters give the
// standard regressor's wrench.
TEST_P(MotionPredictorTest, NominalParametersGiveTheStandardRegressor) {
  const MotionCase& c = GetParam();
  const Model model = load_urdf(c.example.urdf);
  const BaseParameters base = motion_base(model, c.offset, c.moving, false);
  const Eigen::VectorXd pi = ParameterLayout::full().nominal(model);
  Eigen::VectorXd values = Eigen::VectorXd::Zero(base.num_unknowns());
  values.head(base.num_mass()) = base.K * pi;
  const MotionPredictor pred = compile_motion_predictor(model, base, values);
  MotionPredictorData data(pred);
  KinematicsData kin(model);
  Eigen::MatrixXd Y(6, pi.size());
  std::mt19937_64 rng(5);
  for (int k = 0; k < 50; ++k) {
    const Motion m = random_motion(model, rng, c.moving);
    forward_kinematics(model, kin, m.q, m.qd, m.qdd, m.g, m.sensor);
    motion_regressor(model, kin, Y);
    const Wrench expected = Y * pi;
    EXPECT_LE((predict(pred, data, m) - expected).norm(), 1e-10 * expected.norm())
        << "sample " << k;
  }
}

// The batch form computes row by row exactly what single calls compute.
TEST_P(MotionPredictorTest, BatchEqualsSingleCalls) {
  const MotionCase& c = GetParam();
  const Model model = load_urdf(c.example.urdf);
  const BaseParameters base = motion_base(model, c.offset, c.moving, false);
  std::mt19937_64 rng(7);
  std::normal_distribution<double> n;
  Eigen::VectorXd values(base.num_unknowns());
  for (int i = 0; i < values.size(); ++i) values[i] = n(rng);
  const MotionPredictor pred = compile_motion_predictor(model, base, values);
  MotionPredictorData data(pred);
  const int N = 37, nj = model.num_joints();
  // qd inside a taller matrix: each input has its own stride.
  Eigen::MatrixXd Q(N, nj), Qd_storage(N + 5, nj), Qdd(N, nj), G(N, 3), W(N, 6);
  for (Eigen::Index i = 0; i < Q.size(); ++i) {
    Q.data()[i] = 3 * n(rng);
    Qdd.data()[i] = 5 * n(rng);
  }
  for (Eigen::Index i = 0; i < Qd_storage.size(); ++i) Qd_storage.data()[i] = 2 * n(rng);
  const auto Qd = Qd_storage.bottomRows(N);
  for (Eigen::Index i = 0; i < G.size(); ++i) G.data()[i] = 9.81 * n(rng);
  predict_motion(pred, data, Q, Qd, Qdd, G, W);
  for (int i = 0; i < N; ++i) {
    const Eigen::VectorXd q = Q.row(i).transpose(), qd = Qd.row(i).transpose(),
                          qdd = Qdd.row(i).transpose();
    const Wrench single =
        predict_motion(pred, data, q.data(), qd.data(), qdd.data(), G.row(i).transpose());
    EXPECT_EQ(W.row(i).transpose(), single) << "row " << i;
  }
}

// The two-lane path (SSE2, NEON) gives the same bits as the four-lane (AVX2)
// one: no path contracts to fused multiply-adds. Only where the CPU has AVX2
// (elsewhere both predictors would take the two-lane path: the comparison
// would be of a path with itself), and each predictor's plan is asserted.
TEST_P(MotionPredictorTest, TwoLanesGiveTheSameBitsAsFour) {
  if (!detail::cpu_has_avx2()) GTEST_SKIP() << "no AVX2 (an x86-64 without it, or another CPU)";
  const MotionCase& c = GetParam();
  const Model model = load_urdf(c.example.urdf);
  const BaseParameters base = motion_base(model, c.offset, c.moving, false);
  std::mt19937_64 rng(13);
  std::normal_distribution<double> n;
  Eigen::VectorXd values(base.num_unknowns());
  for (int i = 0; i < values.size(); ++i) values[i] = n(rng);
  const MotionPredictor four =
      detail::with_four_lanes(compile_motion_predictor(model, base, values), true);
  const MotionPredictor two = detail::with_four_lanes(four, false);
  ASSERT_TRUE(four.plan->four_lanes);
  ASSERT_FALSE(two.plan->four_lanes);
  MotionPredictorData data2(two), data4(four);
  for (int k = 0; k < 50; ++k) {
    const Motion m = random_motion(model, rng, c.moving);
    const Wrench w2 = predict(two, data2, m), w4 = predict(four, data4, m);
    EXPECT_EQ(w2, w4) << "sample " << k;
  }
}

// The checked overload (Eigen vectors, their sizes checked) gives the raw
// overload's bits for the same numbers, taken from inside larger vectors (a
// wrong array or offset passed on would show).
TEST_P(MotionPredictorTest, CheckedOverloadGivesTheRawOverloadsBits) {
  const MotionCase& c = GetParam();
  const Model model = load_urdf(c.example.urdf);
  const BaseParameters base = motion_base(model, c.offset, c.moving, false);
  std::mt19937_64 rng(23);
  std::normal_distribution<double> n;
  Eigen::VectorXd values(base.num_unknowns());
  for (int i = 0; i < values.size(); ++i) values[i] = n(rng);
  const MotionPredictor pred = compile_motion_predictor(model, base, values);
  MotionPredictorData data(pred);
  const Eigen::Index nj = model.num_joints();
  for (int k = 0; k < 30; ++k) {
    const Motion m = random_motion(model, rng, c.moving);
    if (nj > 0) {
      ASSERT_GT(m.qd.norm() * m.qdd.norm(), 0.0);  // non-zero numbers
    }
    // q, qd, qdd side by side in one vector, between other numbers.
    Eigen::VectorXd all = Eigen::VectorXd::Constant(3 * nj + 2, 7.0);
    all.segment(1, nj) = m.q;
    all.segment(1 + nj, nj) = m.qd;
    all.segment(1 + 2 * nj, nj) = m.qdd;
    const Wrench raw = predict(pred, data, m);
    const Wrench checked = predict_motion(pred, data, all.segment(1, nj), all.segment(1 + nj, nj),
                                          all.segment(1 + 2 * nj, nj), m.g, m.sensor);
    EXPECT_EQ(checked, raw) << "sample " << k;
    ASSERT_GT(raw.norm(), 0.0);
  }
}

// At rest (qd = qdd = 0, sensor at rest) the wrench is the gravity wrench:
// the static predictor's for the same standard parameters (a base for a
// moving sensor holds at rest too).
TEST_P(MotionPredictorTest, AtRestEqualsTheStaticPredictor) {
  const MotionCase& c = GetParam();
  const Model model = load_urdf(c.example.urdf);
  const BaseParameters base = motion_base(model, c.offset, c.moving, false);
  BaseParameterOptions so;
  so.offset = c.offset;
  const BaseParameters static_base = find_base_parameters(model, so);
  std::mt19937_64 rng(17);
  std::normal_distribution<double> n;
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd pi = ParameterLayout::full().nominal(model);
    if (trial > 0)  // random standard parameters
      for (int i = 0; i < pi.size(); ++i) pi[i] = n(rng);
    Eigen::VectorXd pi_first(ParameterLayout::first_moments().size(model));
    for (int l = 0; l < model.num_links(); ++l) pi_first.segment<4>(4 * l) = pi.segment<4>(10 * l);
    Eigen::VectorXd values = Eigen::VectorXd::Zero(base.num_unknowns());
    Eigen::VectorXd static_values = Eigen::VectorXd::Zero(static_base.num_unknowns());
    values.head(base.num_mass()) = base.K * pi;
    static_values.head(static_base.num_mass()) = static_base.K * pi_first;
    const MotionPredictor pred = compile_motion_predictor(model, base, values);
    MotionPredictorData data(pred);
    const Predictor rest = compile_predictor(model, static_base, static_values);
    PredictorData rest_data(rest);
    for (int k = 0; k < 20; ++k) {
      Motion m = random_motion(model, rng, false);
      m.qd.setZero();
      m.qdd.setZero();
      const Wrench expected = massid::predict(rest, rest_data, m.q, m.g);
      EXPECT_LE((predict(pred, data, m) - expected).norm(), 1e-10 * expected.norm())
          << "trial " << trial << " sample " << k;
    }
  }
}

INSTANTIATE_TEST_SUITE_P(Examples, MotionPredictorTest, ::testing::ValuesIn(motion_cases()),
                         [](const auto& info) {
                           return info.param.example.name + (info.param.offset ? "_offset" : "") +
                                  (info.param.moving ? "_moving" : "_rest");
                         });

// A level platform with offsets: constants join the offsets and the total
// mass is not identifiable (total_mass -1, M_t = 0 in the representatives).
TEST(MotionPredictor, FixedGravityWithOffsets) {
  int without_total_mass = 0;
  for (const test::Example& e : test::examples()) {
    const Model model = load_urdf(e.urdf);
    const BaseParameters base = motion_base(model, true, false, true);
    without_total_mass += base.total_mass < 0;
    std::mt19937_64 rng(19);
    std::normal_distribution<double> n;
    RegressorData reg(model, base);
    Eigen::VectorXd values(base.num_unknowns());
    for (int i = 0; i < values.size(); ++i) values[i] = n(rng);
    const MotionPredictor pred = compile_motion_predictor(model, base, values);
    MotionPredictorData data(pred);
    for (int k = 0; k < 20; ++k) {
      Motion m = random_motion(model, rng, false);
      m.g = base.sensor_gravity;
      base_regressor(model, base, reg, m.q, m.qd, m.qdd, m.g, m.sensor);
      const Wrench expected = reg.base * values;
      EXPECT_LE((predict(pred, data, m) + pred.offset - expected).norm(), 1e-10 * expected.norm())
          << e.name << " sample " << k;
    }
  }
  EXPECT_EQ(without_total_mass, static_cast<int>(test::examples().size()));
}

// Every standard parameter as its own "base parameter" (column c of Y' for
// c = 0 .. 10 L - 1, M_t first): the representatives are then all of pi, so
// every link's mass, first moment and inertia is folded into its body (links
// behind fixed joints at an offset and rotated) and must give Y pi.
void expect_every_standard_parameter_folds(const Model& model, const std::string& name) {
  BaseParameters all;
  all.layout = ParameterLayout::full();
  const int n = all.layout.size(model);
  all.params.resize(static_cast<std::size_t>(n));
  for (int c = 0; c < n; ++c) all.column.push_back(c);
  all.K = Eigen::MatrixXd::Identity(n, n);
  std::mt19937_64 rng(23);
  std::normal_distribution<double> normal;
  Eigen::VectorXd pi(n);
  for (int i = 0; i < n; ++i) pi[i] = normal(rng);
  Eigen::VectorXd values = pi;  // pi' = pi with M_t for m_sensor
  for (int l = 1; l < model.num_links(); ++l) values[kMass] += pi[all.layout.index(l, kMass)];
  const MotionPredictor pred = compile_motion_predictor(model, all, values);
  MotionPredictorData data(pred);
  KinematicsData kin(model);
  Eigen::MatrixXd Y(6, n);
  for (int k = 0; k < 20; ++k) {
    const Motion m = random_motion(model, rng, true);
    forward_kinematics(model, kin, m.q, m.qd, m.qdd, m.g, m.sensor);
    motion_regressor(model, kin, Y);
    const Wrench expected = Y * pi;
    EXPECT_LE((predict(pred, data, m) - expected).norm(), 1e-10 * expected.norm())
        << name << " sample " << k;
  }
}

TEST(MotionPredictor, FoldsEveryStandardParameterIntoItsBody) {
  for (const test::Example& e : test::examples())
    expect_every_standard_parameter_folds(load_urdf(e.urdf), e.name);
}

// Joint axes along negative axes of the parent's frame, a mount yawed by 30
// degrees (the first body's frame is turned so that its child's axis is an
// axis of it), a prismatic joint along -y behind a rolled frame, a skew axis
// (the general path) and a branch.
TEST(MotionPredictor, AxisSignsYawedMountsAndSkewAxes) {
  const std::string inertial =
      "<inertial><origin xyz=\"0.03 -0.02 0.05\"/><mass value=\"1.5\"/><inertia ixx=\"0.02\" "
      "ixy=\"0.001\" ixz=\"-0.002\" iyy=\"0.03\" iyz=\"0.003\" izz=\"0.01\"/></inertial>";
  const auto link = [&](const std::string& name) {
    return "<link name=\"" + name + "\">" + inertial + "</link>";
  };
  const auto joint = [](const std::string& name, const std::string& type, const std::string& parent,
                        const std::string& child, const std::string& xyz, const std::string& rpy,
                        const std::string& axis) {
    return "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent +
           "\"/><child link=\"" + child + "\"/><origin xyz=\"" + xyz + "\" rpy=\"" + rpy +
           "\"/><axis xyz=\"" + axis +
           "\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" "
           "velocity=\"1\"/></joint>";
  };
  const std::string xml =
      "<robot name=\"signs\">" + link("sensor") + link("base") + link("l1") + link("l2") +
      link("l3") + link("l4") + link("l5") +
      joint("mount", "fixed", "sensor", "base", "0 0 0.02", "0 0 0.5235987755982988", "1 0 0") +
      joint("j1", "revolute", "base", "l1", "0 0 0.1", "0 0 0", "0 0 -1") +
      joint("j2", "prismatic", "l1", "l2", "0.1 0.05 0.2", "1.5707963267948966 0 0", "0 -1 0") +
      joint("j3", "continuous", "l2", "l3", "0 0.1 0.3", "0 0 1.5707963267948966", "1 0 0") +
      joint("j4", "revolute", "l3", "l4", "0.2 0 0", "0.1 0.2 0.3", "0.6 0 0.8") +
      joint("j5", "revolute", "base", "l5", "0 -0.2 0.1", "0 0 0", "0 -1 0") + "</robot>";
  const Model model = load_urdf_string(xml);
  ASSERT_EQ(model.num_joints(), 5);
  expect_every_standard_parameter_folds(model, "signs");
  for (bool offset : {false, true}) {
    const BaseParameters base = motion_base(model, offset, true, false);
    std::mt19937_64 rng(29);
    std::normal_distribution<double> n;
    RegressorData reg(model, base);
    Eigen::VectorXd values(base.num_unknowns());
    for (int i = 0; i < values.size(); ++i) values[i] = n(rng);
    const MotionPredictor pred = compile_motion_predictor(model, base, values);
    MotionPredictorData data(pred);
    for (int k = 0; k < 20; ++k) {
      const Motion m = random_motion(model, rng, true);
      base_regressor(model, base, reg, m.q, m.qd, m.qdd, m.g, m.sensor);
      const Wrench expected = reg.base * values;
      EXPECT_LE((predict(pred, data, m) + pred.offset - expected).norm(), 1e-10 * expected.norm())
          << "sample " << k;
    }
  }
}

TEST(MotionPredictor, RejectsStaticBasesAndWrongSizes) {
  const Model model = load_urdf(test::examples()[0].urdf);
  const BaseParameters rest = find_base_parameters(model);
  EXPECT_THROW(compile_motion_predictor(model, rest, Eigen::VectorXd::Ones(rest.num_unknowns())),
               InputError);
  const BaseParameters base = motion_base(model, false, false, false);
  EXPECT_THROW(
      compile_motion_predictor(model, base, Eigen::VectorXd::Ones(base.num_unknowns() + 1)),
      ArgumentError);
}

}  // namespace
}  // namespace massid
