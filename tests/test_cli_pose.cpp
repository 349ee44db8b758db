// The sensor's pose instead of joints (interface.md, "The sensor's pose
// instead of joints"; issue 28 item 3), run as a user would: a wrist sensor's
// log given by the arm's joints, and the same log with those joints replaced
// by the sensor frame's orientation in the world (a quaternion qx,qy,qz,qw or
// a rotation matrix r11..r33) and its origin x,y,z. The pose is computed here
// from the arm's own forward kinematics (the sensor at the arm's base: the
// world frame), not through massid's pose code. identify (static and
// --dynamic), predict and compensate give the same numbers either way; the
// conflicts and bad poses are refused with exit 2.
#include <fmt/format.h>

#include <Eigen/Geometry>
#include <random>
#include <set>

#include "cli_support.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/io/urdf.hpp"

namespace massid_cli_test {
namespace {

const std::vector<std::string> kPoseArmJoints = {"shoulder_pan_joint", "shoulder_lift_joint",
                                                 "elbow_joint",        "wrist_1_joint",
                                                 "wrist_2_joint",      "wrist_3_joint"};

std::string pose_num(double x) { return fmt::format("{:.17g}", x); }

// The wrist_3_link frame in the world (the arm's base) at joint positions q.
struct PoseOfWrist {
  Eigen::Matrix3d R;
  Eigen::Vector3d x;
};
PoseOfWrist pose_of_wrist(const Eigen::VectorXd& q) {
  static const massid::Model arm = massid::load_urdf(kUrUrdf);
  static const int wrist = arm.find_link("wrist_3_link");
  massid::KinematicsData kin(arm);
  massid::forward_kinematics(arm, kin, q);
  return {kin.rotation[wrist], kin.position[wrist]};
}

// The table with the arm's joint columns replaced by the pose's: "quaternion"
// (qx,qy,qz,qw; every `flip`-th row's sign negated: the same rotation) or
// "matrix" (r11..r33), and x,y,z when `position`.
Table pose_table(const Table& joints, const std::string& kind, bool position, int flip = 0) {
  Table out = without_columns(joints, [](const std::string& name) {
    return std::find(kPoseArmJoints.begin(), kPoseArmJoints.end(), name) != kPoseArmJoints.end();
  });
  const std::vector<std::string> q = {"qx", "qy", "qz", "qw"};
  const std::vector<std::string> r = {"r11", "r12", "r13", "r21", "r22",
                                      "r23", "r31", "r32", "r33"};
  std::vector<std::string> added = kind == "quaternion" ? q : r;
  if (position) added.insert(added.end(), {"x", "y", "z"});
  out.header.insert(out.header.begin(), added.begin(), added.end());
  for (size_t i = 0; i < out.rows.size(); ++i) {
    Eigen::VectorXd qa(6);
    for (int j = 0; j < 6; ++j) qa[j] = joints.num(i, kPoseArmJoints[static_cast<size_t>(j)]);
    const PoseOfWrist p = pose_of_wrist(qa);
    std::vector<std::string> cells;
    if (kind == "quaternion") {
      Eigen::Quaterniond h(p.R);
      if (flip > 0 && i % static_cast<size_t>(flip) == 0) h.coeffs() = -h.coeffs();
      for (int k = 0; k < 4; ++k) cells.push_back(pose_num(h.coeffs()[k]));  // x, y, z, w
    } else {
      for (int a = 0; a < 3; ++a)
        for (int b = 0; b < 3; ++b) cells.push_back(pose_num(p.R(a, b)));
    }
    if (position)
      for (int k = 0; k < 3; ++k) cells.push_back(pose_num(p.x[k]));
    out.rows[i].insert(out.rows[i].begin(), cells.begin(), cells.end());
  }
  return out;
}

std::vector<double> pose_values(const std::string& params) {
  std::vector<double> v;
  const json j = json::parse(read_file(params));
  for (const auto& p : j["base_parameters"]) v.push_back(p["value"].get<double>());
  return v;
}

class CliPose : public Cli {
 protected:
  // A static wrist log: 120 random arm poses, the tool's weight with noise
  // and an offset (simulate, gravity from the arm's joints).
  std::string static_log() {
    std::mt19937 rng(28);
    std::uniform_real_distribution<double> u(-2.5, 2.5);
    std::string plan = join(kPoseArmJoints) + "\n";
    for (int r = 0; r < 120; ++r) {
      std::vector<std::string> cells;
      for (int j = 0; j < 6; ++j) cells.push_back(pose_num(u(rng)));
      plan += join(cells) + "\n";
    }
    const Result s = run({"simulate", kUrUrdf, file("plan.csv", plan), "--sensor", "wrist_3_link",
                          "-o", path("joints.csv"), "--noise-force", "0.05", "--noise-moment",
                          "0.003", "--offset", "1,-2,3.5,0.1,-0.2,0.3", "--seed", "5"});
    EXPECT_EQ(s.code, 0) << s;
    return path("joints.csv");
  }

