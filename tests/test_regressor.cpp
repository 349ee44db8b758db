// The standard regressor against an independent computation of the gravity
// wrench, sum_i c_i x m_i g with poses from an Isometry3d chain, and against
// central finite differences of that direct wrench in the masses and centres
// of mass.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <random>

#include "massid/core/kinematics.hpp"
#include "massid/core/regressor.hpp"
#include "massid/io/urdf.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

struct Inertials {
  std::vector<double> mass;
  std::vector<Eigen::Vector3d> com;  // link frame
};

Inertials urdf_inertials(const Model& model) {
  Inertials in;
  for (const Link& l : model.links) {
    in.mass.push_back(l.mass);
    in.com.push_back(l.com);
  }
  return in;
}

// Direct wrench: poses by composing Isometry3d transforms link by link.
Eigen::Matrix<double, 6, 1> direct_wrench(const Model& model, const Inertials& in,
                                          const Eigen::VectorXd& q, const Eigen::Vector3d& g) {
  std::vector<Eigen::Isometry3d> T(model.num_links());
  Eigen::Vector3d f = Eigen::Vector3d::Zero(), m = Eigen::Vector3d::Zero();
  for (int l = 0; l < model.num_links(); ++l) {
    const Link& link = model.links[l];
    if (l == 0) {
      T[l].setIdentity();
    } else {
      Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
      if (link.type == JointType::Revolute)
        motion.rotate(Eigen::AngleAxisd(q[link.joint_index], link.axis));
      else if (link.type == JointType::Prismatic)
        motion.translate(q[link.joint_index] * link.axis);
      T[l] = T[link.parent] * link.origin * motion;
    }
    const Eigen::Vector3d c = T[l] * in.com[l];  // centre of mass in the sensor frame
    f += in.mass[l] * g;
    m += c.cross(in.mass[l] * g);
  }
  Eigen::Matrix<double, 6, 1> w;
  w << f, m;
  return w;
}

class RegressorTest : public ::testing::TestWithParam<test::Example> {};

TEST_P(RegressorTest, MatchesDirectSumOfMomentsOfWeights) {
  const Model model = load_urdf(GetParam().urdf);
  const Inertials in = urdf_inertials(model);
  const Eigen::VectorXd pi = nominal_standard_parameters(model);
  KinematicsData kin(model);
  Eigen::MatrixXd Y(6, num_standard_parameters(model));
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> n;
  for (int trial = 0; trial < 50; ++trial) {
    Eigen::VectorXd q(model.num_joints());
    for (int j = 0; j < model.num_joints(); ++j) q[j] = model.joints[j].generic_position(u(rng));
    const Eigen::Vector3d g = 9.81 * Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
    forward_kinematics(model, kin, q);
    standard_regressor(model, kin, g, Y);
    const Eigen::Matrix<double, 6, 1> w = Y * pi, ref = direct_wrench(model, in, q, g);
    EXPECT_LT((w - ref).norm(), 1e-12 * (1 + ref.norm())) << "trial " << trial;
    // Paper eq. 31: the moment is perpendicular to gravity; f = M_t g.
    EXPECT_NEAR(w.tail<3>().dot(g), 0.0, 1e-12 * ref.norm() * g.norm());
    EXPECT_LT((w.head<3>() - model.nominal_total_mass() * g).norm(), 1e-12 * ref.norm());
  }
}

TEST_P(RegressorTest, ColumnsAreFiniteDifferencesOfTheDirectWrench) {
  const Model model = load_urdf(GetParam().urdf);
  Inertials in = urdf_inertials(model);
  // Give every link some mass so that d/dc is informative everywhere.
  for (double& m : in.mass) m += 0.5;
  KinematicsData kin(model);
  Eigen::MatrixXd Y(6, num_standard_parameters(model));
  Eigen::VectorXd q(model.num_joints());
  for (int j = 0; j < model.num_joints(); ++j)
    q[j] = model.joints[j].generic_position(0.3 + 0.05 * j);
  const Eigen::Vector3d g(1.0, -2.0, -9.5);
  forward_kinematics(model, kin, q);
  standard_regressor(model, kin, g, Y);
  const double h = 1e-6;
  for (int l = 0; l < model.num_links(); ++l) {
    const int c = kParamsPerLink * l;
    // d w / d c_lk = m_l Y(h_lk)
    for (int k = 0; k < 3; ++k) {
      Inertials plus = in, minus = in;
      plus.com[l][k] += h;
      minus.com[l][k] -= h;
      const Eigen::Matrix<double, 6, 1> fd =
          (direct_wrench(model, plus, q, g) - direct_wrench(model, minus, q, g)) / (2 * h);
      EXPECT_LT((fd - in.mass[l] * Y.col(c + kMx + k)).norm(), 1e-6) << model.links[l].name << k;
    }
    // d w / d m_l at fixed c_l = Y(m_l) + sum_k c_lk Y(h_lk)
    Inertials plus = in, minus = in;
    plus.mass[l] += h;
    minus.mass[l] -= h;
    const Eigen::Matrix<double, 6, 1> fd =
        (direct_wrench(model, plus, q, g) - direct_wrench(model, minus, q, g)) / (2 * h);
    const Eigen::Matrix<double, 6, 1> col = Y.col(c + kMass) + Y.middleCols<3>(c + kMx) * in.com[l];
    EXPECT_LT((fd - col).norm(), 1e-6) << model.links[l].name;
  }
}

INSTANTIATE_TEST_SUITE_P(Examples, RegressorTest, ::testing::ValuesIn(test::examples()),
                         [](const auto& info) { return info.param.name; });

}  // namespace
}  // namespace massid
