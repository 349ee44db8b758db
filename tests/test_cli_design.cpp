// `massid design` run as a user runs it: every option of the issue has a test
// here, checked on the plan file it writes (columns, limits, tilts, gravity,
// heights computed independently by forward kinematics) and on the figures it
// prints (condition number, log det, predicted standard deviations, expected
// prediction error), and `--evaluate` against what `identify` reports.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <map>
#include <numbers>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"
#include "massid/io/urdf.hpp"

namespace {

using namespace massid_cli_test;

constexpr double kDeg = std::numbers::pi / 180.0;
constexpr double kG = 9.80665;

const std::string kBranchingUrdf = example("branching/branching.urdf");
const std::string kWristUrdf = example("wrist_tool/wrist_tool.urdf");

// The PUMA's sensor frame has gravity +z when the platform is level.
const std::vector<std::string> kPumaLevel = {"--gravity", "0,0,9.80665"};

class CliDesign : public Cli {
 protected:
  // massid design URDF -o NAME --poses N --candidates 300 ARGS...
  Result design(const std::string& urdf, const std::string& name, int poses,
                const std::vector<std::string>& extra) {
    std::vector<std::string> args{
        "design", urdf, "-o", path(name), "--poses", std::to_string(poses), "--candidates", "300"};
    args.insert(args.end(), extra.begin(), extra.end());
    return run(args);
  }
};

std::vector<std::string> operator+(std::vector<std::string> a, const std::vector<std::string>& b) {
  a.insert(a.end(), b.begin(), b.end());
  return a;
}

// The number printed after `key` in `text` (NaN when absent).
double number_after(const std::string& text, const std::string& key) {
  const size_t at = text.find(key);
  if (at == std::string::npos) return NAN;
  return std::strtod(text.c_str() + at + key.size(), nullptr);
}

double condition_number(const std::string& out) {
  return number_after(out, "condition number (eq. 36, moment rows): ");
}
double log_det(const std::string& out) {
  return number_after(out, "log det of the information matrix ");
}

// The table of predicted standard deviations: unknown name -> std.
std::map<std::string, double> predicted_std(const std::string& out) {
  std::map<std::string, double> s;
  std::istringstream in(out);
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    if (line.rfind("predicted standard deviations", 0) == 0) {
      inside = true;
    } else if (line.rfind("expected error", 0) == 0) {
      break;
    } else if (inside) {
      std::istringstream cells(line);
      std::string name;
      double value = NAN;
      cells >> name >> value;
      s[name] = value;
    }
  }
  return s;
}

// The expected error of the predicted wrench, per axis.
std::map<std::string, double> expected_error(const std::string& out) {
  std::map<std::string, double> e;
  const size_t at = out.find("expected error of the predicted wrench");
  if (at == std::string::npos) return e;
  const size_t start = out.find('\n', at) + 1;
  std::istringstream cells(out.substr(start, out.find('\n', start) - start));
  std::string axis;
  double value = NAN;
  while (cells >> axis >> value) e[axis] = value;
  return e;
}

// Gravity in the tilted sensor frame: R^T g_level, R = Rx(ax) Ry(ay).
Eigen::Vector3d tilted(const Eigen::Vector3d& level, double ax_deg, double ay_deg) {
  const Eigen::Matrix3d R = (Eigen::AngleAxisd(ax_deg * kDeg, Eigen::Vector3d::UnitX()) *
                             Eigen::AngleAxisd(ay_deg * kDeg, Eigen::Vector3d::UnitY()))
                                .toRotationMatrix();
  return R.transpose() * level;
}

Eigen::Vector3d gravity_of(const Table& t, size_t r) {
  return {t.num(r, "gx"), t.num(r, "gy"), t.num(r, "gz")};
}