  // A motion log of the arm at 500 Hz (positions only: the filter derives
  // the rest), the tool's full wrench with noise.
  std::string motion_log(double duration) {
    std::string traj = "t";
    for (const std::string& j : kPoseArmJoints) traj += "," + j;
    for (const std::string& j : kPoseArmJoints) traj += "," + j + "_vel";
    for (const std::string& j : kPoseArmJoints) traj += "," + j + "_acc";
    traj += "\n";
    const double q0[6] = {0.3, -1.3, 1.4, -1.2, -1.4, 0.4};
    const int n = static_cast<int>(duration * 500);
    for (int i = 0; i < n; ++i) {
      const double t = i / 500.0;
      std::vector<double> q(6), qd(6), qdd(6);
      for (int j = 0; j < 6; ++j) {
        const double a = j < 3 ? 0.4 : 1.2, f = 2 * std::numbers::pi * (0.23 + 0.11 * j);
        const double b = 0.3 * a, g = 2.3 * f, ph = 0.7 * j;
        q[j] = q0[j] + a * std::sin(f * t) + b * std::sin(g * t + ph);
        qd[j] = a * f * std::cos(f * t) + b * g * std::cos(g * t + ph);
        qdd[j] = -a * f * f * std::sin(f * t) - b * g * g * std::sin(g * t + ph);
      }
      traj += pose_num(t);
      for (const auto* v : {&q, &qd, &qdd})
        for (double x : *v) traj += "," + pose_num(x);
      traj += "\n";
    }
    const Result s = run({"simulate", kUrUrdf, file("traj.csv", traj), "--dynamic", "--sensor",
                          "wrist_3_link", "-o", path("sim.csv"), "--noise-force", "0.05",
                          "--noise-moment", "0.003", "--seed", "7"});
    EXPECT_EQ(s.code, 0) << s;
    const Table joints = without_columns(read_table(path("sim.csv")), [](const std::string& c) {
      return c.ends_with("_vel") || c.ends_with("_acc");
    });
    return file("motion_joints.csv", to_csv(joints));
  }

