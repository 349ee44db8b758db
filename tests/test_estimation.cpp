// Identification: exact recovery from noise-free data, standard deviations that
// match the actual errors over many noise seeds, the eq. 36 condition number
// against the paper's own W, and clear failures when the data cannot determine
// the parameters.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <Eigen/QR>
#include <Eigen/SVD>
#include <cmath>
#include <iostream>
#include <random>

#include "massid/core/base_parameters.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/regressor.hpp"
#include "massid/core/simulate.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/identification.hpp"
#include "massid/identify/streaming.hpp"
#include "massid/io/urdf.hpp"
#include "massid/report/report.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

using test::kOffset;

using test::offset_plan;

struct EstimationCase {
  test::Example example;
  bool offset;
};

std::vector<EstimationCase> estimation_cases() {
  std::vector<EstimationCase> out;
  for (const auto& ex : test::examples()) {
    out.push_back({ex, false});
    out.push_back({ex, true});
  }
  return out;
}

class EstimationTest : public ::testing::TestWithParam<EstimationCase> {};

TEST_P(EstimationTest, RecoversEveryBaseParameterFromNoiseFreeData) {
  const auto& [ex, offset] = GetParam();
  const Model model = load_urdf(ex.urdf);
  BaseParameterOptions bo;
  bo.offset = offset;
  const BaseParameters base = find_base_parameters(model, bo);
  Samples s = test::load_plan(model, offset ? offset_plan(ex) : ex.plan);
  SimulateOptions so;
  if (offset) so.offset = kOffset;
  s.wrench = simulate_wrenches(model, s, so);
  const IdentifySummary r = identify(model, base, s);
  const Eigen::VectorXd t = test::true_values(model, base, so.offset);
  for (int i = 0; i < base.num_unknowns(); ++i)
    EXPECT_LE(std::abs(r.value[i] - t[i]), 1e-9 * std::max(std::abs(t[i]), 1e-3))
        << base.unknown_name(i) << " = " << t[i];
  EXPECT_LT(r.residual_rms.maxCoeff(), 1e-10);
}

TEST_P(EstimationTest, StandardDeviationsMatchTheErrorsOver200Seeds) {
  const auto& [ex, offset] = GetParam();
  const Model model = load_urdf(ex.urdf);
  BaseParameterOptions bo;
  bo.offset = offset;
  const BaseParameters base = find_base_parameters(model, bo);
  Samples s = test::load_plan(model, offset ? offset_plan(ex) : ex.plan);
  const Eigen::VectorXd t = test::true_values(model, base, offset ? kOffset : Wrench::Zero());
  const int seeds = 200;
  Eigen::VectorXd sum_z2 = Eigen::VectorXd::Zero(base.num_unknowns());
  for (int seed = 1; seed <= seeds; ++seed) {
    SimulateOptions so;
    so.noise_force = 0.05;
    so.noise_moment = 0.004;
    so.seed = seed;
    if (offset) so.offset = kOffset;
    s.wrench = simulate_wrenches(model, s, so);
    const IdentifySummary r = identify(model, base, s);
    sum_z2 += ((r.value - t).cwiseQuotient(r.stddev)).cwiseAbs2();
  }
  const Eigen::VectorXd spread = (sum_z2 / seeds).cwiseSqrt();
  const double overall = std::sqrt(sum_z2.sum() / (seeds * base.num_unknowns()));
  EXPECT_GT(overall, 0.8);
  EXPECT_LT(overall, 1.25);
  for (int i = 0; i < base.num_unknowns(); ++i) {
    EXPECT_GT(spread[i], 0.75) << base.unknown_name(i);
    EXPECT_LT(spread[i], 1.3) << base.unknown_name(i);
  }
}

INSTANTIATE_TEST_SUITE_P(Examples, EstimationTest, ::testing::ValuesIn(estimation_cases()),
                         [](const auto& info) {
                           return info.param.example.name + (info.param.offset ? "_offset" : "");
                         });

