// Base parameters: the defining property Y = Y_b K on fresh random samples, the
// rank, the total mass, and for the PUMA 260 the paper's eq. 28 combinations.
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <fstream>
#include <iterator>
#include <random>

#include "massid/core/base_parameters.hpp"
#include "massid/core/base_regressor.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/regressor.hpp"
#include "massid/io/urdf.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

// Stacked standard and base regressors over random samples (another seed than
// find_base_parameters uses).
void stacked(const Model& model, const BaseParameters& base, int samples, Eigen::MatrixXd& Y,
             Eigen::MatrixXd& Yb) {
  std::mt19937_64 rng(99);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> n;
  RegressorData data(model, base);
  Y.resize(6 * samples, num_standard_parameters(model));
  Yb.resize(6 * samples, base.num_unknowns());
  Eigen::VectorXd q(model.num_joints());
  for (int s = 0; s < samples; ++s) {
    for (int j = 0; j < model.num_joints(); ++j) q[j] = model.joints[j].generic_position(u(rng));
    const Eigen::Vector3d g = 9.8 * Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
    base_regressor(model, base, data, q, g);
    Y.middleRows(6 * s, 6) = data.standard;
    Yb.middleRows(6 * s, 6) = data.base;
  }
}

class BaseParametersTest : public ::testing::TestWithParam<test::Example> {};

TEST_P(BaseParametersTest, BaseRegressorReproducesTheStandardOne) {
  const Model model = load_urdf(GetParam().urdf);
  const BaseParameters base = find_base_parameters(model);
  EXPECT_EQ(base.num_mass(), GetParam().base_parameters);
  Eigen::MatrixXd Y, Yb;
  stacked(model, base, 80, Y, Yb);
  // Y pi = Y_b K pi for every pi: Y = Y_b K.
  EXPECT_LT((Y - Yb * base.K).norm(), 1e-10 * Y.norm());
  // Nothing more can be determined: rank Y = number of base parameters.
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Y);
  qr.setThreshold(1e-10);
  EXPECT_EQ(qr.rank(), base.num_mass());
  // ...and nothing less: Y_b has full column rank.
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qrb(Yb);
  EXPECT_EQ(qrb.rank(), base.num_mass());
}

TEST_P(BaseParametersTest, TotalMassIsABaseParameter) {
  const Model model = load_urdf(GetParam().urdf);
  const BaseParameters base = find_base_parameters(model);
  const BaseParameter& M = base.params[base.total_mass];
  EXPECT_EQ(M.name, "M");
  EXPECT_EQ(M.unit, "kg");
  ASSERT_EQ(static_cast<int>(M.terms.size()), model.num_links());
  for (const Term& t : M.terms) {
    EXPECT_EQ(t.param, kMass);
    EXPECT_EQ(t.coef, 1.0);
  }
}

TEST_P(BaseParametersTest, TermsAreTheRowsOfK) {
  const Model model = load_urdf(GetParam().urdf);
  const BaseParameters base = find_base_parameters(model);
  for (int i = 0; i < base.num_mass(); ++i) {
    Eigen::VectorXd row = Eigen::VectorXd::Zero(num_standard_parameters(model));
    for (const Term& t : base.params[i].terms) row[kParamsPerLink * t.link + t.param] += t.coef;
    EXPECT_EQ((row.transpose() - base.K.row(i)).norm(), 0.0) << base.params[i].name;
  }
}

TEST_P(BaseParametersTest, OffsetsAddSixUnknowns) {
  const Model model = load_urdf(GetParam().urdf);
  BaseParameterOptions opts;
  opts.offset = true;
  const BaseParameters base = find_base_parameters(model, opts);
  EXPECT_EQ(base.num_unknowns(), GetParam().base_parameters + 6);
  EXPECT_EQ(base.unknown_name(base.num_mass() + 4), "offset_my");
}

INSTANTIATE_TEST_SUITE_P(Examples, BaseParametersTest, ::testing::ValuesIn(test::examples()),
                         [](const auto& info) { return info.param.name; });

