// The command-line tool in motion, as a user runs it: design --dynamic ->
// simulate --dynamic -> identify --dynamic -> predict on another trajectory;
// the same from positions only (derivatives filtered); a tool on a wrist
// sensor from the arm's joints; the errors of motion logs. The numbers are
// checked against the URDF (total mass, the base parameters' true values
// from `model --dynamic`'s terms evaluated on the URDF's inertials) and
// against the simulated wrench, not against massid's own output.
#include <Eigen/Core>

#include "cli_support.hpp"
#include "massid/core/model.hpp"
#include "massid/core/parameters.hpp"
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
  const massid::Model wrist = massid::load_urdf(kUrUrdf, "wrist_3_link");
  for (const auto& q : params["base_parameters"])
    EXPECT_NEAR(q["value"].get<double>(), true_value(wrist, q), 4 * q["std"].get<double>())
        << q["name"] << " = " << q["expression"];
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