TEST(Estimation, GravityFromTheMeasuredForceGivesTheSameResult) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/ur_like/ur_like.urdf");
  const BaseParameters base = find_base_parameters(model);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/ur_like/plan.csv");
  s.wrench = simulate_wrenches(model, s);
  const IdentifySummary a = identify(model, base, s);
  // Paper eq. 37: gravity along the measured force, |g| = 9.80665 (the plan's).
  for (int i = 0; i < s.size(); ++i) {
    const Eigen::Vector3d f = s.wrench.row(i).head<3>();
    s.gravity.row(i) = kStandardGravity * f.normalized();
  }
  s.gravity_from_force = true;
  const IdentifySummary b = identify(model, base, s);
  EXPECT_LT((a.value - b.value).norm(), 1e-9 * a.value.norm());
  EXPECT_TRUE(b.gravity_from_force);
}

TEST(Estimation, OffsetsWithGravityFromForceAreRefused) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/ur_like/ur_like.urdf");
  BaseParameterOptions bo;
  bo.offset = true;
  const BaseParameters base = find_base_parameters(model, bo);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/ur_like/plan.csv");
  s.wrench = simulate_wrenches(model, s);
  s.gravity_from_force = true;
  EXPECT_THROW(identify(model, base, s), IdentifiabilityError);
}

TEST(Estimation, UserSigmasScaleTheCovariance) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const BaseParameters base = find_base_parameters(model);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/puma260/plan.csv");
  SimulateOptions so;
  so.noise_force = 0.05;
  so.noise_moment = 0.005;
  s.wrench = simulate_wrenches(model, s, so);
  IdentifyOptions o1, o2;
  o1.sigma_force = 0.05, o1.sigma_moment = 0.005;
  o2.sigma_force = 0.1, o2.sigma_moment = 0.01;
  const IdentifySummary a = identify(model, base, s, o1), b = identify(model, base, s, o2);
  EXPECT_FALSE(a.sigma_estimated);
  EXPECT_LT((b.stddev - 2 * a.stddev).norm(), 1e-12 * a.stddev.norm());
  EXPECT_LT((a.value - b.value).norm(), 1e-12 * a.value.norm());  // same weights ratio
  EXPECT_NEAR(a.chi2_per_dof, 1.0, 0.5);
}

TEST(Puma260, ConditionNumberIsThePapersEq36) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const BaseParameters base = find_base_parameters(model);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/puma260/plan.csv");
  s.wrench = simulate_wrenches(model, s);
  const IdentifySummary r = identify(model, base, s);
  const double paper = test::paper_condition_number(s);
  EXPECT_NEAR(r.condition_number, paper, 1e-9 * paper);
}

// The message of the IdentifiabilityError identify() must throw ("" if none).
std::string identifiability_message(const Model& model, const BaseParameters& base,
                                    const Samples& s) {
  try {
    identify(model, base, s);
  } catch (const IdentifiabilityError& e) {
    return e.what();
  }
  ADD_FAILURE() << "expected IdentifiabilityError";
  return "";
}

TEST(Puma260, OffsetsNeedMoreThanTwoGravityDirections) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  BaseParameterOptions bo;
  bo.offset = true;
  const BaseParameters base = find_base_parameters(model, bo);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/puma260/plan.csv");
  s.wrench = simulate_wrenches(model, s);
  const std::string msg = identifiability_message(model, base, s);
  EXPECT_NE(msg.find("15 of the 16"), std::string::npos) << msg;
  EXPECT_NE(msg.find("offset_m"), std::string::npos) << msg;
  EXPECT_NE(msg.find("tilt the platform"), std::string::npos) << msg;
}

TEST(Estimation, AJointThatNeverMovesIsNamed) {
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const BaseParameters base = find_base_parameters(model);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/puma260/plan.csv");
  s.q.col(2).setConstant(0.3);  // joint3 held still
  s.wrench = simulate_wrenches(model, s);
  const std::string msg = identifiability_message(model, base, s);
  EXPECT_NE(msg.find("joint3"), std::string::npos) << msg;
  EXPECT_EQ(msg.find("joint1"), std::string::npos) << msg;
}