// The paper's eq. 28 as rows over the URDF's standard parameters
// [sensor, base, link1, link2, link3] x [m, mx, my, mz]; the sensor link's
// first moments join the base's (the paper has no sensor link mass).
Eigen::MatrixXd paper_eq28() {
  const double Z = -0.036, l1 = 0.330, l2x = 0.198, l2y = -0.019;
  constexpr int S = 0, B = 4, L1 = 8, L2 = 12, L3 = 16;
  Eigen::MatrixXd P = Eigen::MatrixXd::Zero(10, 20);
  P(0, L3 + kMx) = 1;                                           // p1 = m3 r3x
  P(1, L3 + kMy) = 1;                                           // p2 = m3 r3y
  P(2, L2 + kMx) = 1, P(2, L3 + kMass) = l2x;                   // p3 = m2 r2x + m3 l2x
  P(3, L2 + kMy) = 1, P(3, L3 + kMass) = l2y;                   // p4 = m2 r2y + m3 l2y
  P(4, L1 + kMy) = -1, P(4, L2 + kMz) = 1, P(4, L3 + kMz) = 1;  // p5
  P(5, L1 + kMx) = 1;                                           // p6 = m1 r1x
  P(6, S + kMx) = 1, P(6, B + kMy) = -1;                        // p7 = m0 (-r0y + X) + ..., X = 0
  P(7, S + kMy) = 1, P(7, B + kMx) = -1;                        // p8 = m0 (-r0x + Y) + ..., Y = 0
  P(8, S + kMz) = 1, P(8, B + kMz) = -1, P(8, L1 + kMz) = -1;   // p9
  for (int l : {B, L1, L2, L3}) P(8, l + kMass) = Z;
  P(8, L2 + kMass) -= l1, P(8, L3 + kMass) -= l1;
  for (int l : {S, B, L1, L2, L3}) P(9, l + kMass) = 1;  // M_t
  return P;
}

TEST(Puma260, BaseParametersAreThePapersEq28) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const BaseParameters base = find_base_parameters(model);
  ASSERT_EQ(base.num_mass(), 10);
  const Eigen::MatrixXd P = paper_eq28();
  const Eigen::VectorXd M = P.row(9).transpose();
  // Each paper row equals +-(one of ours) + a multiple of M, and vice versa.
  std::vector<bool> used(10, false);
  for (int r = 0; r < 10; ++r) {
    int found = -1;
    for (int i = 0; i < 10 && found < 0; ++i) {
      for (double s : {1.0, -1.0}) {
        const Eigen::VectorXd d = s * base.K.row(i).transpose() - P.row(r).transpose();
        const double a = d.dot(M) / M.squaredNorm();
        if ((d - a * M).norm() < 1e-12) found = i;
      }
    }
    ASSERT_GE(found, 0) << "paper p" << r + 1 << " has no massid counterpart";
    EXPECT_FALSE(used[found]);
    used[found] = true;
  }
  // Readable expressions with round-off cleaned.
  EXPECT_EQ(base.params[2].expression, "mx(link2) + 0.198 m(link3)");
  EXPECT_EQ(base.params[3].expression, "my(link2) - 0.019 m(link3)");
}

TEST(Puma260, OffsetsMakeSixteenUnknowns) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  BaseParameterOptions opts;
  opts.offset = true;
  EXPECT_EQ(find_base_parameters(model, opts).num_unknowns(), 16);
}

TEST(Puma260, SensorLinkDeeperInTheTree) {
  // A wrist-style sensor at link2: measured bodies link2 and link3, one joint.
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf", "link2");
  ASSERT_EQ(model.num_links(), 2);
  ASSERT_EQ(model.num_joints(), 1);
  const BaseParameters base = find_base_parameters(model);
  // M, the three first moments of the link2 body and two of link3 (about joint3's axis).
  EXPECT_EQ(base.num_mass(), 6);
}

TEST(Expression, FormatsSignsAndCoefficients) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  EXPECT_EQ(format_expression(model, {{2, kMx, 1.0}, {3, kMass, -0.366}, {1, kMz, -1.0}}),
            "mx(link1) - 0.366 m(link2) - mz(base)");
  EXPECT_EQ(format_expression(model, {{4, kMy, -2.5}}), "-2.5 my(link3)");
  EXPECT_EQ(format_expression(model, {}), "0");
}