  std::string identify(const std::string& log, const std::string& out,
                       std::vector<std::string> more = {}) {
    std::vector<std::string> a = {"identify",     kUrUrdf, log,      "--sensor",
                                  "wrist_3_link", "-o",    path(out)};
    a.insert(a.end(), more.begin(), more.end());
    const Result r = run(a);
    EXPECT_EQ(r.code, 0) << r;
    return r.out + r.err;
  }
};

// (a) A static log by joints, by quaternion (some rows' signs flipped) and by
// rotation matrix: the same parameters to round-off; the note names the pose.
TEST_F(CliPose, StaticWristLogByQuaternionOrMatrixIsTheLogByJoints) {
  const Table joints = read_table(static_log());
  const std::string quat = file("quat.csv", to_csv(pose_table(joints, "quaternion", false, 3)));
  const std::string mat = file("mat.csv", to_csv(pose_table(joints, "matrix", true)));
  identify(path("joints.csv"), "joints.json", {"--offset"});
  const std::string said = identify(quat, "quat.json", {"--offset"});
  EXPECT_NE(said.find("the sensor's pose from qx,qy,qz,qw"), std::string::npos) << said;
  identify(mat, "mat.json", {"--offset"});
  const std::vector<double> a = pose_values(path("joints.json"));
  ASSERT_EQ(a.size(), 4u);  // the tool's mass and first moments
  for (const char* other : {"quat.json", "mat.json"}) {
    const std::vector<double> b = pose_values(path(other));
    ASSERT_EQ(b.size(), a.size());
    for (size_t k = 0; k < a.size(); ++k)
      EXPECT_NEAR(b[k], a[k], 1e-9 * (1 + std::abs(a[k]))) << other << " p" << k;
  }
  const json params = json::parse(read_file(path("quat.json")));
  EXPECT_EQ(params["gravity_from"], "sensor pose");
  EXPECT_FALSE(params.contains("upstream_joints"));

  // (c) predict and compensate: the same *_comp with the pose as with the joints.
  ASSERT_EQ(
      run({"predict", kUrUrdf, path("joints.json"), path("joints.csv"), "-o", path("pj.csv")}).code,
      0);
  const Result pq = run({"predict", kUrUrdf, path("joints.json"), quat, "-o", path("pq.csv")});
  ASSERT_EQ(pq.code, 0) << pq;
  const Result cj = run({"compensate", kUrUrdf, path("joints.json")}, path("joints.csv"));
  const Result cm = run({"compensate", kUrUrdf, path("joints.json")}, mat);
  ASSERT_EQ(cj.code, 0) << cj;
  ASSERT_EQ(cm.code, 0) << cm;
  write_file(path("cj.csv"), cj.out);
  write_file(path("cm.csv"), cm.out);
  const Table tj = read_table(path("pj.csv")), tq = read_table(path("pq.csv"));
  const Table uj = read_table(path("cj.csv")), um = read_table(path("cm.csv"));
  ASSERT_EQ(tq.rows.size(), tj.rows.size());
  ASSERT_EQ(um.rows.size(), tj.rows.size());
  double worst = 0;
  for (size_t i = 0; i < tj.rows.size(); ++i)
    for (const char* w : {"fx", "fy", "fz", "mx", "my", "mz"}) {
      const std::string c = std::string(w) + "_comp";
      worst =
          std::max({worst, std::abs(tq.num(i, c) - tj.num(i, c)),
                    std::abs(um.num(i, c) - uj.num(i, c)), std::abs(uj.num(i, c) - tj.num(i, c))});
    }
  EXPECT_LT(worst, 1e-9);
}

// (b), (c) A motion log by joints and by quaternion and x,y,z (a third of the
// rows' signs flipped: the filter must see a continuous quaternion): identify
// --dynamic derives the same motion (the filter smooths and differentiates
// other signals, the joints' or the quaternion's: the estimates agree within
// 0.3 std, 0.25 seen), and predict's *_comp agree within the noise (the
// largest difference over the rows 0.15 sigma in force, 0.36 sigma in moment
// seen). A matrix is turned into a quaternion before the filter: the same
// numbers as the quaternion.
TEST_F(CliPose, MotionLogByQuaternionAndPositionIsTheLogByJoints) {
  const std::string log = motion_log(16.0);
  const Table joints = read_table(log);
  const std::string quat = file("mquat.csv", to_csv(pose_table(joints, "quaternion", true, 3)));
  const std::string mat = file("mmat.csv", to_csv(pose_table(joints, "matrix", true)));
  identify(log, "mj.json", {"--dynamic"});
  identify(quat, "mq.json", {"--dynamic"});
  identify(mat, "mm.json", {"--dynamic"});
  const json pj = json::parse(read_file(path("mj.json")));
  ASSERT_EQ(pj["base_parameters"].size(), 10u);
  for (const char* other : {"mq.json", "mm.json"}) {
    const json po = json::parse(read_file(path(other)));
    ASSERT_EQ(po["base_parameters"].size(), 10u) << other;
    EXPECT_EQ(po["motion"]["sensor_moving"], true);
    for (size_t k = 0; k < 10; ++k) {
      const double a = pj["base_parameters"][k]["value"], b = po["base_parameters"][k]["value"];
      const double sd = pj["base_parameters"][k]["std"];
      EXPECT_NEAR(b, a, 0.3 * sd) << other << " " << pj["base_parameters"][k]["expression"];
    }
  }
  // predict: the same compensated wrench, far within the noise (0.05 N, 0.003 N m).
  ASSERT_EQ(run({"predict", kUrUrdf, path("mj.json"), log, "-o", path("pmj.csv")}).code, 0);
  const Result r = run({"predict", kUrUrdf, path("mj.json"), quat, "-o", path("pmq.csv")});
  ASSERT_EQ(r.code, 0) << r;
  const Table a = read_table(path("pmj.csv")), b = read_table(path("pmq.csv"));
  ASSERT_EQ(a.rows.size(), b.rows.size());
  double worst_f = 0, worst_m = 0;
  for (size_t i = 0; i < a.rows.size(); ++i)
    for (int k = 0; k < 6; ++k) {
      const std::string c = std::string(k < 3 ? "f" : "m") + "xyz"[k % 3] + "_comp";
      (k < 3 ? worst_f : worst_m) =
          std::max(k < 3 ? worst_f : worst_m, std::abs(a.num(i, c) - b.num(i, c)));
    }
  EXPECT_LT(worst_f, 0.2 * 0.05);
  EXPECT_LT(worst_m, 0.5 * 0.003);
}

// (e) What is refused, with exit 2 and a message naming the columns (and the
// line of a bad pose).
TEST_F(CliPose, ConflictsPartialSetsAndBadPosesAreRefused) {
  const Table joints = read_table(static_log());
  const Table quat = pose_table(joints, "quaternion", true);
  const auto refused = [&](const Table& t, const std::string& name, const std::string& says,
                           std::vector<std::string> more = {}) {
    std::vector<std::string> a = {"identify",     kUrUrdf, file(name, to_csv(t)), "--sensor",
                                  "wrist_3_link", "-o",    path("x.json")};
    a.insert(a.end(), more.begin(), more.end());
    const Result r = run(a);
    EXPECT_EQ(r.code, 2) << name << r;
    EXPECT_NE(r.err.find(says), std::string::npos) << name << r;
  };
  const auto with_column = [](Table t, const std::string& name, const std::string& value) {
    t.header.push_back(name);
    for (auto& row : t.rows) row.push_back(value);
    return t;
  };
  const auto without = [](const Table& t, std::set<std::string> names) {
    return without_columns(t, [&](const std::string& c) { return names.count(c) > 0; });
  };
  refused(with_column(with_column(with_column(quat, "gx", "0"), "gy", "0"), "gz", "-9.8"), "g.csv",
          "columns gx,gy,gz both give gravity");
  refused(with_column(quat, "wx", "0"), "w.csv", "columns wx both give the sensor frame's motion");
  refused(with_column(quat, "elbow_joint", "0.1"), "j.csv",
          "the joints above sensor link 'wrist_3_link' (elbow_joint) both give its orientation");
  refused(without(quat, {"qw"}), "q3.csv", "column(s) qw missing");
  refused(without(quat, {"z"}), "xy.csv", "column(s) z missing");
  Table both = pose_table(joints, "matrix", false);
  const Table plain_matrix = both;
  for (const char* k : {"qx", "qy", "qz", "qw"}) {
    const int c = quat.col(k);
    both.header.push_back(k);
    for (size_t i = 0; i < both.rows.size(); ++i)
      both.rows[i].push_back(quat.rows[i][static_cast<size_t>(c)]);
  }
  refused(both, "both.csv", "both a quaternion qx,qy,qz,qw and a rotation matrix r11..r33");
  refused(with_column(plain_matrix, "r11_vel", "0"), "rates.csv",
          "column 'r11_vel': the rates of a rotation matrix are not read");
  // A quaternion of norm 1.01 on the 5th data row (line 6); 1.0005 is normalised.
  Table bad = quat;
  const int qx = bad.col("qx");
  for (int k = 0; k < 4; ++k) {
    std::string& cell = bad.rows[4][static_cast<size_t>(qx + k)];
    cell = pose_num(1.01 * std::stod(cell));
  }
  refused(bad, "norm.csv", ":6: columns qx,qy,qz,qw: the quaternion");
  refused(bad, "norm_stream.csv", "has norm 1.01", {"--dynamic"});
  Table small = quat;
  for (int k = 0; k < 4; ++k) {
    std::string& cell = small.rows[4][static_cast<size_t>(qx + k)];
    cell = pose_num(1.0005 * std::stod(cell));
  }
  EXPECT_EQ(run({"identify", kUrUrdf, file("small.csv", to_csv(small)), "--sensor", "wrist_3_link",
                 "--offset", "-o", path("small.json")})
                .code,
            0);
  // A matrix that is no rotation (a row scaled by 1.1), named by line.
  Table mat = pose_table(joints, "matrix", false);
  const int r11 = mat.col("r11");
  for (int k = 0; k < 3; ++k) {
    std::string& cell = mat.rows[2][static_cast<size_t>(r11 + k)];
    cell = pose_num(1.1 * std::stod(cell));
  }
  refused(mat, "mat.csv", ":4: columns r11..r33: the matrix is not a rotation");
  // In motion, a pose without x,y,z: the origin's acceleration is unknown.
  const std::string log = motion_log(4.0);
  refused(pose_table(read_table(log), "quaternion", false), "noxyz.csv",
          "no position columns x,y,z", {"--dynamic"});
}

// --columns binds a recorder's names to the pose's roles.
TEST_F(CliPose, ColumnsBindARecordersNamesToThePose) {
  const Table joints = read_table(static_log());
  Table t = pose_table(joints, "quaternion", false);
  for (const char* k : {"qx", "qy", "qz", "qw"})
    t.header[static_cast<size_t>(t.col(k))] = std::string("orientation.") + k[1];
  const std::string log = file("ros.csv", to_csv(t));
  identify(path("joints.csv"), "joints.json", {"--offset"});
  identify(log, "ros.json",
           {"--offset", "--columns",
            "qx=orientation.x,qy=orientation.y,qz=orientation.z,qw=orientation.w"});
  const std::vector<double> a = pose_values(path("joints.json")), b = pose_values(path("ros.json"));
  ASSERT_EQ(a.size(), b.size());
  for (size_t k = 0; k < a.size(); ++k) EXPECT_NEAR(b[k], a[k], 1e-9 * (1 + std::abs(a[k])));
}

}  // namespace
}  // namespace massid_cli_test
