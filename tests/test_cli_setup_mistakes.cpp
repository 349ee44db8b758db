// Set-up mistakes on a real description (the published UR5, world root): a
// flipped or swapped wrench channel, a sensor turned 180 deg, a URDF without
// inertials, joints in degrees given to simulate, predict and design
// --evaluate, and the outlier test with gravity taken from the force. Each
// mistake is exit 2 with a message naming the file and the fix, and following
// the fix gives the clean result.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <regex>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.hpp"

namespace {

using namespace massid_cli_test;

const std::string kUr5 = kSource + "/tests/data/robots/ur5_robot.urdf";
constexpr double kUr5Mass =
    4.0 + 3.7 + 8.393 + 2.275 + 1.219 + 1.219 + 0.1879;  // its <mass> values

std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

double total_mass(const std::string& out) {
  const size_t at = out.find("total mass: ");
  return at == std::string::npos ? NAN : std::stod(out.substr(at + 12));
}

class SetupMistakes : public Cli {
 protected:
  // A plan of the UR5 tilted up to 25 deg (design puts most poses at the
  // largest tilt: gz then hardly varies), simulated with the README's noise
  // and a sensor offset.
  std::string plan(int poses = 60) {
    const Result r = run({"design", kUr5, "-o", path("plan.csv"), "--poses", std::to_string(poses),
                          "--tilt-max", "25", "--seed", "1"});
    EXPECT_EQ(r.code, 0) << r;
    return path("plan.csv");
  }
  std::string simulated(const std::string& plan_path, const std::string& name, int seed = 3,
                        const std::string& offset = "1,-2,3.5,0.1,-0.2,0.3") {
    const Result r =
        run({"simulate", kUr5, plan_path, "-o", path(name), "--noise-force", "0.05",
             "--noise-moment", "0.005", "--offset", offset, "--seed", std::to_string(seed)});
    EXPECT_EQ(r.code, 0) << r;
    return path(name);
  }
  static std::function<void(const Table&, std::vector<std::string>&)> scaled(
      const std::vector<std::string>& cols, double k) {
    return [=](const Table& t, std::vector<std::string>& row) {
      for (const auto& c : cols) row[t.col(c)] = num(k * std::stod(row[t.col(c)]));
    };
  }
  static void swap_fx_fy(const Table& t, std::vector<std::string>& row) {
    std::swap(row[t.col("fx")], row[t.col("fy")]);
  }
  // identify with --offset (the simulated sensor has one) unless told not to;
  // no params file is left from an earlier run.
  Result identify(const std::string& urdf, const std::string& data,
                  const std::vector<std::string>& extra = {"--offset"}) {
    fs::remove(path("p.json"));
    std::vector<std::string> args{"identify", urdf, data, "-o", path("p.json")};
    args.insert(args.end(), extra.begin(), extra.end());
    return run(args);
  }
  // The UR5 without any <inertial> element.
  std::string massless() {
    const std::string text =
        std::regex_replace(read_file(kUr5), std::regex("<inertial>[^]*?</inertial>"), "");
    EXPECT_EQ(text.find("inertial"), std::string::npos);
    return file("ur5_nomass.urdf", text);
  }
};

// ----------------------------------------------------------- item 2: channels

TEST_F(SetupMistakes, NegatedFzIsExit2NamingTheChannelAndTheFixWorks) {
  const std::string data = simulated(plan(), "d.csv");
  const Result clean = identify(kUr5, data);
  ASSERT_EQ(clean.code, 0) << clean;
  EXPECT_EQ(clean.err, "") << clean;
  EXPECT_NEAR(total_mass(clean.out), kUr5Mass, 0.05) << clean;

  const std::string neg = edited(data, "negfz.csv", scaled({"fz"}, -1.0));
  const Result r = identify(kUr5, neg);
  expect_input_error(r, {neg, "'fz' is negated", "negate fz", "--no-checks"});
  EXPECT_EQ(count_lines(r.err), 1) << r;
  EXPECT_EQ(r.err.find("'mz'"), std::string::npos) << r;  // the moments are right
  EXPECT_FALSE(fs::exists(path("p.json")));
  // The advice applied: the clean data again.
  const std::string fixed = edited(neg, "fixed.csv", scaled({"fz"}, -1.0));
  const Result f = identify(kUr5, fixed);
  EXPECT_EQ(f.code, 0) << f;
  EXPECT_NEAR(total_mass(f.out), total_mass(clean.out), 1e-9) << f;
}

TEST_F(SetupMistakes, NegatedFzAndMzAreNamedTogether) {
  const std::string data = simulated(plan(), "d.csv");
  const std::string neg = edited(data, "neg.csv", scaled({"fz", "mz"}, -1.0));
  expect_input_error(identify(kUr5, neg),
                     {neg, "'fz' is negated", "'mz' is negated", "negate fz and negate mz"});
  // mz alone: the moment channels.
  const std::string negm = edited(data, "negm.csv", scaled({"mz"}, -1.0));
  const Result r = identify(kUr5, negm);
  expect_input_error(r, {negm, "moment channels", "'mz' is negated", "negate mz"});
  EXPECT_EQ(r.err.find("'fz'"), std::string::npos) << r;
}

TEST_F(SetupMistakes, SwappedForceChannelsAreNamedNotCalledARotation) {
  const std::string data = simulated(plan(), "d.csv");
  const std::string sw = edited(data, "swap.csv", swap_fx_fy);
  const Result r = identify(kUr5, sw);
  expect_input_error(r, {sw, "'fx' holds fy", "'fy' holds fx"});
  EXPECT_EQ(r.err.find("rotated"), std::string::npos) << r;
  const Result f = identify(kUr5, edited(sw, "fixed.csv", swap_fx_fy));
  EXPECT_EQ(f.code, 0) << f;
  EXPECT_EQ(f.err, "") << f;
}

TEST_F(SetupMistakes, EverySingleNegatedForceChannelIsFound) {
  const std::string data = simulated(plan(), "d.csv");
  for (const std::string ch : {"fx", "fy", "fz", "mx", "my", "mz"}) {
    const std::string neg = edited(data, "neg_" + ch + ".csv", scaled({ch}, -1.0));
    expect_input_error(identify(kUr5, neg), {neg, "'" + ch + "' is negated", "negate " + ch});
  }
}

// ----------------------------------------------------------- item 3: 180 deg

TEST_F(SetupMistakes, SensorTurned180DegAboutZIsARotationNotASignError) {
  const std::string data = simulated(plan(), "d.csv");
  const std::string rot = edited(data, "rot.csv", scaled({"fx", "fy", "mx", "my"}, -1.0));
  const Result r = identify(kUr5, rot);
  expect_input_error(r, {rot, "rotated", "180.00 deg about (", "Rotate fx,fy,fz and mx,my,mz"});
  EXPECT_EQ(count_lines(r.err), 1) << r;
  EXPECT_EQ(r.err.find("against gravity"), std::string::npos) << r;
  EXPECT_EQ(r.err.find("(lines ;"), std::string::npos) << r;
  EXPECT_EQ(r.err.find("lines ;"), std::string::npos) << r;
  // R^T applied (180 deg about z: negate x and y of both): the clean fit.
  const Result f = identify(kUr5, edited(rot, "fixed.csv", scaled({"fx", "fy", "mx", "my"}, -1.0)));
  EXPECT_EQ(f.code, 0) << f;
  EXPECT_EQ(f.err, "") << f;
}

TEST_F(SetupMistakes, NegatedWrenchIsStillTheSignErrorWithItsLines) {
  const std::string data = simulated(plan(), "d.csv");
  const std::string neg =
      edited(data, "neg.csv", scaled({"fx", "fy", "fz", "mx", "my", "mz"}, -1.0));
  const Result r = identify(kUr5, neg);
  expect_input_error(r, {neg, "points against gravity", "negate fx,fy,fz,mx,my,mz"});
  EXPECT_EQ(r.err.find("at 0 of"), std::string::npos) << r;
  EXPECT_EQ(count_lines(r.err), 1) << r;
}

// ----------------------------------------------------------- item 7: no inertials

TEST_F(SetupMistakes, UrdfWithoutInertialsIsSaidAndUnitsAreJudgedBySize) {
  const std::string urdf = massless();
  const Result m = run({"model", urdf});
  EXPECT_EQ(m.code, 0) << m;
  EXPECT_NE(m.err.find("massid: warning: " + urdf + ": no measured link has a mass"),
            std::string::npos)
      << m;
  const std::string p = plan();
  const Result s = run({"simulate", urdf, p, "-o", path("nothing.csv")});
  EXPECT_EQ(s.code, 2) << s;
  EXPECT_NE(s.err.find(urdf + ": no measured link has a mass"), std::string::npos) << s;
  EXPECT_FALSE(fs::exists(path("nothing.csv")));

  // Data of the real UR5 identified against the massless description: clean
  // data pass; mN and N mm are caught without a nominal mass.
  const std::string data = simulated(p, "d.csv");
  const Result clean = identify(urdf, data);
  EXPECT_EQ(clean.code, 0) << clean;
  EXPECT_EQ(clean.err, "") << clean;
  EXPECT_NEAR(total_mass(clean.out), kUr5Mass, 0.05) << clean;
  const std::string mN = edited(data, "mN.csv", scaled({"fx", "fy", "fz"}, 1000.0));
  expect_input_error(identify(urdf, mN),
                     {mN, "no mass", "look like mN", "divide fx,fy,fz by 1000"});
  const std::string nmm = edited(data, "Nmm.csv", scaled({"mx", "my", "mz"}, 1000.0));
  expect_input_error(identify(urdf, nmm),
                     {nmm, "no mass", "look like N mm", "divide mx,my,mz by 1000"});
}

// ----------------------------------------------------------- item 8: degrees elsewhere

TEST_F(SetupMistakes, JointsInDegreesAreCaughtBySimulatePredictAndEvaluate) {
  const std::string p = plan();
  const std::string data = simulated(p, "d.csv");
  ASSERT_EQ(identify(kUr5, data).code, 0);
  const std::string params = path("p.json");
  const double to_deg = 180 / std::numbers::pi;
  // Clean files: nothing said.
  for (const Result& r :
       {run({"simulate", kUr5, p, "-o", path("s.csv")}), run({"predict", kUr5, params, data}),
        run({"design", kUr5, "--evaluate", p})}) {
    EXPECT_EQ(r.code, 0) << r;
    EXPECT_EQ(r.err, "") << r;
  }
  const std::string pdeg = edited(p, "plan_deg.csv", scaled({"elbow_joint"}, to_deg));
  const std::string ddeg = edited(data, "data_deg.csv", scaled({"elbow_joint"}, to_deg));
  const std::vector<std::string> says{"'elbow_joint'", "elbow_joint_deg", "degrees"};
  expect_input_error(run({"simulate", kUr5, pdeg, "-o", path("s2.csv")}), {pdeg, says[0], says[1]});
  EXPECT_FALSE(fs::exists(path("s2.csv")));
  expect_input_error(run({"predict", kUr5, params, ddeg}), {ddeg, says[0], says[1]});
  expect_input_error(run({"predict", kUr5, params, pdeg}), {pdeg, says[0], says[1]});
  expect_input_error(run({"design", kUr5, "--evaluate", pdeg}), {pdeg, says[0], says[1]});
  // --no-checks: as asked.
  EXPECT_EQ(run({"predict", kUr5, params, ddeg, "--no-checks"}).code, 0);
  EXPECT_EQ(run({"simulate", kUr5, pdeg, "-o", path("s3.csv"), "--no-checks"}).code, 0);
  EXPECT_EQ(run({"design", kUr5, "--evaluate", pdeg, "--no-checks"}).code, 0);
  // Gravity in g in a plan given to simulate.
  const std::string pg = edited(p, "plan_g.csv", scaled({"gx", "gy", "gz"}, 1 / 9.80665));
  expect_input_error(run({"simulate", kUr5, pg, "-o", path("s4.csv")}),
                     {pg, "gx,gy,gz", "multiply gx,gy,gz by 9.80665"});
}

// ----------------------------------------------------------- item 14: outliers, eq. 37

TEST_F(SetupMistakes, GravityFromTheForceFlagsNoCleanSampleButARealOutlier) {
  const std::string p = plan(120);
  for (int seed : {1, 2, 3, 4, 5}) {
    const std::string data = simulated(p, "d.csv", seed, "0,0,0,0,0,0");
    const Table t = read_table(data);
    const Table s = without_columns(
        t, [](const std::string& c) { return c == "gx" || c == "gy" || c == "gz"; });
    const std::string nog = file("nog.csv", to_csv(s));
    const Result r = identify(kUr5, nog, {});  // offsets need gx,gy,gz
    EXPECT_EQ(r.code, 0) << r;
    EXPECT_EQ(r.err.find("implausible"), std::string::npos) << "seed " << seed << "\n" << r;
    EXPECT_NEAR(total_mass(r.out), kUr5Mass, 0.05) << r;
    // One sample bumped by 1 N along fx (20 sigma): found by its line (the
    // header is line 1, row k is line k + 2).
    Table b = s;
    b.rows[40][b.col("fx")] = num(std::stod(b.rows[40][b.col("fx")]) + 1.0);
    const std::string bumped = file("bumped.csv", to_csv(b));
    const Result o = identify(kUr5, bumped, {});
    EXPECT_EQ(o.code, 0) << o;
    EXPECT_NE(o.err.find("1 sample(s) have residuals implausible"), std::string::npos)
        << "seed " << seed << "\n"
        << o;
    EXPECT_NE(o.err.find(" 42 (d = "), std::string::npos) << o;
  }
}

}  // namespace