TEST(Expression, NoRoundOffTermsFromAnAlmostRightAngle) {
  // ur5_robot.urdf (ros-industrial) writes pi/2 as 1.57079632679, 4.9e-12 short:
  // with wrist_1 held at 0 in motion, a combination then carried
  // "1.95866e-11 ixz(wrist_1_link)". Terms below the rank tolerance relative to
  // the largest of their combination are dropped: the URDF gets the expressions
  // of the exact right angle, and none of its terms is that small.
  std::ifstream in(MASSID_SOURCE_DIR "/examples/ur_like/ur_like.urdf");
  std::string exact((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  std::string rounded = exact;
  int replaced = 0;
  for (size_t at; (at = rounded.find("1.5707963267948966")) != std::string::npos; ++replaced)
    rounded.replace(at, 18, "1.57079632679");
  ASSERT_GE(replaced, 3);
  for (const double held : {0.0, 1.5707963267948966})
    for (const bool motion : {false, true}) {
      BaseParameterOptions o;
      if (motion) o.layout = ParameterLayout::full();
      const std::vector<std::pair<std::string, double>> hold{{"wrist_1_joint", held}};
      const BaseParameters a = find_base_parameters(hold_joints(load_urdf_string(exact), hold), o);
      const Model model = hold_joints(load_urdf_string(rounded), hold);
      const BaseParameters b = find_base_parameters(model, o);
      ASSERT_EQ(a.num_mass(), b.num_mass());
      for (int i = 0; i < b.num_mass(); ++i) {
        // The same terms, coefficients equal to the angle's error (a coefficient
        // near a printing boundary may print its sixth digit differently).
        ASSERT_EQ(a.params[i].terms.size(), b.params[i].terms.size()) << b.params[i].expression;
        for (size_t t = 0; t < a.params[i].terms.size(); ++t) {
          const Term &x = a.params[i].terms[t], &y = b.params[i].terms[t];
          EXPECT_TRUE(x.link == y.link && x.param == y.param) << b.params[i].expression;
          EXPECT_NEAR(x.coef, y.coef, 1e-9 * std::abs(x.coef)) << b.params[i].expression;
        }
        double largest = 0.0;
        for (const Term& t : b.params[i].terms) largest = std::max(largest, std::abs(t.coef));
        for (const Term& t : b.params[i].terms)
          EXPECT_GE(std::abs(t.coef), 1e-8 * largest) << b.params[i].expression;
        EXPECT_EQ(b.params[i].expression.find("e-"), std::string::npos) << b.params[i].expression;
      }
      // What was dropped is below what the data could ever show: the base
      // regressor still reproduces the standard one on random parameters.
      std::mt19937_64 rng(3);
      std::normal_distribution<double> normal;
      RegressorData data(model, b);
      for (int trial = 0; trial < 5; ++trial) {
        const int nj = model.num_joints();
        Eigen::VectorXd q(nj), qd(nj), qdd(nj);
        for (int j = 0; j < nj; ++j) q[j] = normal(rng), qd[j] = normal(rng), qdd[j] = normal(rng);
        const Eigen::Vector3d g(0.3, -1.1, -9.7);
        if (motion)
          base_regressor(model, b, data, q, qd, qdd, g, FrameMotion{});
        else
          base_regressor(model, b, data, q, g);
        const Eigen::MatrixXd& Y = data.standard;
        Eigen::VectorXd pi(Y.cols());
        for (Eigen::Index c = 0; c < pi.size(); ++c) pi[c] = normal(rng);
        const Eigen::VectorXd w = Y * pi, wb = data.base * (b.K * pi);
        EXPECT_LT((w - wb).norm(), 1e-9 * w.norm());
      }
    }
}

TEST(BaseParameters, OneLinkRobot) {
  // No dependent parameters: the QR solve has an empty right-hand side.
  const Model model = load_urdf_string(
      "<robot name=\"r\"><link name=\"sensor\"><inertial><mass value=\"1\"/>"
      "<origin xyz=\"0 0 0.1\"/></inertial></link></robot>");
  const BaseParameters base = find_base_parameters(model);
  EXPECT_EQ(base.num_mass(), 4);  // m, mx, my, mz of the one link
  EXPECT_EQ(base.params.back().name, "M");
}

}  // namespace
}  // namespace massid
