// The level gravity that tilt columns (tilt_x_deg,tilt_y_deg) turn: one rule
// at every door (SampleOptions::level_gravity, tilt_level_gravity): --gravity
// (sensor frame), else --root-gravity turned into the sensor frame through the
// fixed joints above the sensor link. The logs here are made in the test from
// the direct sum f = M g, m = sum_i c_i x m_i g, not by massid.
#include <Eigen/Geometry>
#include <random>

#include "cli_support.hpp"

namespace massid_cli_test {
namespace {

// A sensor link mounted upside down: the fixed joint above it turns it 180
// degrees about x (MOUNT_X), so with the root's gravity 0,0,-g the sensor
// frame's level gravity is 0,0,+g. Two links below it, on j1 (about z) and j2
// (about y).
constexpr const char* kLevelGravityUrdf = R"(<robot name="flipped">
  <link name="base"/>
  <joint name="mount" type="fixed">
    <parent link="base"/><child link="ft"/>
    <origin xyz="0 0 0.3" rpy="MOUNT_X 0 0"/>
  </joint>
  <link name="ft"/>
  <joint name="j1" type="revolute">
    <parent link="ft"/><child link="link1"/>
    <origin xyz="0 0 0.05"/><axis xyz="0 0 1"/>
    <limit lower="-3.2" upper="3.2" effort="10" velocity="1"/>
  </joint>
  <link name="link1">
    <inertial><origin xyz="0.10 0.02 0.04"/><mass value="2.0"/>
      <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="j2" type="revolute">
    <parent link="link1"/><child link="link2"/>
    <origin xyz="0.2 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-1.6" upper="1.6" effort="10" velocity="1"/>
  </joint>
  <link name="link2">
    <inertial><origin xyz="0.15 0 0.03"/><mass value="1.0"/>
      <inertia ixx="0.01" iyy="0.01" izz="0.01" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
</robot>
)";
constexpr double kLevelGravityMass = 3.0;
constexpr double kLevelG = 9.80665;

// Gravity in the sensor frame at a tilt (radians) of the platform, the sensor
// mounted turned by `mount` about x: (Rx(tx) Ry(ty))^T level, the rotation
// docs/formats.md gives for the tilt columns, with level = Rx(mount)^T
// (0,0,-g) (0,0,+g upside down).
Eigen::Vector3d level_gravity_tilted(double tx, double ty, double mount) {
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(tx, Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(ty, Eigen::Vector3d::UnitY()))
                                .toRotationMatrix();
  const Eigen::Vector3d level =
      Eigen::AngleAxisd(mount, Eigen::Vector3d::UnitX()).toRotationMatrix().transpose() *
      Eigen::Vector3d(0, 0, -kLevelG);
  return R.transpose() * level;
}

// The wrench the two links' weight puts on the sensor: f = M g, m = sum c_i x m_i g.
Eigen::Matrix<double, 6, 1> level_gravity_wrench(double q1, double q2, const Eigen::Vector3d& g) {
  const Eigen::Matrix3d R1 = Eigen::AngleAxisd(q1, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Matrix3d R2 =
      R1 * Eigen::AngleAxisd(q2, Eigen::Vector3d::UnitY()).toRotationMatrix();
  const Eigen::Vector3d p1(0, 0, 0.05), p2 = p1 + R1 * Eigen::Vector3d(0.2, 0, 0);
  const Eigen::Vector3d c1 = p1 + R1 * Eigen::Vector3d(0.10, 0.02, 0.04);
  const Eigen::Vector3d c2 = p2 + R2 * Eigen::Vector3d(0.15, 0, 0.03);
  Eigen::Matrix<double, 6, 1> w;
  w.head<3>() = kLevelGravityMass * g;
  w.tail<3>() = c1.cross(2.0 * g) + c2.cross(1.0 * g);
  return w;
}

class CliLevelGravity : public Cli {
 protected:
  double mount = std::numbers::pi;
  std::string urdf() {
    std::string text = kLevelGravityUrdf;
    text.replace(text.find("MOUNT_X"), 7, num_text(mount));
    return file("robot.urdf", text);
  }

  // A static log of n poses at random joints and tilts (within 25 degrees),
  // with the tilt columns and no gx,gy,gz (with_gravity: gx,gy,gz too), the
  // wrench with noise of sigma 0.01 N and 0.001 N m (noise 0: exact).
  std::string log(const std::string& name, int n, unsigned seed, bool with_gravity = false,
                  double noise = 1.0) {
    std::mt19937 rng(seed);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    std::normal_distribution<double> z(0.0, 1.0);
    std::string text = std::string("j1,j2,tilt_x_deg,tilt_y_deg,") +
                       (with_gravity ? "gx,gy,gz," : "") + "fx,fy,fz,mx,my,mz\n";
    for (int i = 0; i < n; ++i) {
      const double q1 = 3.0 * u(rng), q2 = 1.5 * u(rng);
      const double tx = 25.0 * u(rng), ty = 25.0 * u(rng);
      const Eigen::Vector3d g =
          level_gravity_tilted(tx * std::numbers::pi / 180, ty * std::numbers::pi / 180, mount);
      Eigen::Matrix<double, 6, 1> w = level_gravity_wrench(q1, q2, g);
      for (int k = 0; k < 6; ++k) w[k] += noise * (k < 3 ? 0.01 : 0.001) * z(rng);
      text += num_text(q1) + "," + num_text(q2) + "," + num_text(tx) + "," + num_text(ty) + ",";
      if (with_gravity) text += num_text(g[0]) + "," + num_text(g[1]) + "," + num_text(g[2]) + ",";
      for (int k = 0; k < 6; ++k) text += num_text(w[k]) + (k < 5 ? "," : "\n");
    }
    return file(name, text);
  }
  static std::string num_text(double v) {
    char b[40];
    std::snprintf(b, sizeof b, "%.17g", v);
    return b;
  }
};

// (a) identify and predict with default flags turn the root gravity through
// the fixed mount: the total mass is the URDF's, and on another log the
// prediction is the direct sum to the noise, *_comp noise-level; the sensor
// upside down and turned a quarter about x. The old code turned the root
// gravity 0,0,-g as if it were the sensor frame's level gravity. Upside down,
// identify refused the log (exit 2) telling the user to negate the wrench;
// with --no-checks it wrote a total mass of -3 kg (every parameter negated)
// with exit 0. A quarter turn: exit 2 blaming the sensor's column mapping;
// with --no-checks a total mass of -0.13 kg.
TEST_F(CliLevelGravity, TiltColumnsTurnTheRootGravityThroughTheFixedJoints) {
  for (const double turn : {std::numbers::pi, std::numbers::pi / 2}) {
    mount = turn;
    const std::string robot = urdf();
    Result r = run(
        {"identify", robot, log("fit.csv", 60, 1), "--sensor", "ft", "-o", path("params.json")});
    ASSERT_EQ(r.code, 0) << r;
    const json params = json::parse(read_file(path("params.json")));
    EXPECT_NEAR(params.at("total_mass").get<double>(), kLevelGravityMass, 0.01) << turn;

    const std::string other = log("other.csv", 40, 2, false, 0.0);
    r = run({"predict", robot, path("params.json"), other, "-o", path("pred.csv")});
    ASSERT_EQ(r.code, 0) << r;
    const Table in = read_table(other), out = read_table(path("pred.csv"));
    ASSERT_EQ(out.rows.size(), in.rows.size());
    const char* names[6] = {"fx", "fy", "fz", "mx", "my", "mz"};
    for (size_t i = 0; i < out.rows.size(); ++i)
      for (int k = 0; k < 6; ++k) {
        const std::string n = names[k];
        const double tol = k < 3 ? 0.02 : 0.003;
        EXPECT_NEAR(out.num(i, n + "_pred"), in.num(i, n), tol) << turn << " row " << i << n;
        EXPECT_NEAR(out.num(i, n + "_comp"), 0.0, tol) << turn << " row " << i << " " << n;
      }
  }
}

// (b) One tilted log through identify, predict and compensate: the same
// gravity at every door, with default flags and with an explicit --gravity
// (the level gravity the mount gives, 0,0,+g): predict's and compensate's
// *_comp agree to 1e-9, and each door's explicit --gravity gives the same
// numbers as its default. A --gravity of the wrong sign at compensate moves
// *_comp by twice the weight: the option is read.
TEST_F(CliLevelGravity, EveryDoorTurnsTheSameLevelGravity) {
  const std::string robot = urdf(), data = log("fit.csv", 60, 3), other = log("other.csv", 30, 4);
  const std::vector<std::string> explicit_gravity{"--gravity", "0,0,9.80665"};
  const auto with = [](std::vector<std::string> a, const std::vector<std::string>& b) {
    a.insert(a.end(), b.begin(), b.end());
    return a;
  };
  std::vector<Table> predicted, compensated;
  for (const std::vector<std::string>& extra : {std::vector<std::string>{}, explicit_gravity}) {
    const std::string tag = std::to_string(predicted.size());
    Result r = run(with(
        {"identify", robot, data, "--sensor", "ft", "-o", path("params" + tag + ".json")}, extra));
    ASSERT_EQ(r.code, 0) << r;
    r = run(with({"predict", robot, path("params" + tag + ".json"), other, "-o",
                  path("pred" + tag + ".csv")},
                 extra));
    ASSERT_EQ(r.code, 0) << r;
    predicted.push_back(read_table(path("pred" + tag + ".csv")));
    r = run(with({"compensate", robot, path("params" + tag + ".json")}, extra), other);
    ASSERT_EQ(r.code, 0) << r;
    write_file(path("comp" + tag + ".csv"), r.out);
    compensated.push_back(read_table(path("comp" + tag + ".csv")));
  }
  const char* names[6] = {"fx_comp", "fy_comp", "fz_comp", "mx_comp", "my_comp", "mz_comp"};
  for (size_t d = 0; d < 2; ++d) {
    ASSERT_EQ(predicted[d].rows.size(), 30u);
    ASSERT_EQ(compensated[d].rows.size(), 30u);
    for (size_t i = 0; i < 30; ++i)
      for (const char* n : names) {
        EXPECT_NEAR(predicted[d].num(i, n), compensated[d].num(i, n), 1e-9) << d << " " << n;
        EXPECT_NEAR(predicted[d].num(i, n), predicted[0].num(i, n), 1e-9) << d << " " << n;
        EXPECT_LT(std::abs(predicted[d].num(i, n)), 0.05) << d << " " << n;
      }
  }
  // The option is read: the level gravity upside down flips the weight.
  const Result r =
      run({"compensate", robot, path("params0.json"), "--gravity", "0,0,-9.80665"}, other);
  ASSERT_EQ(r.code, 0) << r;
  write_file(path("flipped.csv"), r.out);
  const Table flipped = read_table(path("flipped.csv"));
  EXPECT_NEAR(
      std::hypot(flipped.num(0, "fx_comp"), flipped.num(0, "fy_comp"), flipped.num(0, "fz_comp")),
      2 * kLevelGravityMass * kLevelG, 0.1);
}

// (c) --gravity with a log whose gravity comes from elsewhere (gx,gy,gz here)
// would go unused: an error at every door that reads a log, naming it.
TEST_F(CliLevelGravity, GravityWithoutTiltColumnsIsAnErrorAtEveryDoor) {
  const std::string robot = urdf(), data = log("fit.csv", 60, 5, true);
  Result r = run({"identify", robot, data, "--sensor", "ft", "-o", path("params.json")});
  ASSERT_EQ(r.code, 0) << r;
  const std::vector<std::vector<std::string>> doors{
      {"identify", robot, data, "--sensor", "ft", "-o", path("p2.json")},
      {"predict", robot, path("params.json"), data, "-o", path("pred.csv")},
      {"simulate", robot, data, "--sensor", "ft", "-o", path("sim.csv")},
      {"compensate", robot, path("params.json")}};
  for (std::vector<std::string> door : doors) {
    door.insert(door.end(), {"--gravity", "0,0,9.80665"});
    r = run(door, data);
    EXPECT_EQ(r.code, 2) << door[0] << "\n" << r;
    EXPECT_NE(r.err.find("a level gravity is given, but the file has no tilt columns "
                         "tilt_x_deg,tilt_y_deg for it to turn (its gravity comes from its "
                         "columns gx,gy,gz): drop it (--gravity)"),
              std::string::npos)
        << door[0] << "\n"
        << r;
  }
  // A bad vector: named as the option.
  r = run({"identify", robot, data, "--sensor", "ft", "-o", path("p3.json"), "--gravity", "0,0"});
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_NE(r.err.find("--gravity"), std::string::npos) << r;
}

// A level gravity upside down (the URDF's mount is upside down, the user's
// --gravity not): the set-up checks see the force against gravity and name
// the level gravity and --gravity, not gx,gy,gz (which the log does not
// have). The old message told the user to negate gx,gy,gz.
TEST_F(CliLevelGravity, AnUpsideDownLevelGravityIsNamedByTheChecks) {
  const std::string robot = urdf(), data = log("fit.csv", 60, 6);
  const Result r = run({"identify", robot, data, "--sensor", "ft", "-o", path("params.json"),
                        "--gravity", "0,0,-9.80665"});
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_NE(r.err.find("the measured force points against gravity (the level gravity turned by "
                       "tilt_x_deg,tilt_y_deg) at 60 of 60 rows"),
            std::string::npos)
      << r;
  EXPECT_NE(r.err.find("if the level gravity points up in the sensor frame, give it along "
                       "gravity (sensor frame, platform level) (--gravity; --no-checks"),
            std::string::npos)
      << r;
}

// A level gravity 10 degrees off the sensor frame's: the force turns with
// the tilts about another vertical than the one given. The rotation check
// names what gravity came from (the level gravity and its tilt columns, not
// gx,gy,gz the log does not have) and the fix that applies to it.
TEST_F(CliLevelGravity, ARotatedLevelGravityIsNamedByTheRotationCheck) {
  const std::string robot = urdf(), data = log("fit.csv", 80, 8);
  const Eigen::Vector3d off =
      Eigen::AngleAxisd(10.0 * std::numbers::pi / 180, Eigen::Vector3d::UnitX()) *
      Eigen::Vector3d(0, 0, kLevelG);  // the truth upside down is 0,0,+g
  const Result r =
      run({"identify", robot, data, "--sensor", "ft", "-o", path("params.json"), "--gravity",
           num_text(off[0]) + "," + num_text(off[1]) + "," + num_text(off[2])});
  EXPECT_EQ(r.code, 2) << r;
  const std::string head =
      "the force direction disagrees with the level gravity turned by tilt_x_deg,tilt_y_deg by ";
  const std::size_t at = r.err.find(head);
  ASSERT_NE(at, std::string::npos) << r;
  EXPECT_NEAR(std::stod(r.err.substr(at + head.size())), 10.0, 0.5) << r;
  EXPECT_NE(r.err.find("give it as R times it (--gravity, sensor frame, platform level)"),
            std::string::npos)
      << r;
  EXPECT_EQ(r.err.find("gx,gy,gz by R"), std::string::npos) << r;
}

// design --evaluate of a plan without gx,gy,gz: its tilt columns turn
// design's own level gravity (--gravity, default 0,0,-9.80665 in the sensor
// frame: interface.md), as when design wrote them, not the readers' default
// through the mount. The sensor turned a quarter about x, where the two
// differ: the evaluation of the plan without gx,gy,gz is the plan's with them.
TEST_F(CliLevelGravity, DesignEvaluatesTiltColumnsWithItsLevelGravity) {
  mount = std::numbers::pi / 2;
  const std::string robot = urdf();
  Result r = run({"design", robot, "--sensor", "ft", "--poses", "12", "--tilt-max", "25", "-o",
                  path("plan.csv")});
  ASSERT_EQ(r.code, 0) << r;
  const Table plan = read_table(path("plan.csv"));
  ASSERT_GE(plan.col("gx"), 0);
  ASSERT_GE(plan.col("tilt_x_deg"), 0);
  write_file(path("tilts.csv"), to_csv(without_columns(plan, [](const std::string& c) {
               return c == "gx" || c == "gy" || c == "gz";
             })));
  const auto evaluate = [&](const std::string& name) {
    Result e = run({"design", robot, "--sensor", "ft", "--evaluate", path(name)});
    EXPECT_EQ(e.code, 0) << e;
    std::string out = e.out;
    for (size_t at; (at = out.find(path(name))) != std::string::npos;)
      out.replace(at, path(name).size(), "PLAN");
    return out;
  };
  const std::string with_gravity = evaluate("plan.csv");
  EXPECT_NE(with_gravity.find("condition number"), std::string::npos) << with_gravity;
  EXPECT_EQ(evaluate("tilts.csv"), with_gravity);
}

// The sensor link below a movable joint (link1, below j1) whose column the
// log does not have: the level gravity does not follow from the root gravity,
// an error asking for --gravity; given, it is read (here an unidentifiable
// log: exit 3, its diagnosis read the file with the same --gravity: the old
// one read it without and failed on the tilt columns, exit 2). A log with
// j1's column and tilt columns: both would turn gravity, an error at every
// door (compensate alone refused it before; identify and simulate used j1
// and ignored the tilts).
TEST_F(CliLevelGravity, TiltColumnsBelowMovableJoints) {
  const std::string robot = urdf();
  std::string text = "j2,tilt_x_deg,tilt_y_deg,fx,fy,fz,mx,my,mz\n";
  for (int i = 0; i < 20; ++i)
    text += num_text(0.1 * i) + ",0,0,0,0,9.8," + num_text(0.01 * i) + ",0.02,0\n";
  const std::string wrist = file("wrist.csv", text);
  Result r =
      run({"identify", robot, wrist, "--sensor", "link1", "-o", path("w.json"), "--no-checks"});
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_NE(r.err.find("wrist.csv:1: tilt_x_deg,tilt_y_deg turn the level gravity in the sensor "
                       "frame, and sensor link 'link1' is below movable joints (j1) whose columns "
                       "the file does not have: give the level gravity in the sensor frame, or "
                       "those columns (--gravity)"),
            std::string::npos)
      << r;
  r = run({"identify", robot, wrist, "--sensor", "link1", "-o", path("w.json"), "--no-checks",
           "--gravity", "0,0,9.80665"});
  EXPECT_EQ(r.code, 3) << r;
  EXPECT_NE(r.err.find("the 20 samples determine only"), std::string::npos) << r;

  const std::string both = log("both.csv", 20, 7);  // j1, j2 and the tilts
  for (const std::vector<std::string>& door :
       {std::vector<std::string>{"identify", robot, both, "--sensor", "link1", "-o",
                                 path("b.json")},
        std::vector<std::string>{"simulate", robot, both, "--sensor", "link1", "-o",
                                 path("b.csv")}}) {
    r = run(door);
    EXPECT_EQ(r.code, 2) << door[0] << "\n" << r;
    EXPECT_NE(r.err.find("both.csv:1: tilt_x_deg,tilt_y_deg and the joints above sensor link "
                         "'link1' both turn gravity"),
              std::string::npos)
        << door[0] << "\n"
        << r;
  }
}

}  // namespace
}  // namespace massid_cli_test