TEST(Estimation, LevelOnlyDataNeedsATilt) {
  // With gravity always along z, the z first moments stay hidden (paper sec. III).
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/puma260/puma260.urdf");
  const BaseParameters base = find_base_parameters(model);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/puma260/plan.csv");
  for (int i = 0; i < s.size(); ++i) s.gravity.row(i) << 0, 0, kStandardGravity;
  s.wrench = simulate_wrenches(model, s);
  const std::string msg = identifiability_message(model, base, s);
  EXPECT_NE(msg.find("p9"), std::string::npos) << msg;
  EXPECT_NE(msg.find("tilt the platform"), std::string::npos) << msg;
}

TEST(Estimation, UndeterminedParametersOfARobotWithoutJoints) {
  // The diagnosis of a robot without joints (N x 0 joint matrix; fuzz_csv
  // reached it first).
  const Model model = load_urdf(MASSID_SOURCE_DIR "/examples/wrist_tool/wrist_tool.urdf");
  ASSERT_EQ(model.num_joints(), 0);
  const BaseParameters base = find_base_parameters(model);
  Samples s = test::load_plan(model, MASSID_SOURCE_DIR "/examples/wrist_tool/plan.csv");
  for (int i = 0; i < s.size(); ++i) s.gravity.row(i) << 0, 0, kStandardGravity;
  s.wrench = simulate_wrenches(model, s);
  const std::string msg = identifiability_message(model, base, s);
  EXPECT_NE(msg.find("tilt the platform"), std::string::npos) << msg;
}

// ------------------------------------------------------- many unknowns

// A base link carrying `arms` arms of four revolute joints (z, y, y, x), each
// link with its own mass and centre of mass: about eight static base
// parameters per arm, the kind of big tree (a humanoid, a mobile manipulator)
// whose unknowns approach the equation count.
std::string many_arms_urdf(int arms) {
  std::string x = "<robot name='many_arms'>\n";
  const auto link = [&](const std::string& name, double m, double cx, double cy, double cz) {
    x += fmt::format(
        "<link name='{}'><inertial><origin xyz='{} {} {}'/><mass value='{}'/>"
        "<inertia ixx='0.01' iyy='0.01' izz='0.01' ixy='0' ixz='0' iyz='0'/></inertial></link>\n",
        name, cx, cy, cz, m);
  };
  const auto joint = [&](const std::string& name, const std::string& parent,
                         const std::string& child, double ox, double oy, double oz,
                         const char* axis) {
    x += fmt::format(
        "<joint name='{}' type='revolute'><parent link='{}'/><child link='{}'/>"
        "<origin xyz='{} {} {}'/><axis xyz='{}'/>"
        "<limit lower='-3.14159' upper='3.14159' effort='1' velocity='1'/></joint>\n",
        name, parent, child, ox, oy, oz, axis);
  };
  link("base", 5.0, 0.01, -0.02, 0.05);
  const char* axes[] = {"0 0 1", "0 1 0", "0 1 0", "1 0 0"};
  for (int a = 0; a < arms; ++a) {
    const double t = 2 * M_PI * a / arms;
    std::string parent = "base";
    for (int j = 0; j < 4; ++j) {
      const std::string child = fmt::format("arm{}_link{}", a, j + 1);
      const double len = 0.1 + 0.03 * j + 0.01 * a;
      if (j == 0)
        joint(fmt::format("arm{}_joint1", a), parent, child, 0.2 * std::cos(t), 0.2 * std::sin(t),
              0.1, axes[0]);
      else
        joint(fmt::format("arm{}_joint{}", a, j + 1), parent, child, j == 1 ? 0.0 : len, 0.0,
              j == 1 ? 0.12 : 0.0, axes[j]);
      link(child, 1.5 - 0.3 * j + 0.05 * a, 0.5 * len, 0.01 * (j - 1.5), 0.02 + 0.005 * a);
      parent = child;
    }
  }
  return x + "</robot>\n";
}