double angle_between(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

// Joint positions of row r in the model's joint order.
Eigen::VectorXd joints_of(const Table& t, size_t r, const massid::Model& m) {
  Eigen::VectorXd q(m.num_joints());
  for (int j = 0; j < m.num_joints(); ++j) q[j] = t.num(r, m.joints[j].name);
  return q;
}

// The columns every plan has: one per movable joint (named as in the URDF),
// gx, gy, gz, tilt_x_deg, tilt_y_deg; `poses` rows; joints within the URDF
// limits; |g| = |level| and g = R^T g_level for the row's tilt.
void expect_valid_plan(const Table& t, const massid::Model& m, int poses,
                       const Eigen::Vector3d& level) {
  std::set<std::string> want{"gx", "gy", "gz", "tilt_x_deg", "tilt_y_deg"};
  for (const auto& j : m.joints) want.insert(j.name);
  EXPECT_EQ(std::set<std::string>(t.header.begin(), t.header.end()), want);
  EXPECT_EQ(t.header.size(), want.size());
  ASSERT_EQ(t.rows.size(), static_cast<size_t>(poses));
  for (size_t r = 0; r < t.rows.size(); ++r) {
    ASSERT_EQ(t.rows[r].size(), t.header.size()) << "row " << r;
    for (const auto& j : m.joints) {
      const double q = t.num(r, j.name);
      EXPECT_TRUE(std::isfinite(q));
      if (j.limited) {
        EXPECT_GE(q, j.lower) << j.name << " row " << r;
        EXPECT_LE(q, j.upper) << j.name << " row " << r;
      }
    }
    const Eigen::Vector3d g = gravity_of(t, r);
    EXPECT_NEAR(g.norm(), level.norm(), 1e-9 * level.norm()) << "row " << r;
    const Eigen::Vector3d expect = tilted(level, t.num(r, "tilt_x_deg"), t.num(r, "tilt_y_deg"));
    EXPECT_LT((g - expect).norm(), 1e-9 * level.norm()) << "row " << r;
  }
}

// Links whose origin moves with the joints: compare two configurations.
std::vector<int> moving_links(const massid::Model& m) {
  massid::KinematicsData kin(m);
  massid::forward_kinematics(m, kin, Eigen::VectorXd::Constant(m.num_joints(), 0.3));
  const std::vector<Eigen::Vector3d> a = kin.position;
  massid::forward_kinematics(m, kin, Eigen::VectorXd::Constant(m.num_joints(), -1.1));
  std::vector<int> moving;
  for (int l = 0; l < m.num_links(); ++l)
    if ((kin.position[l] - a[l]).norm() > 1e-9) moving.push_back(l);
  return moving;
}

// The lowest moving link origin above the platform plane, -g_level/|g| . p.
double lowest_origin(const massid::Model& m, const Eigen::VectorXd& q,
                     const Eigen::Vector3d& level) {
  massid::KinematicsData kin(m);
  massid::forward_kinematics(m, kin, q);
  double lowest = INFINITY;
  for (int l : moving_links(m)) lowest = std::min(lowest, -level.normalized().dot(kin.position[l]));
  return lowest;
}

// Every row of the plan keeps the moving link origins at least H above the
// platform, and H is a real constraint: some pose within the URDF limits is lower.
void expect_min_height(const Table& t, const massid::Model& m, const Eigen::Vector3d& level,
                       double H) {
  ASSERT_FALSE(moving_links(m).empty());
  for (size_t i = 0; i < t.rows.size(); ++i)
    EXPECT_GE(lowest_origin(m, joints_of(t, i, m), level), H - 1e-12) << "row " << i;
  double lowest = INFINITY;
  for (int k = 0; k < 200; ++k) {
    Eigen::VectorXd q(m.num_joints());
    for (int j = 0; j < m.num_joints(); ++j) {
      const auto& joint = m.joints[j];
      const double u = std::fmod(0.618034 * (k + 1) * (j + 1), 1.0);
      q[j] = joint.limited ? joint.lower + u * (joint.upper - joint.lower) : -3.14 + 6.28 * u;
    }
    lowest = std::min(lowest, lowest_origin(m, q, level));
  }
  EXPECT_LT(lowest, H) << "--min-height " << H << " holds everywhere: the test proves nothing";
}

// Number of runs of equal consecutive tilts.
int tilt_blocks(const Table& t) {
  int blocks = 0;
  for (size_t r = 0; r < t.rows.size(); ++r)
    if (r == 0 || std::abs(t.num(r, "tilt_x_deg") - t.num(r - 1, "tilt_x_deg")) > 1e-9 ||
        std::abs(t.num(r, "tilt_y_deg") - t.num(r - 1, "tilt_y_deg")) > 1e-9)
      ++blocks;
  return blocks;
}

std::vector<std::string> column(const Table& t, const std::string& name) {
  std::vector<std::string> c;
  const int k = t.col(name);
  EXPECT_GE(k, 0) << "no column " << name;
  if (k >= 0)
    for (const auto& row : t.rows) c.push_back(row[k]);
  return c;
}

// Figures every successful design prints.
void expect_figures(const Result& r, int unknowns) {
  EXPECT_EQ(r.code, 0) << r;
  EXPECT_EQ(r.err, "") << r;
  const double cond = condition_number(r.out);
  EXPECT_TRUE(std::isfinite(cond) && cond >= 1.0) << r;
  EXPECT_TRUE(std::isfinite(log_det(r.out))) << r;
  const auto s = predicted_std(r.out);
  EXPECT_EQ(s.size(), static_cast<size_t>(unknowns)) << r;
  EXPECT_EQ(s.count("M"), 1u) << r;
  for (const auto& [name, v] : s) EXPECT_TRUE(std::isfinite(v) && v > 0) << name << "\n" << r;
  const auto e = expected_error(r.out);
  EXPECT_EQ(e.size(), 6u) << r;
  for (const char* axis : {"fx", "fy", "fz", "mx", "my", "mz"})
    EXPECT_TRUE(e.count(axis) && std::isfinite(e.at(axis)) && e.at(axis) >= 0) << axis << "\n" << r;
}

// ---------------------------------------------------------------- the plan file

TEST_F(CliDesign, ListedTiltsPlanColumnsLimitsGravityAndGrouping) {
  const massid::Model m = massid::load_urdf(kPumaUrdf);
  const Result r = design(kPumaUrdf, "plan.csv", 16,
                          kPumaLevel + std::vector<std::string>{"--tilts", "0:0,0:25"});
  expect_figures(r, 10);
  EXPECT_NE(r.out.find("wrote " + path("plan.csv")), std::string::npos) << r;
  const Table t = read_plan(path("plan.csv"));
  expect_valid_plan(t, m, 16, {0, 0, kG});
  std::set<std::pair<double, double>> used;
  for (size_t i = 0; i < t.rows.size(); ++i) {
    const double ax = t.num(i, "tilt_x_deg"), ay = t.num(i, "tilt_y_deg");
    const bool level = std::abs(ax) < 1e-9 && std::abs(ay) < 1e-9;
    const bool tilted_25 = std::abs(ax) < 1e-9 && std::abs(ay - 25) < 1e-9;
    EXPECT_TRUE(level || tilted_25) << "row " << i << ": " << ax << ":" << ay;
    used.insert({std::round(ax), std::round(ay)});
    // 0:25 is Ry(25 deg): g = (-sin 25, 0, cos 25) * 9.80665.
    if (tilted_25) {
      const Eigen::Vector3d g(-std::sin(25 * kDeg), 0, std::cos(25 * kDeg));
      EXPECT_LT((gravity_of(t, i) - kG * g).norm(), 1e-9) << "row " << i;
    }
  }
  ASSERT_EQ(used.size(), 2u) << "both tilts are needed";
  EXPECT_EQ(tilt_blocks(t), 2) << "one tilt change";
  EXPECT_NE(r.out.find("order: 1 tilt changes"), std::string::npos) << r;
}

TEST_F(CliDesign, ThreeListedTiltsOnABranchingRobot) {
  const massid::Model m = massid::load_urdf(kBranchingUrdf);
  const Result r = design(kBranchingUrdf, "plan.csv", 20, {"--tilts", "0:0,20:0,-10:15"});
  EXPECT_EQ(r.code, 0) << r;
  const Table t = read_plan(path("plan.csv"));
  expect_valid_plan(t, m, 20, {0, 0, -kG});
  std::set<std::pair<long, long>> used;
  for (size_t i = 0; i < t.rows.size(); ++i) {
    const std::pair<long, long> tilt{std::lround(t.num(i, "tilt_x_deg")),
                                     std::lround(t.num(i, "tilt_y_deg"))};
    EXPECT_TRUE(tilt == std::make_pair(0L, 0L) || tilt == std::make_pair(20L, 0L) ||
                tilt == std::make_pair(-10L, 15L))
        << "row " << i;
    used.insert(tilt);
  }
  // Grouped: each tilt used is one block of consecutive rows.
  EXPECT_EQ(tilt_blocks(t), static_cast<int>(used.size()));
}

TEST_F(CliDesign, TiltMaxKeepsGravityInTheCone) {
  const massid::Model m = massid::load_urdf(kPumaUrdf);
  const Result r =
      design(kPumaUrdf, "plan.csv", 16, kPumaLevel + std::vector<std::string>{"--tilt-max", "20"});
  expect_figures(r, 10);
  const Table t = read_plan(path("plan.csv"));
  const Eigen::Vector3d level(0, 0, kG);
  expect_valid_plan(t, m, 16, level);
  double largest = 0;
  for (size_t i = 0; i < t.rows.size(); ++i) {
    const double a = angle_between(gravity_of(t, i), level);
    EXPECT_LE(a, 20 * kDeg + 1e-9) << "row " << i;
    largest = std::max(largest, a);
  }
  EXPECT_GT(largest, 5 * kDeg) << "the plan uses the tilt it is given";
}

TEST_F(CliDesign, TiltGroupsLimitTheDistinctTiltsInTheCone) {
  const massid::Model m = massid::load_urdf(kPumaUrdf);
  const Eigen::Vector3d level(0, 0, kG);
  for (const int groups : {2, 3}) {
    SCOPED_TRACE("--tilt-groups " + std::to_string(groups));
    const Result r =
        design(kPumaUrdf, "plan.csv", 14,
               kPumaLevel + std::vector<std::string>{"--tilt-max", "20", "--tilt-groups",
                                                     std::to_string(groups)});
    EXPECT_EQ(r.code, 0) << r;
    const Table t = read_plan(path("plan.csv"));
    expect_valid_plan(t, m, 14, level);
    std::set<std::pair<std::string, std::string>> tilts;
    for (size_t i = 0; i < t.rows.size(); ++i) {
      tilts.insert({t.rows[i][t.col("tilt_x_deg")], t.rows[i][t.col("tilt_y_deg")]});
      EXPECT_LE(angle_between(gravity_of(t, i), level), 20 * kDeg + 1e-9) << "row " << i;
    }
    // The groups, plus level for the poses kept level (14 / 4 = 3 of them).
    EXPECT_LE(tilts.size(), static_cast<size_t>(groups) + 1);
    EXPECT_EQ(tilts.count({"0", "0"}), 1u);
    EXPECT_NE(r.out.find("level poses: 3 of 14"), std::string::npos) << r;
    EXPECT_EQ(tilt_blocks(t), static_cast<int>(tilts.size())) << "grouped";
  }
  expect_input_error(run({"design", kPumaUrdf, "-o", path("x.csv"), "--poses", "12", "--tilts",
                          "0:0,0:25", "--tilt-groups", "2"}),
                     {"--tilt-groups"});
}

TEST_F(CliDesign, NoTiltOptionMeansLevelAndGravityMagnitudeFollowsGravity) {
  // wrist_tool has no movable joint: the plan is gravity and tilt only.
  const massid::Model m = massid::load_urdf(kWristUrdf);
  ASSERT_EQ(m.num_joints(), 0);
  Result r = design(kWristUrdf, "tool.csv", 12, {"--tilt-max", "30", "--gravity", "0,0,-9.81"});
  EXPECT_EQ(r.code, 0) << r;
  expect_valid_plan(read_plan(path("tool.csv")), m, 12, {0, 0, -9.81});
  // Without --tilt-max or --tilts every pose is level, which cannot determine
  // the moments along gravity: exit 3 asking for tilts, and no plan written.
  r = design(kWristUrdf, "level.csv", 12, {"--gravity", "0,-9.81,0"});
  EXPECT_EQ(r.code, 3) << r;
  EXPECT_EQ(count_lines(r.err), 1) << r;
  EXPECT_NE(r.err.find("tilt the platform"), std::string::npos) << r;
  EXPECT_FALSE(fs::exists(path("level.csv")));
}

// ---------------------------------------------------------------- joint constraints

TEST_F(CliDesign, FixedHoldsAJointAndLimitsNarrowARange) {
  const massid::Model m = massid::load_urdf(kPumaUrdf);
  const Result r =
      design(kPumaUrdf, "plan.csv", 16,
             kPumaLevel + std::vector<std::string>{"--tilt-max", "20", "--fixed", "joint2=-1.2",
                                                   "--limits", "joint1=-0.5:0.5"});
  EXPECT_EQ(r.code, 0) << r;
  const Table t = read_plan(path("plan.csv"));
  expect_valid_plan(t, m, 16, {0, 0, kG});
  for (const std::string& v : column(t, "joint2")) EXPECT_EQ(std::stod(v), -1.2) << v;
  std::set<std::string> distinct;
  for (const std::string& v : column(t, "joint1")) {
    EXPECT_GE(std::stod(v), -0.5);
    EXPECT_LE(std::stod(v), 0.5);
    distinct.insert(v);
  }
  EXPECT_GT(distinct.size(), 1u) << "joint1 still moves";

  // A range wider than the URDF's is cut to the URDF limits [-0.9, 4.0].
  const Result w =
      design(kPumaUrdf, "wide.csv", 12,
             kPumaLevel + std::vector<std::string>{"--tilt-max", "20", "--limits", "joint3=-10:1"});
  EXPECT_EQ(w.code, 0) << w;
  for (const std::string& v : column(read_plan(path("wide.csv")), "joint3")) {
    EXPECT_GE(std::stod(v), -0.9);
    EXPECT_LE(std::stod(v), 1.0);
  }
}

TEST_F(CliDesign, MinHeightKeepsEveryMovingLinkOriginAboveThePlatform) {
  // ur_like, level gravity -z: the height of a point is its z.
  const massid::Model m = massid::load_urdf(kUrUrdf);
  const double H = 0.1;
  const Result r = design(kUrUrdf, "plan.csv", 16, {"--tilt-max", "15", "--min-height", "0.1"});
  EXPECT_EQ(r.code, 0) << r;
  const Table t = read_plan(path("plan.csv"));
  expect_valid_plan(t, m, 16, {0, 0, -kG});

  expect_min_height(t, m, {0, 0, -kG}, H);
}

TEST_F(CliDesign, MinHeightIsMeasuredAgainstTheLevelGravity) {
  // The PUMA's sensor frame is upside down (gravity +z when level): up is -z.
  const massid::Model m = massid::load_urdf(kPumaUrdf);
  const double H = 0.2;
  const Result r = design(
      kPumaUrdf, "plan.csv", 16,
      kPumaLevel + std::vector<std::string>{"--tilts", "0:0,0:25,25:0", "--min-height", "0.2"});
  EXPECT_EQ(r.code, 0) << r;
  const Table t = read_plan(path("plan.csv"));
  expect_valid_plan(t, m, 16, {0, 0, kG});
  expect_min_height(t, m, {0, 0, kG}, H);
  // An impossible height is a usage error naming the option.
  const Result bad =
      design(kPumaUrdf, "none.csv", 12, kPumaLevel + std::vector<std::string>{"--min-height", "5"});
  expect_input_error(bad, {"--min-height"});
  EXPECT_FALSE(fs::exists(path("none.csv")));
}

// ---------------------------------------------------------------- criterion, noise, seed

TEST_F(CliDesign, DOptimalPlanHasTheLargerLogDet) {
  const std::vector<std::string> args =
      kPumaLevel + std::vector<std::string>{"--tilt-max", "20", "--seed", "7"};
  const Result cond =
      design(kPumaUrdf, "cond.csv", 14, args + std::vector<std::string>{"--criterion", "cond"});
  const Result dopt =
      design(kPumaUrdf, "dopt.csv", 14, args + std::vector<std::string>{"--criterion", "d-opt"});
  expect_figures(cond, 10);
  expect_figures(dopt, 10);
  EXPECT_NE(dopt.out.find("criterion d-opt"), std::string::npos) << dopt;
  EXPECT_GE(log_det(dopt.out), log_det(cond.out)) << cond << dopt;
  // The default criterion is cond.
  const Result dflt = design(kPumaUrdf, "dflt.csv", 14, args);
  EXPECT_EQ(read_file(path("dflt.csv")), read_file(path("cond.csv")));
  EXPECT_NE(dflt.out.find("criterion cond"), std::string::npos) << dflt;
}

TEST_F(CliDesign, PredictedStdScalesWithTheNoise) {
  const std::vector<std::string> args =
      kPumaLevel + std::vector<std::string>{"--tilt-max", "20", "--offset"};
  const Result one =
      design(kPumaUrdf, "one.csv", 14,
             args + std::vector<std::string>{"--noise-force", "0.05", "--noise-moment", "0.004"});
  const Result two =
      design(kPumaUrdf, "two.csv", 14,
             args + std::vector<std::string>{"--noise-force", "0.1", "--noise-moment", "0.008"});
  expect_figures(one, 16);
  expect_figures(two, 16);
  EXPECT_EQ(read_file(path("one.csv")), read_file(path("two.csv"))) << "cond ignores the noise";
  const auto s1 = predicted_std(one.out), s2 = predicted_std(two.out);
  ASSERT_EQ(s1.size(), s2.size());
  for (const auto& [name, v] : s1) {
    ASSERT_EQ(s2.count(name), 1u) << name;
    EXPECT_NEAR(s2.at(name) / v, 2.0, 0.01) << name;  // printed to 3 digits
  }
  const auto e1 = expected_error(one.out), e2 = expected_error(two.out);
  for (const auto& [axis, v] : e1) EXPECT_NEAR(e2.at(axis) / v, 2.0, 0.01) << axis;
  EXPECT_NEAR(condition_number(one.out), condition_number(two.out), 1e-12);
  // Only the force noise: only the forces' share changes, so no std may shrink.
  const Result force =
      design(kPumaUrdf, "force.csv", 14,
             args + std::vector<std::string>{"--noise-force", "0.1", "--noise-moment", "0.004"});
  const auto sf = predicted_std(force.out);
  for (const auto& [name, v] : s1) {
    EXPECT_GE(sf.at(name), v * 0.99) << name;
    EXPECT_LE(sf.at(name), 2 * v * 1.01) << name;
  }
  EXPECT_GT(sf.at("M"), 1.5 * s1.at("M")) << "the total mass is seen by the forces";
}

TEST_F(CliDesign, SeedGivesTheSamePlan) {
  const std::vector<std::string> args = kPumaLevel + std::vector<std::string>{"--tilt-max", "20"};
  EXPECT_EQ(design(kPumaUrdf, "a.csv", 12, args + std::vector<std::string>{"--seed", "3"}).code, 0);
  EXPECT_EQ(design(kPumaUrdf, "b.csv", 12, args + std::vector<std::string>{"--seed", "3"}).code, 0);
  EXPECT_EQ(design(kPumaUrdf, "c.csv", 12, args + std::vector<std::string>{"--seed", "4"}).code, 0);
  const std::string a = read_file(path("a.csv"));
  EXPECT_FALSE(a.empty());
  EXPECT_EQ(a, read_file(path("b.csv")));
  EXPECT_NE(a, read_file(path("c.csv")));
}

// ---------------------------------------------------------------- offsets

TEST_F(CliDesign, OffsetsNeedThreeGravityDirections) {
  const std::string keep = file("plan.csv", "keep me\n");
  const Result two =
      design(kPumaUrdf, "plan.csv", 16,
             kPumaLevel + std::vector<std::string>{"--tilts", "0:0,0:25", "--offset"});
  EXPECT_EQ(two.code, 3) << two;
  EXPECT_EQ(count_lines(two.err), 1) << two;
  EXPECT_NE(two.err.find("offset"), std::string::npos) << two;
  EXPECT_NE(two.err.find("tilt"), std::string::npos) << two;
  EXPECT_EQ(two.err.find("found plan:"), std::string::npos) << two;
  EXPECT_EQ(read_file(keep), "keep me\n");

  const Result cone = design(kPumaUrdf, "plan.csv", 16,
                             kPumaLevel + std::vector<std::string>{"--tilt-max", "25", "--offset"});
  expect_figures(cone, 16);
  const auto s = predicted_std(cone.out);
  for (const char* o :
       {"offset_fx", "offset_fy", "offset_fz", "offset_mx", "offset_my", "offset_mz"})
    EXPECT_EQ(s.count(o), 1u) << o << "\n" << cone;
  EXPECT_EQ(read_plan(path("plan.csv")).rows.size(), 16u);
}

// ---------------------------------------------------------------- --evaluate

TEST_F(CliDesign, EvaluateGivesTheConditionNumberIdentifyReports) {
  const Result e = run({"design", kPumaUrdf, "--evaluate", kPumaPlan, "--gravity", "0,0,9.80665"});
  expect_figures(e, 10);
  EXPECT_NEAR(condition_number(e.out), 5.361, 1e-9) << e;
  EXPECT_EQ(listing(), std::vector<std::string>{}) << "--evaluate writes nothing";

  const std::string data = puma_data();
  const Result id = run({"identify", kPumaUrdf, data, "-o", path("params.json")});
  ASSERT_EQ(id.code, 0) << id;
  EXPECT_EQ(condition_number(id.out), condition_number(e.out)) << id << e;

  // A data file evaluates like its plan (the wrench columns are ignored).
  const Result d = run({"design", kPumaUrdf, "--evaluate", data, "--gravity", "0,0,9.80665"});
  EXPECT_EQ(d.code, 0) << d;
  EXPECT_EQ(condition_number(d.out), condition_number(e.out)) << d;
  EXPECT_EQ(predicted_std(d.out), predicted_std(e.out)) << d;
  // The level direction only sets the random poses of the expected error: a
  // file far from the default level (-z) still evaluates.
  const Result nog = run({"design", kPumaUrdf, "--evaluate", data});
  EXPECT_EQ(nog.code, 0) << nog;
  EXPECT_EQ(condition_number(nog.out), condition_number(e.out)) << nog;
}

TEST_F(CliDesign, EvaluateOfADesignedPlanReproducesItsFigures) {
  const std::vector<std::string> args =
      kPumaLevel + std::vector<std::string>{"--tilt-max",     "20",   "--noise-force", "0.02",
                                            "--noise-moment", "0.003"};
  const Result r = design(kPumaUrdf, "plan.csv", 14, args);
  ASSERT_EQ(r.code, 0) << r;
  const Result e =
      run(std::vector<std::string>{"design", kPumaUrdf, "--evaluate", path("plan.csv")} + args);
  EXPECT_EQ(e.code, 0) << e;
  EXPECT_EQ(condition_number(e.out), condition_number(r.out)) << r << e;
  EXPECT_EQ(log_det(e.out), log_det(r.out)) << r << e;
  EXPECT_EQ(predicted_std(e.out), predicted_std(r.out)) << r << e;
  EXPECT_EQ(expected_error(e.out), expected_error(r.out)) << r << e;
}

TEST_F(CliDesign, EvaluateOfAPlanWhereAJointNeverMovesExits3) {
  Table t = read_plan(kPumaPlan);
  const int c = t.col("joint2");
  ASSERT_GE(c, 0);
  for (auto& row : t.rows) row[c] = "0.3";
  const std::string still = file("still.csv", to_csv(t));
  const Result r = run({"design", kPumaUrdf, "--evaluate", still, "--gravity", "0,0,9.80665"});
  EXPECT_EQ(r.code, 3) << r;
  EXPECT_EQ(count_lines(r.err), 1) << r;
  EXPECT_NE(r.err.find("joint2"), std::string::npos) << r;
  EXPECT_NE(r.err.find("still.csv"), std::string::npos) << r;
}

// ---------------------------------------------------------------- --sensor

TEST_F(CliDesign, SensorLinkBelowTheRoot) {
  const Result r =
      design(kPumaUrdf, "plan.csv", 12,
             kPumaLevel + std::vector<std::string>{"--sensor", "link2", "--tilt-max", "20"});
  EXPECT_EQ(r.code, 0) << r;
  EXPECT_NE(r.out.find("sensor link 'link2'"), std::string::npos) << r;
  const Table t = read_plan(path("plan.csv"));
  expect_valid_plan(t, massid::load_urdf(kPumaUrdf, "link2"), 12, {0, 0, kG});
  EXPECT_EQ(t.col("joint1"), -1);
  EXPECT_EQ(t.col("joint2"), -1);
  EXPECT_GE(t.col("joint3"), 0);
}

// ---------------------------------------------------------------- bad usage

TEST_F(CliDesign, BadUsageExits2AndLeavesTheOutputUntouched) {
  const std::string out = file("plan.csv", "old plan\n");
  struct Case {
    std::vector<std::string> args;
    std::vector<std::string> pieces;
  };
  const std::vector<Case> cases = {
      {{"--tilt-max", "20", "--tilts", "0:0,0:25"}, {"--tilt-max", "--tilts"}},
      {{"--tilts", "0:x"}, {"--tilts", "x"}},
      {{"--tilts", "0:0,25"}, {"--tilts", "25"}},
      {{"--tilt-max", "95"}, {"--tilt-max"}},
      {{"--fixed", "nosuchjoint=1"}, {"nosuchjoint"}},
      {{"--fixed", "joint2"}, {"--fixed", "joint2"}},
      {{"--fixed", "joint2=abc"}, {"--fixed", "abc"}},
      {{"--fixed", "joint2=5"}, {"--fixed", "joint2"}},  // URDF limits [-3.9, 0.6]
      {{"--limits", "joint1=1:0"}, {"--limits", "joint1"}},
      {{"--limits", "joint1=1"}, {"--limits", "joint1"}},
      {{"--limits", "nosuchjoint=0:1"}, {"--limits", "nosuchjoint"}},
      {{"--criterion", "a-opt"}, {"--criterion"}},
      {{"--noise-force", "0"}, {"--noise-force"}},
      {{"--noise-moment", "-1"}, {"--noise-moment"}},
      {{"--gravity", "0,0"}, {"--gravity"}},
      {{"--gravity", "0,0,0"}, {"--gravity"}},
      {{"--seed", "x"}, {"--seed"}},
      {{"--sensor", "nosuchlink"}, {"nosuchlink"}},
  };
  for (const Case& c : cases) {
    std::vector<std::string> args{"design", kPumaUrdf, "-o", out, "--poses", "12"};
    args.insert(args.end(), c.args.begin(), c.args.end());
    std::string cmd;
    for (const auto& a : c.args) cmd += " " + a;
    SCOPED_TRACE("massid design" + cmd);
    expect_input_error(run(args), c.pieces);
  }
  // Neither -o nor --evaluate, or no --poses.
  expect_input_error(run({"design", kPumaUrdf, "--poses", "12"}), {"-o"});
  expect_input_error(run({"design", kPumaUrdf, "-o", out}), {"--poses"});
  expect_input_error(run({"design", kPumaUrdf, "-o", out, "--poses", "0"}), {"--poses"});
  expect_input_error(run({"design", kPumaUrdf, "--evaluate", path("missing.csv")}),
                     {"missing.csv"});
  EXPECT_EQ(read_file(out), "old plan\n");
  EXPECT_EQ(listing(), std::vector<std::string>{"plan.csv"}) << "no temporary files left";
}

}  // namespace

