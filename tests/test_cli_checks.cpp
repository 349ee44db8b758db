// massid identify's set-up checks as a user meets them: a mistake of the
// set-up (wrench sign, rotated frame, units, gravity, columns) is exit 2 with a
// one-line diagnosis and its fix before any work, a likely mistake is a
// warning, clean data say nothing, and --no-checks skips them.
#include <gtest/gtest.h>

#include <cmath>
#include <functional>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include "cli_support.hpp"

namespace {

using namespace massid_cli_test;

std::string num(double v) {
  std::ostringstream s;
  s.precision(17);
  s << v;
  return s.str();
}

class CliChecks : public Cli {
 protected:
  // Simulated data of an example with the README's noise and a sensor offset.
  std::string simulated(const std::string& ex, const std::string& name,
                        const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args{"simulate",
                                  example(ex + "/" + ex + ".urdf"),
                                  example(ex + "/plan.csv"),
                                  "-o",
                                  path(name),
                                  "--noise-force",
                                  "0.05",
                                  "--noise-moment",
                                  "0.005",
                                  "--offset",
                                  "1,-2,3.5,0.1,-0.2,0.3",
                                  "--seed",
                                  "3"};
    args.insert(args.end(), extra.begin(), extra.end());
    const Result r = run(args);
    EXPECT_EQ(r.code, 0) << r;
    return path(name);
  }

  static void scale(const Table& t, std::vector<std::string>& row,
                    const std::vector<std::string>& cols, double k) {
    for (const auto& c : cols) row[t.col(c)] = num(k * std::stod(row[t.col(c)]));
  }

