// A tool on a wrist sensor (issue 27 item 4): design --dynamic plans the arm's
// motion. Checked on the trajectory it writes: the arm's joints move within
// their limits less a 10 % margin, the tool stays above the floor and the arm
// clear of itself (forward kinematics and distances computed here, by
// AngleAxis and by sampling the segments), the tool's ten parameters have a
// condition number below 50 (an SVD of the stacked, noise-weighted,
// column-scaled regressor), and design -> simulate -> identify recovers them
// within 4 std; held joints (--fixed) stay in the written trajectory.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <Eigen/SVD>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"

namespace {

using namespace massid_cli_test;

const std::string kUrWristUrdf = kSource + "/tests/data/ur_wrist_ft.urdf";
const std::vector<std::string> kWristHeld = {"--fixed", "finger_joint=0.02"};

class CliWrist : public Cli {
 protected:
  // design --dynamic for the tool on the UR5-like arm's wrist sensor, a
  // short run (20 s at 100 Hz, 1500 evaluations).
  Result design_wrist(const std::string& name, const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args{
        "design",   kUrWristUrdf,    "--sensor", "ft_sensor", "--dynamic", "-o",
        path(name), "--duration",    "20",       "--period",  "10",        "--rate",
        "100",      "--evaluations", "1500"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run(args);
  }
};

// The printed figure after `label` (up to the next ':' then a number).
double wrist_printed(const std::string& out, const std::string& label) {
  const size_t at = out.find(label);
  if (at == std::string::npos) return std::numeric_limits<double>::quiet_NaN();
  const size_t colon = out.find(':', at + label.size());
  return std::stod(out.substr(colon + 1));
}

// The number right after `label`.
double wrist_after(const std::string& out, const std::string& label) {
  const size_t at = out.find(label);
  if (at == std::string::npos) return std::numeric_limits<double>::quiet_NaN();
  return std::stod(out.substr(at + label.size()));
}

// Root-frame poses of the chain's link origins, by AngleAxis (independent of
// the library's kinematics).
std::vector<Eigen::Isometry3d> wrist_chain(const massid::Model& m, const Eigen::VectorXd& qu) {
  std::vector<Eigen::Isometry3d> out;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (const massid::ChainStep& s : m.upstream) {
    T = T * s.origin;
    if (s.joint_index >= 0)
      T = T * Eigen::AngleAxisd(s.joint_scale * qu[s.joint_index] + s.joint_offset, s.axis);
    out.push_back(T);
  }
  return out;
}

// Least distance of two segments, by sampling each at 200 points.
double wrist_sampled_distance(const Eigen::Vector3d& a0, const Eigen::Vector3d& a1,
                              const Eigen::Vector3d& b0, const Eigen::Vector3d& b1) {
  double d = std::numeric_limits<double>::infinity();
  for (int i = 0; i <= 200; ++i)
    for (int j = 0; j <= 200; ++j)
      d = std::min(d, ((a0 + (a1 - a0) * (i / 200.0)) - (b0 + (b1 - b0) * (j / 200.0))).norm());
  return d;
}

TEST_F(CliWrist, DesignMovesTheArmWithinMarginsAboveTheFloorAndConditionsTheToolBelow50) {
  const Result r = design_wrist("traj.csv", kWristHeld);
  ASSERT_EQ(r.code, 0) << r;
  const double printed = wrist_printed(r.out, "condition number of the tool's parameters");
  EXPECT_LT(printed, 50.0) << r.out;
  const massid::Model urdf = massid::load_urdf(kUrWristUrdf, "ft_sensor");
  const massid::Model model = massid::hold_joints(urdf, {{"finger_joint", 0.02}});
  ASSERT_EQ(model.num_upstream_joints(), 6);
  ASSERT_EQ(model.num_joints(), 0);
  const Table t = read_table(path("traj.csv"));
  ASSERT_GT(t.rows.size(), 1000u);
  // The arm's joints move, within their limits less 10 %; the held finger stays.
  for (const massid::Joint& j : model.upstream_joints) {
    double lo = 1e9, hi = -1e9;
    for (size_t i = 0; i < t.rows.size(); ++i) {
      lo = std::min(lo, t.num(i, j.name));
      hi = std::max(hi, t.num(i, j.name));
    }
    EXPECT_GT(hi - lo, 0.1) << j.name;
    const double margin = 0.1 * (j.upper - j.lower);
    EXPECT_GE(lo, j.lower + margin - 1e-9) << j.name;
    EXPECT_LE(hi, j.upper - margin + 1e-9) << j.name;
  }
  for (size_t i = 0; i < t.rows.size(); ++i) {
    ASSERT_EQ(t.num(i, "finger_joint"), 0.02);
    ASSERT_EQ(t.num(i, "finger_joint_vel"), 0.0);
  }
  EXPECT_EQ(t.col("gx"), -1);  // gravity follows from the arm's joints

  // Above the floor (z = 0 of the root) by 5 cm and the bodies that no single
  // body joins 5 cm apart, every tenth row.
  const Eigen::Vector3d gripper_com(0.004, -0.002, 0.055 + 0.02);
  double lowest = 1e9, least = 1e9;
  for (size_t i = 0; i < t.rows.size(); i += 10) {
    Eigen::VectorXd qu(6);
    for (int u = 0; u < 6; ++u) qu[u] = t.num(i, model.upstream_joints[u].name);
    const std::vector<Eigen::Isometry3d> chain = wrist_chain(model, qu);
    // Bodies: points after each movable joint; the tool with the last.
    std::vector<std::vector<Eigen::Vector3d>> bodies(1, {Eigen::Vector3d::Zero()});
    for (size_t k = 0; k < chain.size(); ++k) {
      bodies.back().push_back(chain[k].translation());
      if (model.upstream[k].joint_index >= 0) {
        bodies.push_back({chain[k].translation()});
        lowest = std::min(lowest, chain[k].translation().z());
      }
    }
    const Eigen::Vector3d com = chain.back() * gripper_com;
    lowest = std::min(lowest, com.z());
    bodies.back().push_back(com);
    for (size_t a = 0; a < bodies.size(); ++a)
      for (size_t b = a + 2; b < bodies.size(); ++b)
        for (size_t x = 0; x + 1 < bodies[a].size(); ++x)
          for (size_t y = 0; y + 1 < bodies[b].size(); ++y)
            least = std::min(least, wrist_sampled_distance(bodies[a][x], bodies[a][x + 1],
                                                           bodies[b][y], bodies[b][y + 1]));
  }
  EXPECT_GE(lowest, 0.05 - 1e-6);
  EXPECT_GE(least, 0.05 - 2e-3);  // sampled at 1/200 of a segment

  // The tool's condition number, independently: SVD of the stacked regressor,
  // rows over their noise, unit-norm columns.
  massid::SampleOptions read;
  const massid::Samples s = massid::read_samples(model, massid::read_csv(path("traj.csv")),
                                                 massid::WrenchColumns::Optional, read);
  ASSERT_TRUE(s.has_sensor_motion());
  massid::BaseParameterOptions bo;
  bo.layout = massid::ParameterLayout::full();
  bo.sensor_moving = true;
  const massid::BaseParameters base = massid::find_base_parameters(model, bo);
  ASSERT_EQ(base.num_unknowns(), 10);
  Eigen::MatrixXd A = massid::stacked_regressor(model, base, s);
  for (Eigen::Index row = 0; row < A.rows(); ++row) A.row(row) /= row % 6 < 3 ? 0.1 : 0.01;
  for (Eigen::Index c = 0; c < A.cols(); ++c) A.col(c).normalize();
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(A).singularValues();
  const double cond = sv[0] / sv[sv.size() - 1];
  EXPECT_LT(cond, 50.0);
  EXPECT_NEAR(printed, cond, 0.01 * cond) << r.out;
}

TEST_F(CliWrist, DesignSimulateIdentifyRecoversTheToolWithinFourStd) {
  ASSERT_EQ(design_wrist("traj.csv", kWristHeld).code, 0);
  // Noise-free, the held finger's constant column gives the wrench --fixed does.
  for (const bool held : {true, false}) {
    std::vector<std::string> args{
        "simulate", kUrWristUrdf, path("traj.csv"), "-o", path(held ? "held.csv" : "read.csv"),
        "--sensor", "ft_sensor",  "--dynamic"};
    if (held) args.insert(args.end(), kWristHeld.begin(), kWristHeld.end());
    ASSERT_EQ(run(args).code, 0);
  }
  const Table held = read_table(path("held.csv")), read = read_table(path("read.csv"));
  ASSERT_EQ(held.rows.size(), read.rows.size());
  for (size_t i = 0; i < held.rows.size(); i += 97)
    for (const char* axis : {"fx", "fy", "fz", "mx", "my", "mz"})
      ASSERT_NEAR(held.num(i, axis), read.num(i, axis), 1e-12) << axis << " row " << i;
  // The held finger: simulate and identify are told (--fixed), the column is
  // in the trajectory all the same.
  Result r = run({"simulate", kUrWristUrdf, path("traj.csv"), "-o", path("data.csv"), "--sensor",
                  "ft_sensor", "--dynamic", "--fixed", "finger_joint=0.02", "--noise-force", "0.1",
                  "--noise-moment", "0.01", "--seed", "3"});
  ASSERT_EQ(r.code, 0) << r;
  r = run({"identify", kUrWristUrdf, path("data.csv"), "--sensor", "ft_sensor", "--dynamic",
           "--fixed", "finger_joint=0.02", "-o", path("params.json")});
  ASSERT_EQ(r.code, 0) << r;
  const massid::ParamsFile params = massid::read_params(path("params.json"));
  const massid::Model model =
      massid::hold_joints(massid::load_urdf(kUrWristUrdf, "ft_sensor"), {{"finger_joint", 0.02}});
  const massid::BaseParameters base =
      massid::find_base_parameters(model, massid::base_parameter_options(params));
  ASSERT_EQ(base.num_mass(), 10);
  const Eigen::VectorXd truth = base.K * massid::ParameterLayout::full().nominal(model);
  const Eigen::VectorXd fitted = massid::values_in_basis(params, model, base);
  ASSERT_EQ(params.base_parameters.size(), 10u);
  for (int i = 0; i < 10; ++i) {
    const double sd = params.base_parameters[i].stddev;
    ASSERT_GT(sd, 0.0);
    EXPECT_LT(std::abs(fitted[i] - truth[i]), 4.0 * sd)
        << base.params[i].name << " " << base.params[i].expression << ": " << fitted[i] << " vs "
        << truth[i] << " (std " << sd << ")";
  }
  EXPECT_NEAR(params.total_mass, 1.0, 0.02);
}

TEST_F(CliWrist, TheFingerMovesUnlessHeldAndTwoConditionNumbersArePrinted) {
  const Result r = design_wrist("traj.csv");
  ASSERT_EQ(r.code, 0) << r;
  const double tool = wrist_printed(r.out, "condition number of the tool's 10 parameters");
  const double all = wrist_printed(r.out, "condition number of all the identified parameters");
  EXPECT_TRUE(std::isfinite(tool)) << r.out;
  EXPECT_TRUE(std::isfinite(all)) << r.out;
  const Table t = read_table(path("traj.csv"));
  double lo = 1e9, hi = -1e9;
  for (size_t i = 0; i < t.rows.size(); ++i) {
    lo = std::min(lo, t.num(i, "finger_joint"));
    hi = std::max(hi, t.num(i, "finger_joint"));
  }
  EXPECT_GT(hi - lo, 0.005);
  EXPECT_GE(lo, 0.004 - 1e-9);
  EXPECT_LE(hi, 0.036 + 1e-9);
}

TEST_F(CliWrist, TheClearancesBindAndAreRefusedWithoutAnArm) {
  // A floor raised to 0.3 m: the tool keeps above it (the default design goes lower).
  Result r = design_wrist("low.csv", kWristHeld);
  ASSERT_EQ(r.code, 0) << r;
  const double low = wrist_after(r.out, "; lowest ");
  r = design_wrist("high.csv", {"--fixed", "finger_joint=0.02", "--min-height", "0.3"});
  ASSERT_EQ(r.code, 0) << r;
  const double high = wrist_after(r.out, "; lowest ");
  EXPECT_LT(low, 0.3) << r.out;
  EXPECT_GE(high, 0.3 - 1e-9) << r.out;
  r = run({"design", kUrWristUrdf, "--dynamic", "-o", path("x.csv"), "--self-clearance", "0.1",
           "--sensor", "base_link"});
  expect_input_error(r, {"--self-clearance", "wrist"});
  // Gravity given in the sensor frame holds the arm still (the plan of a
  // sensor at the root); the arm's options then do not apply.
  r = design_wrist("t.csv", {"--tilt-max", "10", "--self-clearance", "0.1"});
  expect_input_error(r, {"--self-clearance", "--tilt-max", "one or the other"});
  r = design_wrist("t.csv", {"--tilt-max", "10"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_EQ(read_table(path("t.csv")).col("shoulder_pan_joint"), -1);
}

TEST_F(CliWrist, StaticPlanPosesTheArmAndIdentifiesTheTool) {
  Result r = run({"design", kUrWristUrdf, "--sensor", "ft_sensor", "--fixed", "finger_joint=0.02",
                  "--poses", "12", "--offset", "--candidates", "300", "-o", path("plan.csv")});
  ASSERT_EQ(r.code, 0) << r;
  const massid::Model model =
      massid::hold_joints(massid::load_urdf(kUrWristUrdf, "ft_sensor"), {{"finger_joint", 0.02}});
  const Table t = read_table(path("plan.csv"));
  ASSERT_EQ(t.rows.size(), 12u);
  EXPECT_EQ(t.col("tilt_x_deg"), -1);
  const Eigen::Vector3d gripper_com(0.004, -0.002, 0.055 + 0.02);
  for (const massid::Joint& j : model.upstream_joints) {
    double lo = 1e9, hi = -1e9;
    for (size_t i = 0; i < t.rows.size(); ++i) {
      lo = std::min(lo, t.num(i, j.name));
      hi = std::max(hi, t.num(i, j.name));
    }
    const double margin = 0.1 * (j.upper - j.lower);
    EXPECT_GE(lo, j.lower + margin - 1e-9) << j.name;
    EXPECT_LE(hi, j.upper - margin + 1e-9) << j.name;
  }
  double moved = 0.0;
  for (size_t i = 0; i < t.rows.size(); ++i) {
    Eigen::VectorXd qu(6);
    for (int u = 0; u < 6; ++u) qu[u] = t.num(i, model.upstream_joints[u].name);
    const std::vector<Eigen::Isometry3d> chain = wrist_chain(model, qu);
    // gx,gy,gz: the root gravity in the sensor frame of that arm pose.
    const Eigen::Vector3d g =
        chain.back().linear().transpose() * Eigen::Vector3d(0.0, 0.0, -9.80665);
    EXPECT_NEAR(t.num(i, "gx"), g.x(), 1e-9);
    EXPECT_NEAR(t.num(i, "gy"), g.y(), 1e-9);
    EXPECT_NEAR(t.num(i, "gz"), g.z(), 1e-9);
    EXPECT_GE((chain.back() * gripper_com).z(), 0.05 - 1e-9);
    if (i > 0) moved += std::abs(t.num(i, "elbow_joint") - t.num(0, "elbow_joint"));
  }
  EXPECT_GT(moved, 0.1);
  // --evaluate of the plan reads the arm's columns and gives its figures.
  const Result e = run({"design", kUrWristUrdf, "--sensor", "ft_sensor", "--fixed",
                        "finger_joint=0.02", "--offset", "--evaluate", path("plan.csv")});
  ASSERT_EQ(e.code, 0) << e;
  EXPECT_NEAR(wrist_printed(e.out, "condition number (eq. 36"),
              wrist_printed(r.out, "condition number (eq. 36"), 1e-3)
      << e.out << r.out;
  // The order's travel counts the arm's joints; no platform tilts.
  double travel = 0.0;
  for (size_t i = 1; i < t.rows.size(); ++i)
    for (const massid::Joint& j : model.upstream_joints)
      travel += std::abs(t.num(i, j.name) - t.num(i - 1, j.name));
  EXPECT_NE(r.out.find("order: 0 tilt changes"), std::string::npos) << r.out;
  EXPECT_NEAR(wrist_after(r.out, "joint travel "), travel, 0.005 * travel) << r.out;
  r = run({"simulate", kUrWristUrdf, path("plan.csv"), "-o", path("data.csv"), "--sensor",
           "ft_sensor", "--fixed", "finger_joint=0.02", "--noise-force", "0.05", "--noise-moment",
           "0.005", "--sensor-offset", "1,2,3,0.1,0.2,0.3", "--repeat", "20"});
  ASSERT_EQ(r.code, 0) << r;
  r = run({"identify", kUrWristUrdf, path("data.csv"), "--sensor", "ft_sensor", "--offset",
           "--fixed", "finger_joint=0.02", "-o", path("params.json")});
  ASSERT_EQ(r.code, 0) << r;
  const massid::ParamsFile params = massid::read_params(path("params.json"));
  EXPECT_NEAR(params.total_mass, 1.0, 0.01);
}

}  // namespace