// n poses: random joints, gravity tilted up to 30 degrees from level.
Samples random_poses(const Model& model, int n, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Samples s;
  s.source = "poses.csv";
  s.q.resize(n, model.num_joints());
  s.gravity.resize(n, 3);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < model.num_joints(); ++j) s.q(i, j) = -M_PI + 2 * M_PI * u(rng);
    const double tilt = 30.0 * M_PI / 180.0 * std::sqrt(u(rng)), dir = 2 * M_PI * u(rng);
    s.gravity.row(i) << std::sin(tilt) * std::cos(dir), std::sin(tilt) * std::sin(dir),
        -std::cos(tilt);
    s.gravity.row(i) *= kStandardGravity;
  }
  for (int i = 0; i < n; ++i) s.line.push_back(i + 2);
  return s;
}

// The former noise estimate, computed here on its own: sigma_k^2 = SSR_k /
// (N - p/6) for every axis, iterated four times from unit weights; the
// covariance (A' W A)^-1. Returns the standard deviations.
Eigen::VectorXd shared_dof_stddev(const Eigen::MatrixXd& A, const Eigen::VectorXd& y) {
  const Eigen::Index N = A.rows() / 6, p = A.cols();
  Eigen::VectorXd sigma = Eigen::VectorXd::Ones(6), x;
  Eigen::MatrixXd cov;
  for (int it = 0; it < 4; ++it) {
    Eigen::MatrixXd Aw = A;
    Eigen::VectorXd yw = y;
    for (Eigen::Index r = 0; r < A.rows(); ++r) {
      Aw.row(r) /= sigma[r % 6];
      yw[r] /= sigma[r % 6];
    }
    x = Aw.colPivHouseholderQr().solve(yw);
    cov = (Aw.transpose() * Aw).inverse();
    const Eigen::VectorXd r = y - A * x;
    for (int k = 0; k < 6; ++k) {
      double ssr = 0.0;
      for (Eigen::Index i = 0; i < N; ++i) ssr += r[6 * i + k] * r[6 * i + k];
      sigma[k] = std::sqrt(ssr / (static_cast<double>(N) - static_cast<double>(p) / 6.0));
    }
  }
  return cov.diagonal().cwiseSqrt();
}

struct ManyArms : ::testing::Test {
  const Model model = load_urdf_string(many_arms_urdf(8));
  const BaseParameters base = find_base_parameters(model);
  const Eigen::VectorXd truth = base.K * nominal_standard_parameters(model);
};

TEST_F(ManyArms, HasManyBaseParametersMostlyOnTheMomentAxes) {
  EXPECT_GE(base.num_mass(), 60);
  EXPECT_EQ(model.num_joints(), 32);
}

TEST_F(ManyArms, StandardDeviationsAreHonestWhenUnknownsApproachTheEquations) {
  // 50 poses, 6N = 300 equations for ~68 unknowns, all but M on the three
  // moment axes, and mostly on mx and my (gravity within 30 degrees of -z:
  // the moment h x g lies nearly in the xy plane): their residuals keep about
  // N - p/2 degrees of freedom each, not N - p/6.
  const int N = 50, seeds = 100;
  const Samples plan = random_poses(model, N, 3);
  const Eigen::MatrixXd A = stacked_regressor(model, base, plan);
  double z2 = 0, z2_given = 0, z2_shared = 0;
  Eigen::Matrix<double, 6, 1> dof = Eigen::Matrix<double, 6, 1>::Zero();
  for (int seed = 1; seed <= seeds; ++seed) {
    SimulateOptions so;
    so.noise_force = 0.05;
    so.noise_moment = 0.005;
    so.seed = seed;
    Samples s = plan;
    s.wrench = simulate_wrenches(model, s, so);
    const IdentifySummary r = identify(model, base, s);
    z2 += (r.value - truth).cwiseQuotient(r.stddev).squaredNorm();
    dof += r.residual_dof;
    IdentifyOptions given;
    given.sigma_force = so.noise_force;
    given.sigma_moment = so.noise_moment;
    const IdentifySummary g = identify(model, base, s, given);
    z2_given += (g.value - truth).cwiseQuotient(g.stddev).squaredNorm();
    Eigen::VectorXd y(6 * N);
    for (int i = 0; i < N; ++i) y.segment<6>(6 * i) = s.wrench.row(i).transpose();
    z2_shared += (r.value - truth).cwiseQuotient(shared_dof_stddev(A, y)).squaredNorm();
  }
  const double n = static_cast<double>(seeds) * base.num_mass();
  const double rms = std::sqrt(z2 / n), rms_given = std::sqrt(z2_given / n),
               rms_shared = std::sqrt(z2_shared / n);
  dof /= seeds;
  RecordProperty("normalised_error_rms", fmt::format("{:.3f}", rms));
  RecordProperty("normalised_error_rms_shared_dof", fmt::format("{:.3f}", rms_shared));
  std::cout << fmt::format(
      "p = {}, N = {}: normalised error rms {:.3f} (true sigma given {:.3f}, former N - p/6 "
      "{:.3f}); mean residual dof fx..mz {:.2f} {:.2f} {:.2f} {:.2f} {:.2f} {:.2f}\n",
      base.num_mass(), N, rms, rms_given, rms_shared, dof[0], dof[1], dof[2], dof[3], dof[4],
      dof[5]);
  EXPECT_GT(rms, 0.85);
  EXPECT_LT(rms, 1.15);
  EXPECT_GT(rms_given, 0.85);
  EXPECT_LT(rms_given, 1.15);
  EXPECT_GT(rms_shared, 1.25);  // the former estimate: std about 1.3x too small here
  // The force axes see M alone: almost every residual is free.
  for (int k = 0; k < 3; ++k) EXPECT_GT(dof[k], N - 1.0);
  EXPECT_LT(dof.tail<3>().minCoeff(), N - base.num_mass() / 3.0);
}