// ---------------------------------------------------------------- defaults: clearance, level poses

// A ROS UR5 (root link "world", sensor frame = the mounting plate, z up): by
// default every moving link origin stays 5 cm above the plate, a quarter of
// the poses are level, the output says both and how to turn them off, and the
// plan still identifies.
TEST_F(CliDesign, DefaultPlanKeepsTheUr5AboveItsMountingPlateWithLevelPoses) {
  const std::string ur5 = kSource + "/tests/data/robots/ur5_robot.urdf";
  const massid::Model m = massid::load_urdf(ur5);
  const Result r = design(ur5, "plan.csv", 24, {"--tilt-max", "25"});
  ASSERT_EQ(r.code, 0) << r;
  const Table t = read_plan(path("plan.csv"));
  expect_valid_plan(t, m, 24, {0, 0, -kG});
  expect_min_height(t, m, {0, 0, -kG}, 0.05);
  for (const char* piece :
       {"clearance: every moving link origin", "0.05 m above the platform",
        "--min-height none turns it off", "level poses: 6 of 24", "--level-poses 0"})
    EXPECT_NE(r.out.find(piece), std::string::npos) << piece << "\n" << r;
  int level = 0;
  double gz_min = INFINITY, gz_max = -INFINITY;
  for (size_t i = 0; i < t.rows.size(); ++i) {
    level += t.num(i, "tilt_x_deg") == 0.0 && t.num(i, "tilt_y_deg") == 0.0;
    gz_min = std::min(gz_min, t.num(i, "gz"));
    gz_max = std::max(gz_max, t.num(i, "gz"));
  }
  EXPECT_EQ(level, 6);
  // fz varies: gz spans at least most of g (1 - cos 25 deg).
  EXPECT_GT(gz_max - gz_min, 0.9 * kG * (1 - std::cos(25 * std::numbers::pi / 180)));
  // The plan identifies: noise-free data give a finite, small condition number
  // and back the URDF's total mass.
  ASSERT_EQ(run({"simulate", ur5, path("plan.csv"), "-o", path("data.csv")}).code, 0);
  const Result id = run({"identify", ur5, path("data.csv"), "-o", path("params.json")});
  ASSERT_EQ(id.code, 0) << id;
  const std::string cond = "condition number";
  EXPECT_NE(id.out.find(cond), std::string::npos) << id;
  const Result ev = run({"design", ur5, "--evaluate", path("plan.csv")});
  ASSERT_EQ(ev.code, 0) << ev;
  const size_t at = ev.out.find("condition number (eq. 36, moment rows): ");
  ASSERT_NE(at, std::string::npos) << ev;
  const double c = std::stod(ev.out.substr(at + 41));
  EXPECT_TRUE(std::isfinite(c) && c < 10) << ev;
  EXPECT_NE(ev.out.find("above the platform plane"), std::string::npos) << ev;
}

