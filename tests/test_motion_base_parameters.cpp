// Dynamic base parameters: their number against an independent rank
// computation, and their defining property.
//
// The rank is computed directly as the numerical rank (SVD, relative 1e-9) of
// the standard motion regressor Y (6 x 10 L per sample) stacked over random
// joint positions, velocities and accelerations, with the experiment's gravity
// (level: one fixed vector; tilted: random directions) and sensor motion, and
// the six offset columns appended when offsets are estimated; offsets that
// the data cannot tell from constant columns then reduce the count. The
// reduction (find_base_parameters) works differently: greedy Gram-Schmidt in a
// preference order with the total mass as a column of its own. Both must
// agree, and with the known counts for a UR5-like arm on a base sensor: 43
// level, 44 tilted, 40 level with offsets.
#include <gtest/gtest.h>

#include <Eigen/SVD>
#include <random>

#include "massid/core/base_parameters.hpp"
#include "massid/core/base_regressor.hpp"
#include "massid/core/regressor.hpp"
#include "massid/io/urdf.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

struct Experiment {
  bool level = false, offset = false, moving = false;
};

int independent_rank(const Model& model, const Experiment& e, int samples = 300) {
  const int n = ParameterLayout::full().size(model), nj = model.num_joints();
  const int cols = n + (e.offset ? 6 : 0);
  std::mt19937_64 rng(4242);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(-3.0, 3.0);
  KinematicsData kin(model);
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(6 * samples, cols), Y(6, n);
  Eigen::VectorXd q(nj), qd(nj), qdd(nj);
  for (int s = 0; s < samples; ++s) {
    for (int j = 0; j < nj; ++j) {
      q[j] = uniform(rng);
      qd[j] = normal(rng);
      qdd[j] = normal(rng);
    }
    Eigen::Vector3d g(0, 0, -kStandardGravity);
    if (!e.level)
      g = kStandardGravity * Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    FrameMotion m;
    if (e.moving)
      m = {Eigen::Vector3d(normal(rng), normal(rng), normal(rng)),
           Eigen::Vector3d(normal(rng), normal(rng), normal(rng)),
           Eigen::Vector3d(normal(rng), normal(rng), normal(rng))};
    forward_kinematics(model, kin, q, qd, qdd, g, m);
    motion_regressor(model, kin, Y);
    A.block(6 * s, 0, 6, n) = Y;
    if (e.offset) A.block<6, 6>(6 * s, n).setIdentity();
  }
  for (int c = 0; c < cols; ++c)
    if (A.col(c).norm() > 1e-9 * A.norm()) A.col(c).normalize();
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(A).singularValues();
  int rank = 0;
  for (int i = 0; i < sv.size(); ++i) rank += sv[i] > 1e-9 * sv[0];
  return rank - (e.offset ? 6 : 0);  // the count of base parameters besides the offsets
}

BaseParameters reduce(const Model& model, const Experiment& e) {
  BaseParameterOptions o;
  o.layout = ParameterLayout::full();
  o.fixed_gravity = e.level;
  o.offset = e.offset;
  o.sensor_moving = e.moving;
  return find_base_parameters(model, o);
}

TEST(MotionBaseParameters, CountsAgreeWithAnIndependentRank) {
  for (const test::Example& ex : test::examples()) {
    const Model model = load_urdf(ex.urdf);
    for (const Experiment e : {Experiment{true, false, false}, Experiment{false, false, false},
                               Experiment{true, true, false}, Experiment{false, true, false},
                               Experiment{false, false, true}, Experiment{true, true, true}}) {
      SCOPED_TRACE(ex.name + (e.level ? " level" : " tilted") + (e.offset ? " offset" : "") +
                   (e.moving ? " moving" : ""));
      EXPECT_EQ(reduce(model, e).num_mass(), independent_rank(model, e));
    }
  }
}

TEST(MotionBaseParameters, KnownCountsForTheUrLikeArm) {
  const Model model = load_urdf(test::examples()[1].urdf);
  EXPECT_EQ(reduce(model, {true, false, false}).num_mass(), 43);
  EXPECT_EQ(reduce(model, {false, false, false}).num_mass(), 44);
  EXPECT_EQ(reduce(model, {true, true, false}).num_mass(), 40);
  // The total mass is a base parameter of its own unless level offsets absorb it.
  const BaseParameters level = reduce(model, {true, false, false});
  ASSERT_GE(level.total_mass, 0);
  EXPECT_EQ(level.params[level.total_mass].expression.find("m(sensor)"), 0u);
  EXPECT_EQ(reduce(model, {true, true, false}).total_mass, -1);
}

// Y_b K pi = Y pi for any pi (the defining property, eq. 28's in motion):
// the base parameters carry everything the wrench depends on.
TEST(MotionBaseParameters, BaseRegressorReproducesTheStandardWrench) {
  for (const test::Example& ex : test::examples()) {
    const Model model = load_urdf(ex.urdf);
    for (const Experiment e : {Experiment{true, false, false}, Experiment{false, false, true}}) {
      const BaseParameters base = reduce(model, e);
      std::mt19937_64 rng(7);
      std::normal_distribution<double> normal;
      const int n = ParameterLayout::full().size(model), nj = model.num_joints();
      Eigen::VectorXd pi(n);
      for (int i = 0; i < n; ++i) pi[i] = normal(rng);
      RegressorData data(model, base);
      KinematicsData kin(model);
      Eigen::MatrixXd Y(6, n);
      for (int trial = 0; trial < 20; ++trial) {
        Eigen::VectorXd q(nj), qd(nj), qdd(nj);
        for (int j = 0; j < nj; ++j) {
          q[j] = normal(rng);
          qd[j] = normal(rng);
          qdd[j] = normal(rng);
        }
        const Eigen::Vector3d g =
            e.level ? Eigen::Vector3d(0, 0, -kStandardGravity)
                    : Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized() * 9.8;
        FrameMotion m;
        if (e.moving) m.omega = Eigen::Vector3d(normal(rng), normal(rng), normal(rng));
        base_regressor(model, base, data, q, qd, qdd, g, m);
        forward_kinematics(model, kin, q, qd, qdd, g, m);
        motion_regressor(model, kin, Y);
        const Eigen::VectorXd expected = Y * pi, got = data.base * (base.K * pi);
        EXPECT_LT((expected - got).norm(), 1e-9 * std::max(1.0, expected.norm())) << ex.name;
      }
    }
  }
}

}  // namespace
}  // namespace massid