  Result identify(const std::string& urdf, const std::string& data,
                  const std::vector<std::string>& extra = {}) {
    std::vector<std::string> args{"identify", urdf, data, "-o", path("p.json")};
    args.insert(args.end(), extra.begin(), extra.end());
    return run(args);
  }
};

const std::vector<std::string> kWrench{"fx", "fy", "fz", "mx", "my", "mz"};

TEST_F(CliChecks, CleanDataWithNoiseAndOffsetSayNothing) {
  for (const std::string ex : {"puma260", "ur_like", "branching", "wrist_tool"}) {
    const std::string data = simulated(ex, ex + ".csv");
    const Result r = identify(example(ex + "/" + ex + ".urdf"), data);
    EXPECT_EQ(r.code, 0) << r;
    EXPECT_EQ(r.err, "") << r;
  }
}

TEST_F(CliChecks, NegatedWrenchIsExit2WithTheFix) {
  const std::string data = edited(simulated("puma260", "d.csv"), "neg.csv",
                                  [](const Table& t, auto& row) { scale(t, row, kWrench, -1.0); });
  const Result r = identify(kPumaUrdf, data);
  expect_input_error(r,
                     {data, "points against gravity", "negate fx,fy,fz,mx,my,mz", "--no-checks"});
  EXPECT_FALSE(fs::exists(path("p.json")));
  // --no-checks: identified as asked (a negative total mass).
  const Result n = identify(kPumaUrdf, data, {"--no-checks"});
  EXPECT_EQ(n.code, 0) << n;
  EXPECT_EQ(n.err, "") << n;
  EXPECT_NE(n.out.find("total mass: -1"), std::string::npos) << n;
}

TEST_F(CliChecks, RotatedWrenchFrameIsExit2WithTheRotation) {
  // The wrench 10 deg about z from the gravity columns' frame.
  const double c = std::cos(10 * std::numbers::pi / 180), s = std::sin(10 * std::numbers::pi / 180);
  auto rot = [&](const Table& t, std::vector<std::string>& row) {
    for (const char* p : {"f", "m"}) {
      const std::string x = std::string(p) + "x", y = std::string(p) + "y";
      const double vx = std::stod(row[t.col(x)]), vy = std::stod(row[t.col(y)]);
      row[t.col(x)] = num(c * vx - s * vy);
      row[t.col(y)] = num(s * vx + c * vy);
    }
  };
  const std::string data = edited(simulated("ur_like", "d.csv"), "rot.csv", rot);
  expect_input_error(identify(kUrUrdf, data), {data, "disagrees with gx,gy,gz by", "R = [[",
                                               "1.000)", "Rotate fx,fy,fz and mx,my,mz by R^T"});
}

TEST_F(CliChecks, SmallRotationIsAWarningAndIdentifyGoesOn) {
  const double c = std::cos(3 * std::numbers::pi / 180), s = std::sin(3 * std::numbers::pi / 180);
  auto rot = [&](const Table& t, std::vector<std::string>& row) {
    for (const char* p : {"f", "m"}) {
      const std::string y = std::string(p) + "y", z = std::string(p) + "z";
      const double vy = std::stod(row[t.col(y)]), vz = std::stod(row[t.col(z)]);
      row[t.col(y)] = num(c * vy - s * vz);
      row[t.col(z)] = num(s * vy + c * vz);
    }
  };
  const std::string data = edited(simulated("ur_like", "d.csv"), "rot3.csv", rot);
  const Result r = identify(kUrUrdf, data);
  EXPECT_EQ(r.code, 0) << r;
  EXPECT_EQ(r.err.rfind("massid: warning: " + data + ": the force direction disagrees", 0), 0u)
      << r;
  EXPECT_NE(r.out.find("wrote "), std::string::npos) << r;
}

TEST_F(CliChecks, JointInDegreesIsExit2) {
  const std::string data =
      edited(simulated("puma260", "d.csv"), "deg.csv",
             [](const Table& t, auto& row) { scale(t, row, {"joint2"}, 180 / std::numbers::pi); });
  expect_input_error(identify(kPumaUrdf, data), {data, "'joint2'", "joint2_deg", "degrees"});
}

TEST_F(CliChecks, ForceInMillinewtonsIsExit2) {
  const std::string data =
      edited(simulated("ur_like", "d.csv"), "mN.csv", [](const Table& t, auto& row) {
        scale(t, row, {"fx", "fy", "fz"}, 1000.0);
      });
  expect_input_error(identify(kUrUrdf, data), {data, "mN", "divide fx,fy,fz by 1000"});
}

TEST_F(CliChecks, MomentInNewtonMillimetresIsExit2) {
  const std::string data =
      edited(simulated("ur_like", "d.csv"), "Nmm.csv", [](const Table& t, auto& row) {
        scale(t, row, {"mx", "my", "mz"}, 1000.0);
      });
  expect_input_error(identify(kUrUrdf, data), {data, "N mm", "divide mx,my,mz by 1000"});
}

TEST_F(CliChecks, BothUnitMistakesAreTwoErrorLines) {
  const std::string data =
      edited(simulated("ur_like", "d.csv"), "both.csv",
             [](const Table& t, auto& row) { scale(t, row, kWrench, 1000.0); });
  const Result r = identify(kUrUrdf, data);
  EXPECT_EQ(r.code, 2) << r;
  EXPECT_EQ(count_lines(r.err), 2) << r;
  EXPECT_NE(r.err.find("massid: error: " + data + ": fx,fy,fz"), std::string::npos) << r;
  EXPECT_NE(r.err.find("massid: error: " + data + ": mx,my,mz"), std::string::npos) << r;
}

TEST_F(CliChecks, GravityInWrongUnitsIsExit2) {
  const std::string data =
      edited(simulated("ur_like", "d.csv"), "g.csv", [](const Table& t, auto& row) {
        scale(t, row, {"gx", "gy", "gz"}, 1000.0);
      });
  expect_input_error(identify(kUrUrdf, data),
                     {data, "gx,gy,gz", "mm/s^2", "divide gx,gy,gz by 1000"});
}

TEST_F(CliChecks, DuplicatedWrenchColumnIsExit2) {
  const std::string data =
      edited(simulated("puma260", "d.csv"), "dup.csv",
             [](const Table& t, auto& row) { row[t.col("my")] = row[t.col("mx")]; });
  expect_input_error(identify(kPumaUrdf, data), {data, "'mx' and 'my'", "identical"});
}

TEST_F(CliChecks, DeadWrenchChannelIsExit2) {
  const std::string data = edited(simulated("puma260", "d.csv"), "dead.csv",
                                  [](const Table& t, auto& row) { row[t.col("fz")] = "0"; });
  expect_input_error(identify(kPumaUrdf, data), {data, "'fz'", "dead"});
}

TEST_F(CliChecks, DuplicatedJointColumnIsAWarning) {
  const std::string data = edited(
      simulated("ur_like", "d.csv"), "dupj.csv",
      [](const Table& t, auto& row) { row[t.col("wrist_3_joint")] = row[t.col("wrist_2_joint")]; });
  const Result r = identify(kUrUrdf, data);
  EXPECT_EQ(r.err.rfind("massid: warning: " + data +
                            ": joint columns 'wrist_2_joint' and "
                            "'wrist_3_joint' are identical",
                        0),
            0u)
      << r;
}

TEST_F(CliChecks, BigFilesAreCheckedOnTheirFirstRows) {
  // 120 000 rows (streamed): the checks read the first 100 000 only.
  const std::string big = path("big.csv");
  ASSERT_EQ(run({"simulate", kPumaUrdf, kPumaPlan, "-o", big, "--repeat", "4000", "--noise-force",
                 "0.05", "--noise-moment", "0.005"})
                .code,
            0);
  const Result ok = identify(kPumaUrdf, big);
  EXPECT_EQ(ok.code, 0) << ok;
  EXPECT_EQ(ok.err, "") << ok;
  const std::string neg =
      edited(big, "big_neg.csv", [](const Table& t, auto& row) { scale(t, row, kWrench, -1.0); });
  expect_input_error(identify(kPumaUrdf, neg), {neg, "points against gravity"});
}

}  // namespace