TEST_F(ManyArms, ResidualDegreesOfFreedomAreTheHatMatrixTrace) {
  const Samples plan = random_poses(model, 40, 5);
  Samples s = plan;
  SimulateOptions so;
  so.noise_force = 0.05;
  so.noise_moment = 0.005;
  s.wrench = simulate_wrenches(model, s, so);
  IdentifyOptions given;  // fixed weights: the leverages are those of these weights
  given.sigma_force = 0.04;
  given.sigma_moment = 0.006;
  const IdentifySummary r = identify(model, base, s, given);
  // H = W^1/2 A (A' W A)^-1 A' W^1/2, its diagonal summed over each axis' rows.
  Eigen::MatrixXd Aw = stacked_regressor(model, base, s);
  for (Eigen::Index i = 0; i < Aw.rows(); ++i) Aw.row(i) /= i % 6 < 3 ? 0.04 : 0.006;
  const Eigen::MatrixXd H = Aw * (Aw.transpose() * Aw).inverse() * Aw.transpose();
  const int N = s.size();
  for (int k = 0; k < 6; ++k) {
    double trace = 0.0;
    for (int i = 0; i < N; ++i) trace += H(6 * i + k, 6 * i + k);
    EXPECT_NEAR(r.residual_dof[k], N - trace, 1e-7) << k;
  }
  EXPECT_NEAR(r.residual_dof.sum(), 6.0 * N - base.num_unknowns(), 1e-7);

  // The streamed fit computes the same from its per-axis factors.
  const IdentifySummary st = identify_streaming(model, base, s, given);
  EXPECT_LT((st.residual_dof - r.residual_dof).cwiseAbs().maxCoeff(), 1e-8);
  const IdentifySummary e = identify(model, base, s), se = identify_streaming(model, base, s);
  EXPECT_LT((se.residual_dof - e.residual_dof).cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_LT(((se.sigma - e.sigma).array() / e.sigma.array()).abs().maxCoeff(), 1e-9);
  EXPECT_LT(((se.stddev - e.stddev).array() / e.stddev.array()).abs().maxCoeff(), 1e-8);
}

TEST_F(ManyArms, FewResidualDegreesOfFreedomAreAWarning) {
  SimulateOptions so;
  so.noise_force = 0.05;
  so.noise_moment = 0.005;
  // Just enough poses (2N + 1 >= p): mx and my keep about N - p/2 dof.
  const int N = base.num_mass() / 2 + 2;
  Samples few = random_poses(model, N, 7);
  few.wrench = simulate_wrenches(model, few, so);
  const IdentifySummary r = identify(model, base, few);
  ASSERT_LT(r.residual_dof.segment<2>(3).maxCoeff(), kFewResidualDof);  // mx, my
  ASSERT_GE(r.residual_dof[5], kFewResidualDof);                        // mz: h x g ~ in xy
  std::string all;
  bool noise_hints = false;
  for (const Warning& w : identify_warnings(r, "few.csv")) {
    all += w.message;
    noise_hints |= w.hints == std::vector<Hint>{{Hint::Setting::SigmaForce, ""},
                                                {Hint::Setting::SigmaMoment, ""}};
  }
  EXPECT_TRUE(noise_hints) << all;
  EXPECT_NE(all.find(fmt::format("few.csv: {} samples for {} unknowns leave few degrees of freedom",
                                 N, base.num_unknowns())),
            std::string::npos)
      << all;
  EXPECT_NE(all.find(fmt::format("mx {:.3g}", r.residual_dof[3])), std::string::npos) << all;
  EXPECT_NE(all.find(fmt::format("my {:.3g}", r.residual_dof[4])), std::string::npos) << all;
  EXPECT_EQ(all.find("fx "), std::string::npos) << all;  // the force axes have plenty
  EXPECT_EQ(all.find("mz "), std::string::npos) << all;
  const int needed = N + static_cast<int>(std::ceil(10.0 - r.residual_dof.tail<3>().minCoeff()));
  EXPECT_NE(all.find(fmt::format("record at least {} samples", needed)), std::string::npos) << all;
  // The sensor's noise given: no estimate to doubt.
  IdentifyOptions given;
  given.sigma_force = 0.05;
  given.sigma_moment = 0.005;
  EXPECT_TRUE(identify_warnings(identify(model, base, few, given), "few.csv").empty());
  // Enough poses: no warning.
  Samples many = random_poses(model, 2 * N, 7);
  many.wrench = simulate_wrenches(model, many, so);
  EXPECT_TRUE(identify_warnings(identify(model, base, many), "many.csv").empty());
}

TEST_F(ManyArms, TooFewPosesSayTheCountFirstInOneShortLine) {
  const int p = base.num_unknowns();
  Samples s = random_poses(model, 20, 9);  // 2 N + 1 = 41 equations at best
  s.wrench = simulate_wrenches(model, s);
  const std::string msg = identifiability_message(model, base, s);
  // Independently: a pose at rest gives two moment equations (m = H x g is
  // normal to g) and the force M: K poses determine p unknowns once 2K + 1 >= p,
  // and random poses do.
  const int needed = (p - 1 + 1) / 2;
  const auto rank = [&](int n) {
    Eigen::MatrixXd A = stacked_regressor(model, base, random_poses(model, n, 11));
    const Eigen::VectorXd scale = A.colwise().norm().cwiseInverse().transpose();
    A = A * scale.asDiagonal();
    const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(A).singularValues();
    return static_cast<int>((sv.array() > 1e-9 * sv[0]).count());
  };
  ASSERT_EQ(rank(20), 41);
  ASSERT_EQ(rank(needed), p);
  ASSERT_LT(rank(needed - 1), p);
  EXPECT_EQ(msg.rfind(fmt::format("poses.csv: 20 poses give at most 41 independent equations for "
                                  "{} unknowns: record at least {} poses",
                                  p, needed),
                      0),
            0u)
      << msg;
  EXPECT_EQ(msg.find('\n'), std::string::npos) << msg;
  EXPECT_LT(msg.size(), 700u) << msg;
  EXPECT_NE(msg.find(" more)"), std::string::npos) << msg;  // the list is cut
  EXPECT_EQ(msg.find("move joint"), std::string::npos) << msg;
  // The streamed fit says the same.
  try {
    identify_streaming(model, base, s);
    ADD_FAILURE() << "expected IdentifiabilityError";
  } catch (const IdentifiabilityError& e) {
    EXPECT_EQ(std::string(e.what()), msg);
  }
}

}  // namespace
}  // namespace massid