TEST_F(CliDesign, MinHeightNoneAndLevelPosesZeroTurnTheDefaultsOff) {
  const std::string ur5 = kSource + "/tests/data/robots/ur5_robot.urdf";
  const massid::Model m = massid::load_urdf(ur5);
  const Result r = design(ur5, "plan.csv", 24,
                          {"--tilt-max", "25", "--min-height", "none", "--level-poses", "0"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_NE(r.out.find("clearance: not constrained (--min-height none)"), std::string::npos) << r;
  EXPECT_EQ(r.out.find("level poses:"), std::string::npos) << r;
  // Unconstrained, the optimiser does drive links through the plate (what the
  // default prevents), and tilts every pose.
  const Table t = read_plan(path("plan.csv"));
  double lowest = INFINITY;
  int level = 0;
  for (size_t i = 0; i < t.rows.size(); ++i) {
    lowest = std::min(lowest, lowest_origin(m, joints_of(t, i, m), {0, 0, -kG}));
    level += t.num(i, "tilt_x_deg") == 0.0 && t.num(i, "tilt_y_deg") == 0.0;
  }
  EXPECT_LT(lowest, 0.0);
  EXPECT_EQ(level, 0);
  // A height that is neither a number nor none is bad usage.
  expect_input_error(design(ur5, "bad.csv", 12, {"--min-height", "low"}), {"--min-height"});
}

// design --dynamic, cheaply: 6 s, 3 harmonics, 100 Hz, a short search.
std::vector<std::string> dynamic_args(const std::string& urdf, const std::string& out) {
  return {"design", urdf,     "--dynamic", "-o",          out, "--duration",    "6",  "--period",
          "6",      "--rate", "100",       "--harmonics", "3", "--evaluations", "300"};
}

// Independently from the CSV: every row within the position limits (10 %
// margin), the velocity and acceleration limits, at rest in the first and
// last rows, the moving link origins at least `height` above the plate.
void expect_trajectory_within(const Table& t, const massid::Model& m,
                              const std::map<std::string, double>& velocity,
                              const std::map<std::string, double>& acceleration, double height) {
  ASSERT_GT(t.rows.size(), 2u);
  for (const auto& j : m.joints) {
    const double margin = 0.1 * (j.upper - j.lower);
    const double v = velocity.count(j.name) ? velocity.at(j.name)
                     : j.velocity_limit > 0 ? j.velocity_limit
                                            : 1.0;
    const double a = acceleration.count(j.name) ? acceleration.at(j.name) : 4.0;
    for (size_t r = 0; r < t.rows.size(); ++r) {
      if (j.limited) {
        EXPECT_GE(t.num(r, j.name), j.lower + margin - 1e-9) << j.name << " row " << r;
        EXPECT_LE(t.num(r, j.name), j.upper - margin + 1e-9) << j.name << " row " << r;
      }
      EXPECT_LE(std::abs(t.num(r, j.name + "_vel")), v * (1 + 1e-9)) << j.name << " row " << r;
      EXPECT_LE(std::abs(t.num(r, j.name + "_acc")), a * (1 + 1e-9)) << j.name << " row " << r;
    }
    for (const size_t r : {size_t{0}, t.rows.size() - 1}) {
      EXPECT_NEAR(t.num(r, j.name + "_vel"), 0.0, 1e-9) << j.name << " row " << r;
      EXPECT_NEAR(t.num(r, j.name + "_acc"), 0.0, 1e-9) << j.name << " row " << r;
    }
  }
  for (size_t r = 0; r < t.rows.size(); ++r)
    EXPECT_GE(lowest_origin(m, joints_of(t, r, m), gravity_of(t, 0)), height - 1e-9) << "row " << r;
}

TEST_F(CliDesign, DynamicTrajectoryKeepsEveryLimitAndStaysAboveThePlate) {
  const std::string ur5 = kSource + "/tests/data/robots/ur5_robot.urdf";
  const massid::Model m = massid::load_urdf(ur5);
  const Result r = run(dynamic_args(ur5, path("traj.csv")) +
                       std::vector<std::string>{"--velocity-limit", "shoulder_pan_joint=0.5",
                                                "--acceleration-limit", "elbow_joint=2"});
  ASSERT_EQ(r.code, 0) << r;
  const Table t = read_plan(path("traj.csv"));
  EXPECT_EQ(t.rows.size(), 601u);
  expect_trajectory_within(t, m, {{"shoulder_pan_joint", 0.5}}, {{"elbow_joint", 2.0}}, 0.05);
  EXPECT_NE(r.out.find("clearance: every moving link origin"), std::string::npos) << r;
  EXPECT_NE(r.out.find("random trajectories within the same limits: median"), std::string::npos)
      << r;
  // A height above the arm's reach: no trajectory keeps it, an error names the option.
  expect_input_error(
      run(dynamic_args(ur5, path("traj2.csv")) + std::vector<std::string>{"--min-height", "3"}),
      {"--min-height", "above the platform plane"});
  // Without the constraint the search may go below.
  const Result off =
      run(dynamic_args(ur5, path("traj3.csv")) + std::vector<std::string>{"--min-height", "none"});
  ASSERT_EQ(off.code, 0) << off;
  EXPECT_NE(off.out.find("clearance: not constrained"), std::string::npos) << off;
  // Options of static plans only are refused.
  expect_input_error(
      run(dynamic_args(ur5, path("traj4.csv")) + std::vector<std::string>{"--poses", "10"}),
      {"--poses", "static plans only"});
}

// A duration that is not a whole number of periods: the period is adjusted so
// that the trajectory still ends at rest, and the output says so.
TEST_F(CliDesign, DynamicTrajectoryEndsAtRestWhateverTheDuration) {
  const std::string urdf = example("ur_like/ur_like.urdf");
  const massid::Model m = massid::load_urdf(urdf);
  std::vector<std::string> args = dynamic_args(urdf, path("traj.csv"));
  args[6] = "5";  // --duration 5 with --period 6
  ASSERT_EQ(args[5], "--duration");
  const Result r = run(args);
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_NE(r.out.find("period 5 s, 5 s at 100 Hz (--period 6 s adjusted to 1 period in 5 s"),
            std::string::npos)
      << r;
  const Table t = read_plan(path("traj.csv"));
  EXPECT_EQ(t.rows.size(), 501u);
  expect_trajectory_within(t, m, {}, {}, 0.05);
}

TEST_F(CliDesign, DynamicTrajectoryIsByteIdenticalForTheSameSeed) {
  const std::string urdf = example("ur_like/ur_like.urdf");
  for (const char* name : {"a.csv", "b.csv"})
    ASSERT_EQ(run(dynamic_args(urdf, path(name)) + std::vector<std::string>{"--seed", "4"}).code,
              0);
  EXPECT_EQ(read_file(path("a.csv")), read_file(path("b.csv")));
  ASSERT_EQ(run(dynamic_args(urdf, path("c.csv")) + std::vector<std::string>{"--seed", "5"}).code,
            0);
  EXPECT_NE(read_file(path("a.csv")), read_file(path("c.csv")));
}

// Tilts: a block per tilt, gravity fixed in each and tilted as listed; the
// simulated log identifies end to end with gravity varying (44 parameters of
// ur_like, against 43 level), from the given derivatives and from positions
// only (the filter restarts at each block).
TEST_F(CliDesign, DynamicTiltsGiveGravityBlocksThatIdentifyEndToEnd) {
  const std::string urdf = example("ur_like/ur_like.urdf");
  const massid::Model m = massid::load_urdf(urdf);
  const Result r = run(dynamic_args(urdf, path("traj.csv")) +
                       std::vector<std::string>{"--tilts", "0:0,20:0,0:-20"});
  ASSERT_EQ(r.code, 0) << r;
  EXPECT_NE(r.out.find("once per tilt (3 blocks)"), std::string::npos) << r;
  const Table t = read_plan(path("traj.csv"));
  ASSERT_EQ(t.rows.size(), 3u * 601u);
  ASSERT_GE(t.col("block"), 0);
  const Eigen::Vector3d level(0, 0, -kG);
  const Eigen::Vector3d want[3] = {level, tilted(level, 20, 0), tilted(level, 0, -20)};
  for (size_t i = 0; i < t.rows.size(); ++i) {
    const int b = static_cast<int>(i / 601);
    EXPECT_EQ(t.num(i, "block"), b) << "row " << i;
    EXPECT_LT((gravity_of(t, i) - want[b]).norm(), 1e-9) << "row " << i;
    if (i > 0) {
      EXPECT_GT(t.num(i, "t"), t.num(i - 1, "t")) << "row " << i;
    }
    // Every block is the same trajectory.
    for (const auto& j : m.joints) EXPECT_EQ(t.num(i, j.name), t.num(i % 601, j.name));
  }
  expect_trajectory_within(t, m, {}, {}, 0.05);
  const Result sim = run({"simulate", urdf, path("traj.csv"), "-o", path("log.csv"), "--dynamic",
                          "--noise-force", "0.1", "--noise-moment", "0.01"});
  ASSERT_EQ(sim.code, 0) << sim;
  const Result id = run({"identify", urdf, path("log.csv"), "--dynamic", "-o", path("p.json")});
  ASSERT_EQ(id.code, 0) << id;
  const json p = json::parse(read_file(path("p.json")));
  EXPECT_EQ(p["base_parameters"].size(), 44u) << id;
  const Result level_id = run(dynamic_args(urdf, path("level.csv")));
  ASSERT_EQ(level_id.code, 0) << level_id;
  EXPECT_NE(level_id.out.find("43 dynamic base parameters"), std::string::npos) << level_id;
  EXPECT_NE(r.out.find("44 dynamic base parameters"), std::string::npos) << r;
  // From positions only: drop the _vel and _acc columns.
  const Table pos = without_columns(read_plan(path("log.csv")), [](const std::string& c) {
    return c.ends_with("_vel") || c.ends_with("_acc");
  });
  write_file(path("log_q.csv"), to_csv(pos));
  const Result idq = run({"identify", urdf, path("log_q.csv"), "--dynamic", "-o", path("q.json")});
  ASSERT_EQ(idq.code, 0) << idq;
  EXPECT_EQ(json::parse(read_file(path("q.json")))["base_parameters"].size(), 44u) << idq;
}
