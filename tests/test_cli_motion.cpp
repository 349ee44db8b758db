// The command-line tool in motion, as a user runs it: design --dynamic ->
// simulate --dynamic -> identify --dynamic -> predict on another trajectory;
// the same from positions only (derivatives filtered); a tool on a wrist
// sensor from the arm's joints; the errors of motion logs. The numbers are
// checked against the URDF (total mass, the base parameters' true values
// from `model --dynamic`'s terms evaluated on the URDF's inertials) and
// against the simulated wrench, not against massid's own output.
#include <fmt/format.h>

#include <Eigen/Core>
#include <Eigen/SVD>
#include <cmath>
#include <random>

#include "cli_support.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"
#include "massid/core/parameters.hpp"
#include "massid/core/regressor.hpp"
#include "massid/io/urdf.hpp"

namespace massid_cli_test {
namespace {

class CliMotion : public Cli {
 protected:
  // A trajectory of ur_like (design --dynamic, a short search) and its simulated log.
  std::string trajectory(const std::string& name, int seed, double duration, double rate) {
    const Result r = run({"design", kUrUrdf, "--dynamic", "-o", path(name), "--duration",
                          std::to_string(duration), "--rate", std::to_string(rate), "--seed",
                          std::to_string(seed), "--evaluations", "1000"});
    EXPECT_EQ(r.code, 0) << r;
    return path(name);
  }
  std::string simulate(const std::string& traj, const std::string& name,
                       std::vector<std::string> extra = {}) {
    std::vector<std::string> args{"simulate", kUrUrdf, traj, "-o", path(name), "--dynamic"};
    args.insert(args.end(), extra.begin(), extra.end());
    const Result r = run(args);
    EXPECT_EQ(r.code, 0) << r;
    return path(name);
  }
};

// The true value of every base parameter of a params file: its terms on the URDF.
double true_value(const massid::Model& model, const json& p) {
  const Eigen::VectorXd pi = massid::ParameterLayout::full().nominal(model);
  double v = 0.0;
  for (const auto& t : p["terms"])
    v += t["coef"].get<double>() *
         pi[massid::ParameterLayout::full().index(
             model.find_link(t["link"]), massid::ParameterLayout::kind_from_name(t["param"]))];
  return v;
}

TEST_F(CliMotion, DesignSimulateIdentifyPredict) {
  const std::string traj = trajectory("traj.csv", 1, 20.0, 500.0);
  const Table t = read_table(traj);
  EXPECT_EQ(t.rows.size(), 10001u);
  for (const char* c : {"t", "shoulder_pan_joint", "shoulder_pan_joint_vel",
                        "shoulder_pan_joint_acc", "gx", "gy", "gz"})
    EXPECT_GE(t.col(c), 0) << c;
  const std::string log = simulate(
      traj, "log.csv",
      {"--noise-force", "0.1", "--noise-moment", "0.01", "--sensor-offset", "1,2,3,0.1,0.2,0.3"});
  Result r = run({"identify", kUrUrdf, log, "--dynamic", "--offset", "-o", path("params.json")});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_NE(r.out.find("condition number (all rows"), std::string::npos) << r;
  const json params = json::parse(read_file(path("params.json")));
  EXPECT_EQ(params["model"], "dynamic");
  EXPECT_EQ(params["motion"]["gravity"], "fixed");
  EXPECT_EQ(params["base_parameters"].size(), 40u);  // level, with offsets
  const massid::Model model = massid::load_urdf(kUrUrdf);
  for (const auto& p : params["base_parameters"])
    EXPECT_NEAR(p["value"].get<double>(), true_value(model, p), 4 * p["std"].get<double>())
        << p["name"] << " = " << p["expression"];

  // Another trajectory, noise-free and without offset: predict's fx_pred .. mz_pred
  // plus the identified offsets (which hold the true offsets and the constants
  // level data cannot tell from them: the weight in fz ...) are the wrench;
  // fx_comp .. mz_comp = measured - fx_pred - offset.
  const std::string other = simulate(trajectory("other.csv", 7, 8.0, 200.0), "other_log.csv");
  r = run({"predict", kUrUrdf, path("params.json"), other, "-o", path("pred.csv")});
  ASSERT_EQ(r.code, 0) << r;
  const Table pred = read_table(path("pred.csv"));
  const double offset[6] = {1, 2, 3, 0.1, 0.2, 0.3};
  const char* axes[6] = {"fx", "fy", "fz", "mx", "my", "mz"};
  const json& so = params["sensor_offset"];
  for (int k = 0; k < 6; ++k) {
    const double identified = so[k < 3 ? "force" : "moment"][k % 3].get<double>();
    double lo = 1e300, hi = -1e300, worst = 0, comp = 0;
    for (size_t i = 0; i < pred.rows.size(); ++i) {
      const double w = pred.num(i, axes[k]);
      const double p = pred.num(i, std::string(axes[k]) + "_pred");
      lo = std::min(lo, w);
      hi = std::max(hi, w);
      worst = std::max(worst, std::abs(p + identified - offset[k] - w));
      comp = std::max(comp,
                      std::abs(pred.num(i, std::string(axes[k]) + "_comp") - (w - p - identified)));
    }
    EXPECT_LT(worst, 0.01 * (hi - lo)) << axes[k];
    EXPECT_LT(comp, 1e-9 * (1 + hi - lo)) << axes[k];
  }
}

TEST_F(CliMotion, FromPositionsOnlyWithTheFilter) {
  const std::string traj = trajectory("traj.csv", 3, 20.0, 1000.0);
  const std::string log =
      simulate(traj, "log.csv", {"--noise-force", "0.1", "--noise-moment", "0.01"});
  // Drop the _vel and _acc columns.
  const Table p = without_columns(read_table(log), [](const std::string& name) {
    return name.find("_vel") != std::string::npos || name.find("_acc") != std::string::npos;
  });
  write_file(path("positions.csv"), to_csv(p));
  Result r =
      run({"identify", kUrUrdf, path("positions.csv"), "--dynamic", "-o", path("params.json")});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_NE(r.out.find("derived from t and the positions"), std::string::npos) << r;
  EXPECT_NE(r.out.find("10 Hz"), std::string::npos) << r;  // the default cutoff, said
  const json params = json::parse(read_file(path("params.json")));
  const massid::Model model = massid::load_urdf(kUrUrdf);
  EXPECT_EQ(params["base_parameters"].size(), 43u);
  for (const auto& q : params["base_parameters"])
    EXPECT_NEAR(q["value"].get<double>(), true_value(model, q), 4 * q["std"].get<double>())
        << q["name"] << " = " << q["expression"];
  EXPECT_NEAR(params["total_mass"].get<double>(), model.nominal_total_mass(), 0.01);

  // A lower cutoff is applied and said.
  r = run({"identify", kUrUrdf, path("positions.csv"), "--dynamic", "--cutoff", "5", "-o",
           path("params5.json")});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_NE(r.out.find("5 Hz"), std::string::npos) << r;
}

TEST_F(CliMotion, ToolOnAWristSensorFromTheArmJoints) {
  const std::string traj = trajectory("traj.csv", 5, 20.0, 500.0);
  // The arm's joints give the wrist's motion and gravity: drop gx,gy,gz.
  const Table p = without_columns(read_table(traj), [](const std::string& name) {
    return name == "gx" || name == "gy" || name == "gz";
  });
  write_file(path("arm.csv"), to_csv(p));
  const std::string log =
      simulate(path("arm.csv"), "wrist.csv",
               {"--sensor", "wrist_3_link", "--noise-force", "0.05", "--noise-moment", "0.005"});
  Result r = run(
      {"identify", kUrUrdf, log, "--dynamic", "--sensor", "wrist_3_link", "-o", path("tool.json")});
  ASSERT_EQ(r.code, 0) << r;
  const json params = json::parse(read_file(path("tool.json")));
  EXPECT_EQ(params["base_parameters"].size(), 10u);  // all ten of the tool
  EXPECT_EQ(params["motion"]["sensor_moving"], true);
  // The joints whose columns the fit used: the arm's, above the sensor link.
  const std::vector<std::string> arm{"shoulder_pan_joint", "shoulder_lift_joint", "elbow_joint",
                                     "wrist_1_joint",      "wrist_2_joint",       "wrist_3_joint"};
  EXPECT_EQ(params["joints"].get<std::vector<std::string>>(), arm);
  EXPECT_EQ(params["upstream_joints"].get<std::vector<std::string>>(), arm);
  const massid::Model wrist = massid::load_urdf(kUrUrdf, "wrist_3_link");
  for (const auto& q : params["base_parameters"])
    EXPECT_NEAR(q["value"].get<double>(), true_value(wrist, q), 4 * q["std"].get<double>())
        << q["name"] << " = " << q["expression"];
}

// A log in degrees throughout (JOINT_deg, JOINT_deg_vel, JOINT_deg_acc) is
// read as the same log in radians: the same fit. A _vel column scaled 2x (a
// driver's unit) is refused by joint-derivatives, naming the column and the
// scale; --no-checks lets it through.
TEST_F(CliMotion, DegreesThroughoutAndAScaledVelocityColumn) {
  const std::string log = simulate(trajectory("traj.csv", 11, 6.0, 250.0), "log.csv",
                                   {"--noise-force", "0.05", "--noise-moment", "0.005"});
  const Table rad = read_table(log);
  const massid::Model model = massid::load_urdf(kUrUrdf);
  Table deg = rad;
  for (const massid::Joint& j : model.joints)
    for (const std::string suffix : {"", "_vel", "_acc"}) {
      const int c = deg.col(j.name + suffix);
      ASSERT_GE(c, 0) << j.name << suffix;
      deg.header[c] = j.name + "_deg" + suffix;
      for (auto& row : deg.rows) row[c] = fmt::format("{:.17g}", std::stod(row[c]) * 180.0 / M_PI);
    }
  write_file(path("deg.csv"), to_csv(deg));
  Result r = run({"identify", kUrUrdf, log, "--dynamic", "-o", path("rad.json")});
  ASSERT_EQ(r.code, 0) << r;
  r = run({"identify", kUrUrdf, path("deg.csv"), "--dynamic", "-o", path("deg.json")});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_EQ(r.out.find("derived from t"), std::string::npos) << r;  // the columns were read
  const json a = json::parse(read_file(path("rad.json")));
  const json b = json::parse(read_file(path("deg.json")));
  ASSERT_EQ(a["base_parameters"].size(), b["base_parameters"].size());
  for (size_t i = 0; i < a["base_parameters"].size(); ++i) {
    const double va = a["base_parameters"][i]["value"].get<double>();
    const double sa = a["base_parameters"][i]["std"].get<double>();
    EXPECT_NEAR(b["base_parameters"][i]["value"].get<double>(), va, 1e-6 * (std::abs(va) + sa))
        << a["base_parameters"][i]["name"];
  }

  // shoulder_lift_joint_vel twice the derivative of shoulder_lift_joint.
  Table twice = rad;
  const int v = twice.col("shoulder_lift_joint_vel");
  for (auto& row : twice.rows) row[v] = fmt::format("{:.17g}", 2 * std::stod(row[v]));
  write_file(path("twice.csv"), to_csv(twice));
  r = run({"identify", kUrUrdf, path("twice.csv"), "--dynamic", "-o", path("twice.json")});
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_NE(r.err.find("column 'shoulder_lift_joint_vel' is 2 times the derivative of column "
                       "'shoulder_lift_joint'"),
            std::string::npos)
      << r;
  EXPECT_FALSE(fs::exists(path("twice.json")));
  r = run({"identify", kUrUrdf, path("twice.csv"), "--dynamic", "--no-checks", "-o",
           path("twice.json")});
  EXPECT_EQ(r.code, 0) << r;
  // The degrees log with its velocities declared as rad/s: 57.3, and the fix.
  Table undeclared = deg;
  for (std::string& h : undeclared.header)
    if (h.size() > 8 && h.compare(h.size() - 8, 8, "_deg_vel") == 0)
      h = h.substr(0, h.size() - 8) + "_vel";
  write_file(path("undeclared.csv"), to_csv(undeclared));
  r = run({"identify", kUrUrdf, path("undeclared.csv"), "--dynamic", "-o", path("u.json")});
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_NE(r.err.find("'elbow_joint_vel' is 57.3 times the derivative of column "
                       "'elbow_joint_deg'"),
            std::string::npos)
      << r;
  EXPECT_NE(r.err.find("declare it as 'elbow_joint_deg_vel'"), std::string::npos) << r;
}

TEST_F(CliMotion, MotionLogErrorsNameTheFileAndLine) {
  // No velocities and no t.
  const std::string still = file("still.csv",
                                 "shoulder_pan_joint,shoulder_lift_joint,elbow_joint,wrist_1_joint,"
                                 "wrist_2_joint,wrist_3_joint,gx,gy,gz,fx,fy,fz,mx,my,mz\n"
                                 "0,0,0,0,0,0,0,0,-9.8,0,0,-229,0,0,0\n");
  expect_input_error(run({"identify", kUrUrdf, still, "--dynamic", "-o", path("p.json")}),
                     {"still.csv", "JOINT_vel", "t"});
  // Time going backwards.
  std::string text =
      "t,shoulder_pan_joint,shoulder_lift_joint,elbow_joint,wrist_1_joint,wrist_2_joint,"
      "wrist_3_joint,gx,gy,gz,fx,fy,fz,mx,my,mz\n";
  for (int i = 0; i < 3000; ++i)
    text += std::to_string(i == 1500 ? 1.0 : i * 0.001) + ",0,0,0,0,0,0,0,0,-9.8,0,0,-229,0,0,0\n";
  const std::string back = file("back.csv", text);
  const Result r = run({"identify", kUrUrdf, back, "--dynamic", "-o", path("p.json")});
  expect_input_error(r, {"back.csv:"});
  EXPECT_FALSE(fs::exists(path("p.json")));
  // simulate --dynamic without velocities.
  expect_input_error(run({"simulate", kUrUrdf, still, "-o", path("s.csv"), "--dynamic"}),
                     {"still.csv", "_vel", "design --dynamic"});
}

TEST_F(CliMotion, ModelDynamicPrintsTheCounts) {
  Result r = run({"model", kUrUrdf, "--dynamic", "--gravity", "level", "--json"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_EQ(json::parse(r.out)["base_parameters"].size(), 43u);
  r = run({"model", kUrUrdf, "--dynamic"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_NE(r.out.find("base parameters: 44"), std::string::npos) << r;
  EXPECT_NE(r.out.find("kg m^2"), std::string::npos) << r;
}

// The rank of the motion regressor stacked over random samples of a sensor
// below movable joints, computed here: the joints above the sensor link at
// random positions, moving (random velocities and accelerations: the sensor
// frame's motion and gravity from them) or held still (gravity still turned
// by their positions); the joints below at random. Columns scaled to unit
// norm, rank = singular values above 1e-9 of the largest.
int wrist_regressor_rank(const massid::Model& m, bool upstream_moves) {
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> n(0.0, 1.0);
  const int cols = massid::ParameterLayout::full().size(m), S = 400;
  const int nu = m.num_upstream_joints(), nj = m.num_joints();
  massid::KinematicsData kin(m);
  Eigen::MatrixXd Ys(6 * S, cols), Y(6, cols);
  for (int s = 0; s < S; ++s) {
    Eigen::VectorXd qu(nu), qdu = Eigen::VectorXd::Zero(nu), qddu = Eigen::VectorXd::Zero(nu);
    for (int j = 0; j < nu; ++j) {
      qu[j] = -3.0 + 6.0 * u(rng);
      if (upstream_moves) {
        qdu[j] = n(rng);
        qddu[j] = 3.0 * n(rng);
      }
    }
    Eigen::VectorXd q(nj), qd(nj), qdd(nj);
    for (int j = 0; j < nj; ++j) {
      q[j] = m.joints[j].generic_position(u(rng));
      qd[j] = n(rng);
      qdd[j] = 3.0 * n(rng);
    }
    const massid::SensorPose pose = massid::upstream_kinematics(m, qu, qdu, qddu);
    const Eigen::Vector3d g = pose.rotation.transpose() * Eigen::Vector3d(0, 0, -9.80665);
    massid::forward_kinematics(m, kin, q, qd, qdd, g, pose.motion);
    massid::motion_regressor(m, kin, Y);
    Ys.middleRows(6 * s, 6) = Y;
  }
  double largest = 0;
  for (int c = 0; c < cols; ++c) largest = std::max(largest, Ys.col(c).norm());
  Eigen::MatrixXd Z(Ys.rows(), 0);
  for (int c = 0; c < cols; ++c)
    if (Ys.col(c).norm() > 1e-10 * largest) {
      Z.conservativeResize(Eigen::NoChange, Z.cols() + 1);
      Z.col(Z.cols() - 1) = Ys.col(c) / Ys.col(c).norm();
    }
  const Eigen::VectorXd sv = Eigen::JacobiSVD<Eigen::MatrixXd>(Z).singularValues();
  return static_cast<int>((sv.array() > 1e-9 * sv[0]).count());
}

// A UR5 (as published) with a sensor `ft_sensor` on tool0 and a Robotiq 2F-85 on it.
std::string ur5_with_gripper(const std::string& dir) {
  const auto body = [](const std::string& text) {
    const size_t open = text.find('>', text.find("<robot"));
    return text.substr(open + 1, text.rfind("</robot>") - open - 1);
  };
  const std::string robots = kSource + "/tests/data/robots/";
  const std::string text =
      "<?xml version=\"1.0\"?>\n<robot name=\"ur5_gripper\">\n" +
      body(read_file(robots + "ur5_robot.urdf")) + body(read_file(robots + "robotiq_2f_85.urdf")) +
      "  <link name=\"ft_sensor\"/>\n"
      "  <joint name=\"tool0_to_sensor\" type=\"fixed\"><parent link=\"tool0\"/>"
      "<child link=\"ft_sensor\"/><origin xyz=\"0 0 0.02\" rpy=\"0 0 0\"/></joint>\n"
      "  <joint name=\"sensor_to_gripper\" type=\"fixed\"><parent link=\"ft_sensor\"/>"
      "<child link=\"robotiq_85_base_link\"/><origin xyz=\"0 0 0.02\" rpy=\"0 0 0\"/></joint>\n"
      "</robot>\n";
  const std::string path = dir + "/ur5_gripper.urdf";
  write_file(path, text);
  return path;
}

// model --dynamic for a sensor below movable joints counts as identify does
// (the sensor frame moving with them) and says so; --sensor-at-rest counts
// with them held still and says so. Both counts are the rank computed here.
TEST_F(CliMotion, ModelCountsAWristSensorAsIdentifyDoes) {
  const std::string ur5 = ur5_with_gripper(path("."));
  struct Case {
    std::string urdf, sensor;
    std::vector<std::string> extra;
  };
  for (const Case& c :
       {Case{ur5, "ft_sensor", {}}, Case{ur5, "ft_sensor", {"--fixed", "finger_joint=0.3"}},
        Case{kUrUrdf, "wrist_2_link", {}}}) {
    SCOPED_TRACE(c.sensor + (c.extra.empty() ? "" : " held"));
    massid::Model m = massid::load_urdf(c.urdf, c.sensor);
    if (!c.extra.empty()) m = massid::hold_joints(m, {{"finger_joint", 0.3}});
    ASSERT_GT(m.num_upstream_joints(), 0);
    for (const bool at_rest : {false, true}) {
      std::vector<std::string> args{"model", c.urdf, "--dynamic", "--sensor", c.sensor};
      args.insert(args.end(), c.extra.begin(), c.extra.end());
      if (at_rest) args.push_back("--sensor-at-rest");
      Result r = run(args);
      ASSERT_EQ(r.code, 0) << r;
      EXPECT_NE(r.out.find(at_rest ? "assumed: the sensor frame at rest (--sensor-at-rest)"
                                   : "assumed: the sensor frame moving with the joints above "
                                     "sensor link '" +
                                         c.sensor + "'"),
                std::string::npos)
          << r;
      args.push_back("--json");
      r = run(args);
      ASSERT_EQ(r.code, 0) << r;
      const int count = static_cast<int>(json::parse(r.out)["base_parameters"].size());
      EXPECT_EQ(count, wrist_regressor_rank(m, !at_rest)) << (at_rest ? "at rest" : "moving");
    }
  }
  // The rigid tool (the gripper held): all ten of it, as identify finds.
  const Result r = run({"model", ur5, "--dynamic", "--sensor", "ft_sensor", "--fixed",
                        "finger_joint=0.3", "--json"});
  EXPECT_EQ(json::parse(r.out)["base_parameters"].size(), 10u) << r;
  EXPECT_EQ(run({"model", ur5, "--dynamic", "--sensor", "ft_sensor", "--sensor-at-rest",
                 "--moving-sensor"})
                .code,
            2);
}

TEST_F(CliMotion, OldSpellingsStillWorkAndWarn) {
  // simulate --offset fx,..,mz is --sensor-offset's old spelling: the same file, and a warning.
  Result r = run({"simulate", kPumaUrdf, kPumaPlan, "-o", path("new.csv"), "--sensor-offset",
                  "1,-2,3,0.1,-0.2,0.3"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_EQ(r.err, "");
  r = run(
      {"simulate", kPumaUrdf, kPumaPlan, "-o", path("old.csv"), "--offset", "1,-2,3,0.1,-0.2,0.3"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_EQ(r.err,
            "massid: warning: --offset with six numbers is deprecated: use --sensor-offset\n");
  EXPECT_EQ(read_file(path("old.csv")), read_file(path("new.csv")));
  const Table t = read_table(path("new.csv"));
  r = run({"simulate", kPumaUrdf, kPumaPlan, "-o", path("zero.csv")});
  const Table zero = read_table(path("zero.csv"));
  EXPECT_DOUBLE_EQ(t.num(0, "fy") - zero.num(0, "fy"), -2.0);  // the offset is there
  // model --gravity level|varying is --gravity-model's.
  r = run({"model", kUrUrdf, "--dynamic", "--gravity-model", "level", "--json"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_EQ(r.err, "");
  const Result old = run({"model", kUrUrdf, "--dynamic", "--gravity", "level", "--json"});
  ASSERT_EQ(old.code, 0) << old;
  EXPECT_EQ(old.out, r.out);
  EXPECT_EQ(old.err,
            "massid: warning: --gravity level|varying is deprecated: use --gravity-model\n");
}

TEST_F(CliMotion, ModelLevelGravityIsTheSensorFramesBelowAWrist) {
  // The sensor on the wrist: the level root gravity is no single vector in its frame.
  const Result r =
      run({"model", kUrUrdf, "--dynamic", "--gravity-model", "level", "--sensor", "wrist_3_link"});
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_NE(r.err.find("is below movable joints (shoulder_pan_joint"), std::string::npos) << r;
  EXPECT_NE(r.err.find("use the varying gravity model"), std::string::npos) << r;
}

TEST_F(CliMotion, RequestRulesSpeakInOptions) {
  const std::string data = path("any.csv");  // never read: the rules come first
  const auto err = [&](std::vector<std::string> extra) {
    std::vector<std::string> a{"identify", kUrUrdf, data, "-o", path("p.json")};
    a.insert(a.end(), extra.begin(), extra.end());
    const Result r = run(a);
    EXPECT_EQ(r.code, 2) << r;
    return r.err;
  };
  EXPECT_EQ(err({"--delay", "auto"}),
            "massid: error: --delay goes with --dynamic (a motion log): at rest a lag does not "
            "matter\n");
  EXPECT_EQ(err({"--dynamic", "--rest", "off"}),
            "massid: error: --rest goes with static identification (--dynamic uses every row)\n");
  EXPECT_EQ(err({"--cutoff", "5"}),
            "massid: error: --cutoff goes with --dynamic (identification in motion)\n");
  EXPECT_EQ(err({"--drift", "quadratic"}),
            "massid: error: --drift: 'quadratic' is not 'linear' or 'per-block'\n");
  EXPECT_EQ(err({"--dynamic", "--delay", "2ms"}),
            "massid: error: --delay: '2ms' is not 'auto' or a number of seconds\n");
}

}  // namespace
}  // namespace massid_cli_test
