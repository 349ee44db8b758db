// Numerical range: the same robot scaled from 1 g to 1 t and from 1 mm to 5 m
// lever arms is identified to the round-off floor from noise-free data and as
// the standard deviations predict from noisy data; a robot mixing those scales;
// near-singular plans (nearly level, nearly two gravity directions, a joint
// that hardly moves) either fail with IdentifiabilityError naming what is
// undetermined or return a huge condition number with standard deviations
// that cover the errors; a million samples streamed agree with the truth, the
// std and a dense fit of a subsample, bit-identically on 1, 2 and 4 threads.
// docs/accuracy.md reports the figures these tests measure.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/model.hpp"
#include "massid/core/regressor.hpp"
#include "massid/core/simulate.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/streaming.hpp"
#include "massid/io/urdf.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

constexpr int kLinks = 6;  // sensor, base (fixed), link1..link3 (revolute), link4 (prismatic)

// Per link: mass (kg) and length scale (m) of its centre-of-mass offset and of
// the origin of the joints to its children.
struct Scales {
  std::array<double, kLinks> mass;
  std::array<double, kLinks> length;
};

Scales uniform(double mass, double length) {
  Scales s;
  s.mass.fill(mass);
  s.length.fill(length);
  return s;
}

std::string xyz(const Eigen::Vector3d& v) {
  std::ostringstream os;
  os.precision(17);
  os << v.x() << " " << v.y() << " " << v.z();
  return os.str();
}

// A sensor, a fixed base and a serial arm of three revolute joints (z, y, x)
// and a prismatic one; every centre of mass off every axis, so no base
// parameter vanishes.
std::string scaled_urdf(const Scales& sc) {
  const std::array<const char*, kLinks> names{"sensor", "base", "link1", "link2", "link3", "link4"};
  const std::array<Eigen::Vector3d, kLinks> com{
      Eigen::Vector3d(0.11, 0.23, 0.31),  Eigen::Vector3d(0.07, -0.13, 0.21),
      Eigen::Vector3d(0.29, 0.17, 0.19),  Eigen::Vector3d(0.53, 0.06, -0.12),
      Eigen::Vector3d(0.22, 0.31, -0.14), Eigen::Vector3d(0.18, -0.26, 0.09)};
  // Joint origin of link l in its parent's frame, in units of the parent's length.
  const std::array<Eigen::Vector3d, kLinks> origin{
      Eigen::Vector3d::Zero(),           Eigen::Vector3d(0.02, 0.01, 0.5),
      Eigen::Vector3d(0.03, -0.02, 0.4), Eigen::Vector3d(0.12, 0.21, 0.33),
      Eigen::Vector3d(0.61, 0.04, 0.05), Eigen::Vector3d(0.4, 0.1, -0.07)};
  const std::array<const char*, kLinks> type{"",         "fixed",    "revolute",
                                             "revolute", "revolute", "prismatic"};
  const std::array<const char*, kLinks> axis{"", "", "0 0 1", "0 1 0", "1 0 0", "0.6 0 0.8"};
  std::ostringstream u;
  u.precision(17);
  u << "<?xml version=\"1.0\"?>\n<robot name=\"scaled\">\n";
  for (int l = 0; l < kLinks; ++l) {
    const double m = sc.mass[l], L = sc.length[l], I = 0.01 * m * L * L;
    u << "  <link name=\"" << names[l] << "\"><inertial><origin xyz=\"" << xyz(L * com[l])
      << "\" rpy=\"0 0 0\"/><mass value=\"" << m << "\"/><inertia ixx=\"" << I
      << "\" ixy=\"0\" ixz=\"0\" iyy=\"" << I << "\" iyz=\"0\" izz=\"" << I
      << "\"/></inertial></link>\n";
    if (l == 0) continue;
    const double Lp = sc.length[l - 1];
    const std::string joint = l == 1 ? std::string("base_fixed") : "joint" + std::to_string(l - 1);
    u << "  <joint name=\"" << joint << "\" type=\"" << type[l] << "\"><parent link=\""
      << names[l - 1] << "\"/><child link=\"" << names[l] << "\"/><origin xyz=\""
      << xyz(Lp * origin[l]) << "\" rpy=\"0.1 -0.2 0.3\"/>";
    if (std::string(type[l]) != "fixed") u << "<axis xyz=\"" << axis[l] << "\"/>";
    if (std::string(type[l]) == "revolute")
      u << "<limit lower=\"-3.14159\" upper=\"3.14159\" effort=\"1\" velocity=\"1\"/>";
    if (std::string(type[l]) == "prismatic")
      u << "<limit lower=\"" << -0.5 * L << "\" upper=\"" << 0.5 * L
        << "\" effort=\"1\" velocity=\"1\"/>";
    u << "</joint>\n";
  }
  u << "</robot>\n";
  return u.str();
}

// Random joint positions over their generic ranges, the platform tilted by up
// to `tilt_max` rad in any direction.
Samples random_plan(const Model& model, int n, double tilt_max, std::uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Samples s;
  s.source = "random plan";
  s.q.resize(n, model.num_joints());
  s.gravity.resize(n, 3);
  s.line.resize(n);
  for (int i = 0; i < n; ++i) {
    for (int j = 0; j < model.num_joints(); ++j)
      s.q(i, j) = model.joints[j].generic_position(u(rng));
    const double tilt = tilt_max * u(rng), az = 2 * 3.141592653589793 * u(rng);
    s.gravity.row(i) =
        -kStandardGravity * Eigen::Vector3d(std::sin(tilt) * std::cos(az),
                                            std::sin(tilt) * std::sin(az), std::cos(tilt));
    s.line[i] = i + 2;
  }
  return s;
}

// Offsets of the size of the wrench: total mass M and lever arm L.
Wrench scaled_offset(double M, double L) {
  const double f = M * kStandardGravity;
  return (Wrench() << 0.05 * f, -0.03 * f, 0.1 * f, 0.05 * f * L, -0.02 * f * L, 0.03 * f * L)
      .finished();
}

double max_length(const Scales& sc) {
  return *std::max_element(sc.length.begin(), sc.length.end());
}

struct Fixture {
  Model model;
  BaseParameters base;
  Eigen::VectorXd truth;
  Wrench offset = Wrench::Zero();
};

Fixture make(const Scales& sc, bool offset) {
  Fixture f{load_urdf_string(scaled_urdf(sc)), {}, {}, Wrench::Zero()};
  BaseParameterOptions bo;
  bo.offset = offset;
  f.base = find_base_parameters(f.model, bo);
  if (offset) f.offset = scaled_offset(f.model.nominal_total_mass(), max_length(sc));
  f.truth = test::true_values(f.model, f.base, f.offset);
  return f;
}

// max_i |value_i - truth_i| / |truth_i|
double max_relative_error(const Eigen::VectorXd& value, const Eigen::VectorXd& t) {
  return (value - t).cwiseAbs().cwiseQuotient(t.cwiseAbs()).maxCoeff();
}

const std::array<double, 3> kMasses{1e-3, 1.0, 1e3};
const std::array<double, 3> kLengths{1e-3, 0.1, 5.0};

// ------------------------------------------------------------ scales, noise-free

// Every base parameter to 1e-12 relative (measured: at most 1.1e-14 over the
// nine scales, with and without offsets), and the basis is the same at every
// scale: round-off stays relative.
TEST(NumericalRange, NoiseFreeRecoveryAtEveryMassAndLeverArmScale) {
  for (const bool offset : {false, true}) {
    const Fixture ref = make(uniform(1.0, 0.1), offset);
    for (const double m : kMasses)
      for (const double L : kLengths) {
        SCOPED_TRACE("mass " + std::to_string(m) + " kg, length " + std::to_string(L) + " m" +
                     (offset ? ", offsets" : ""));
        const Fixture f = make(uniform(m, L), offset);
        ASSERT_EQ(f.base.num_mass(), ref.base.num_mass());
        for (int i = 0; i < f.base.num_mass(); ++i) {
          EXPECT_EQ(f.base.params[i].name, ref.base.params[i].name);
          EXPECT_EQ(f.base.column[i], ref.base.column[i]) << f.base.params[i].name;
          // No base parameter is nearly zero: relative errors mean something.
          const double scale = f.base.params[i].unit == "kg" ? m : m * L;
          EXPECT_GT(std::abs(f.truth[i]), 1e-2 * scale) << f.base.params[i].name;
        }
        Samples s = random_plan(f.model, 200, 0.5, 7);
        SimulateOptions so;
        so.offset = f.offset;
        s.wrench = simulate_wrenches(f.model, s, so);
        const IdentifySummary r = identify(f.model, f.base, s);
        const double err = max_relative_error(r.value, f.truth);
        std::cout << "[ noise-free ] m " << m << " kg, L " << L << " m" << (offset ? " +offs" : "")
                  << ": max relative error " << err << ", cond " << r.condition_number << "\n";
        EXPECT_LT(err, 1e-12);
        for (int i = 0; i < f.base.num_unknowns(); ++i)
          EXPECT_LE(std::abs(r.value[i] - f.truth[i]), 1e-12 * std::abs(f.truth[i]))
              << f.base.unknown_name(i);
        // The eq. 36 condition number is of the moment rows, unscaled: it moves
        // with the lever arm only.
        EXPECT_GT(r.condition_number, 1.0);
      }
  }
}

// ------------------------------------------------------------ scales, noisy

// Noise proportional to the scale (1e-3 of the total weight, times the lever
// arm for moments): the errors over 40 seeds are as the std predict, and the
// relative std and relative errors are the same at every scale.
TEST(NumericalRange, NoisyRecoveryIsAsTheStdPredictAtEveryScale) {
  const int seeds = 40;
  Eigen::VectorXd ref_rel_std;
  for (const double m : kMasses)
    for (const double L : kLengths) {
      SCOPED_TRACE("mass " + std::to_string(m) + " kg, length " + std::to_string(L) + " m");
      const Fixture f = make(uniform(m, L), true);
      Samples s = random_plan(f.model, 200, 0.5, 8);
      const double M = f.model.nominal_total_mass();
      const int p = f.base.num_unknowns();
      Eigen::VectorXd sum_z2 = Eigen::VectorXd::Zero(p), rel_std;
      double worst_z = 0.0;
      for (int seed = 1; seed <= seeds; ++seed) {
        SimulateOptions so;
        so.offset = f.offset;
        so.noise_force = 1e-3 * M * kStandardGravity;
        so.noise_moment = so.noise_force * L;
        so.seed = seed;
        s.wrench = simulate_wrenches(f.model, s, so);
        const IdentifySummary r = identify(f.model, f.base, s);
        const Eigen::VectorXd z = (r.value - f.truth).cwiseQuotient(r.stddev);
        sum_z2 += z.cwiseAbs2();
        worst_z = std::max(worst_z, z.cwiseAbs().maxCoeff());
        if (seed == 1) rel_std = r.stddev.cwiseQuotient(f.truth.cwiseAbs());
      }
      const Eigen::VectorXd spread = (sum_z2 / seeds).cwiseSqrt();
      std::cout << "[ noisy ] m " << m << " kg, L " << L << " m: relative std "
                << rel_std.minCoeff() << " .. " << rel_std.maxCoeff() << ", error/std rms "
                << std::sqrt(sum_z2.sum() / (seeds * p)) << ", max " << worst_z << "\n";
      EXPECT_LT(worst_z, 5.0);
      for (int i = 0; i < p; ++i) {
        EXPECT_GT(spread[i], 0.6) << f.base.unknown_name(i);
        EXPECT_LT(spread[i], 1.45) << f.base.unknown_name(i);
      }
      // Scale invariance: the same relative std at every scale.
      if (ref_rel_std.size() == 0) ref_rel_std = rel_std;
      for (int i = 0; i < p; ++i)
        EXPECT_NEAR(rel_std[i], ref_rel_std[i], 1e-9 * ref_rel_std[i]) << f.base.unknown_name(i);
    }
}

// ------------------------------------------------------------ mixed scales

// One robot mixing 1 t links with 1 g links at 1 mm or 5 m, noise-free: the
// round-off is absolute, at most 1e-16 x the condition number of the largest
// parameter of the same unit (asserted with a margin of 10), so the light
// links' parameters (down to 1e-11 of the largest) lose as many digits
// (measured: 8e-10 relative for the 1 g tool at 5 m, 6e-6 for the 1 g, 1 mm
// one, 7e-15 for a 1 g sensor under the 1 t arm); the std (from the round-off
// residuals) still cover the errors.
TEST(NumericalRange, MixedScaleRobot) {
  struct Mixed {
    std::string name;
    Scales sc;
    double bound;  // asserted max relative error, 10 to 20 times the measured one
  };
  const std::vector<Mixed> robots{
      {"1 t arm with a 1 g tool at 5 m",
       {{1e3, 1e3, 1e3, 1e3, 1e-3, 1e-3}, {5.0, 5.0, 5.0, 5.0, 5.0, 5.0}},
       1e-8},
      {"1 t arm with a 1 g, 1 mm tool",
       {{1e3, 1e3, 1e3, 1e3, 1e-3, 1e-3}, {5.0, 5.0, 5.0, 5.0, 1e-3, 1e-3}},
       1e-4},
      {"1 g sensor and base under a 1 t arm",
       {{1e-3, 1e-3, 1e3, 1e3, 1e3, 1e3}, {1e-3, 1e-3, 5.0, 5.0, 5.0, 5.0}},
       1e-13},
  };
  for (const Mixed& mx : robots) {
    SCOPED_TRACE(mx.name);
    const Fixture f = make(mx.sc, false);
    Samples s = random_plan(f.model, 200, 0.5, 9);
    s.wrench = simulate_wrenches(f.model, s);
    const IdentifySummary r = identify(f.model, f.base, s);
    const Eigen::VectorXd rel = (r.value - f.truth).cwiseAbs().cwiseQuotient(f.truth.cwiseAbs());
    const Eigen::VectorXd z = (r.value - f.truth).cwiseQuotient(r.stddev);
    std::cout << "[ mixed ] " << mx.name << ": cond " << r.condition_number << "\n";
    for (int i = 0; i < f.base.num_mass(); ++i) {
      double largest = 0.0;  // of the parameters of the same unit
      for (int j = 0; j < f.base.num_mass(); ++j)
        if (f.base.params[j].unit == f.base.params[i].unit)
          largest = std::max(largest, std::abs(f.truth[j]));
      const double abs_err = std::abs(r.value[i] - f.truth[i]) / largest;
      EXPECT_LT(abs_err, 1e-15 * r.condition_number) << f.base.params[i].name;
      std::cout << "    " << f.base.params[i].name << " = " << f.truth[i] << "  rel err " << rel[i]
                << "  err/std " << z[i] << "  err/largest " << abs_err << "  ("
                << f.base.params[i].expression << ")\n";
      EXPECT_LT(rel[i], mx.bound) << f.base.params[i].name;
      EXPECT_LT(std::abs(z[i]), 5.0) << f.base.params[i].name;
    }
  }
}

// ------------------------------------------------------------ near-singular plans

// Either an IdentifiabilityError whose message contains every piece, or a
// result whose std cover the errors (|error| < 5 std for every unknown).
struct Outcome {
  bool threw = false;
  double cond = 0.0;
  double worst_z = 0.0;  // max |error| / std
  double worst_rel = 0.0;
  std::string message;  // of the IdentifiabilityError
};

Outcome identify_or_explain(const Fixture& f, const Samples& s,
                            const std::vector<std::string>& pieces) {
  Outcome o;
  try {
    const IdentifySummary r = identify(f.model, f.base, s);
    o.cond = r.condition_number;
    o.worst_z = (r.value - f.truth).cwiseQuotient(r.stddev).cwiseAbs().maxCoeff();
    o.worst_rel = max_relative_error(r.value, f.truth);
    for (int i = 0; i < f.base.num_unknowns(); ++i)
      EXPECT_LT(std::abs(r.value[i] - f.truth[i]), 5 * r.stddev[i])
          << f.base.unknown_name(i) << ": " << r.value[i] << " +- " << r.stddev[i] << ", truth "
          << f.truth[i] << ", condition number " << r.condition_number;
  } catch (const IdentifiabilityError& e) {
    o.threw = true;
    const std::string msg = e.what();
    o.message = msg;
    for (const std::string& p : pieces)
      EXPECT_NE(msg.find(p), std::string::npos) << "'" << p << "' in: " << msg;
  }
  return o;
}

void print(const std::string& what, double eps, bool noisy, const Outcome& o) {
  std::cout << "[ near-singular ] " << what << " " << eps << (noisy ? " noisy" : " noise-free")
            << ": "
            << (o.threw ? std::string("IdentifiabilityError")
                        : "cond " + std::to_string(o.cond) + ", max |err|/std " +
                              std::to_string(o.worst_z) + ", max rel err " +
                              std::to_string(o.worst_rel))
            << "\n";
  if (o.threw && eps == 0.0) std::cout << "    " << o.message << "\n";
}

const std::vector<double> kEps{1e-1, 1e-2, 1e-3, 1e-4,  1e-5,  1e-6,
                               1e-7, 1e-8, 1e-9, 1e-10, 1e-12, 0.0};

// Simulates the plan noise-free, then with noise (three seeds), and checks each.
// Returns whether the noisy runs threw, and the condition number seen.
Outcome check_plan(const Fixture& f, Samples s, const std::string& what, double eps,
                   const std::vector<std::string>& pieces) {
  SimulateOptions so;
  so.offset = f.offset;
  s.wrench = simulate_wrenches(f.model, s, so);
  print(what, eps, false, identify_or_explain(f, s, pieces));
  Outcome noisy;
  for (std::uint64_t seed = 1; seed <= 3; ++seed) {
    so.noise_force = 1e-3 * f.model.nominal_total_mass() * kStandardGravity;
    so.noise_moment = 0.1 * so.noise_force;
    so.seed = seed;
    s.wrench = simulate_wrenches(f.model, s, so);
    noisy = identify_or_explain(f, s, pieces);
    if (seed == 1) print(what, eps, true, noisy);
  }
  return noisy;
}

// Where it returns, the condition number grows as 1/eps at least.
void expect_condition_grows(const std::vector<Outcome>& out) {
  for (size_t k = 0; k < kEps.size(); ++k) {
    if (!out[k].threw) {
      EXPECT_GT(out[k].cond, 1e-2 / kEps[k]) << kEps[k];
    }
  }
}

// Gravity within eps of the sensor's z axis: the z first moments are seen
// through sin(eps) only.
TEST(NumericalRange, NearlyLevelPlans) {
  const Fixture f = make(uniform(1.0, 0.1), false);
  std::vector<Outcome> out;
  for (const double eps : kEps) {
    SCOPED_TRACE("tilt " + std::to_string(eps));
    Samples s = random_plan(f.model, 200, 0.0, 10);
    std::mt19937_64 rng(3);
    std::uniform_real_distribution<double> u(0.0, 2 * 3.141592653589793);
    for (int i = 0; i < s.size(); ++i) {
      const double az = u(rng);  // tilt exactly eps, any direction
      s.gravity.row(i) =
          -kStandardGravity * Eigen::Vector3d(std::sin(eps) * std::cos(az),
                                              std::sin(eps) * std::sin(az), std::cos(eps));
    }
    out.push_back(check_plan(f, s, "tilt", eps, {"tilt the platform"}));
  }
  EXPECT_FALSE(out.front().threw);
  EXPECT_TRUE(out.back().threw);
  expect_condition_grows(out);
}

// With offsets: the plan's gravity takes two directions (level, and tilted
// 0.4 rad about y) and, for a third of the samples, a third direction eps away
// from the second. Two directions cannot separate the moment offsets from the
// sensor's first moments.
TEST(NumericalRange, NearlyTwoGravityDirectionsWithOffsets) {
  const Fixture f = make(uniform(1.0, 0.1), true);
  std::vector<Outcome> out;
  for (const double eps : kEps) {
    SCOPED_TRACE("third direction " + std::to_string(eps));
    Samples s = random_plan(f.model, 300, 0.0, 11);
    for (int i = 0; i < s.size(); ++i) {
      const double ty = i % 3 == 0 ? 0.0 : 0.4, tx = i % 3 == 2 ? eps : 0.0;
      const Eigen::Matrix3d R = (Eigen::AngleAxisd(ty, Eigen::Vector3d::UnitY()) *
                                 Eigen::AngleAxisd(tx, Eigen::Vector3d::UnitX()))
                                    .toRotationMatrix();
      s.gravity.row(i) = (R * Eigen::Vector3d(0, 0, -kStandardGravity)).transpose();
    }
    out.push_back(check_plan(f, s, "third gravity direction", eps, {"offset_m"}));
  }
  EXPECT_FALSE(out.front().threw);
  EXPECT_TRUE(out.back().threw);
  expect_condition_grows(out);
}

// Gravity in one plane of the sensor frame (tilts about y only: 0, 0.2 and
// 0.4 rad) still determines the offsets: three distinct directions suffice,
// coplanar or not (the differences of three points of a circle span its plane).
TEST(NumericalRange, CoplanarGravityDirectionsDetermineTheOffsets) {
  const Fixture f = make(uniform(1.0, 0.1), true);
  Samples s = random_plan(f.model, 300, 0.0, 14);
  for (int i = 0; i < s.size(); ++i) {
    const double ty = 0.2 * (i % 3);
    s.gravity.row(i) =
        (Eigen::AngleAxisd(ty, Eigen::Vector3d::UnitY()) * Eigen::Vector3d(0, 0, -kStandardGravity))
            .transpose();
  }
  const Outcome o = check_plan(f, s, "coplanar gravity", 0.2, {});
  EXPECT_FALSE(o.threw) << o.message;
  EXPECT_LT(o.cond, 1e4);
}

// joint3 moves within +-eps of 0.7 rad (the others over their whole range):
// what only its motion separates is seen through eps.
TEST(NumericalRange, AJointThatHardlyMoves) {
  const Fixture f = make(uniform(1.0, 0.1), false);
  std::vector<Outcome> out;
  for (const double eps : kEps) {
    SCOPED_TRACE("range " + std::to_string(eps));
    Samples s = random_plan(f.model, 200, 0.5, 12);
    std::mt19937_64 rng(5);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int i = 0; i < s.size(); ++i) s.q(i, 2) = 0.7 + eps * u(rng);
    out.push_back(check_plan(f, s, "joint3 range", eps, {"joint3"}));
  }
  EXPECT_FALSE(out.front().threw);
  EXPECT_TRUE(out.back().threw);
  expect_condition_grows(out);
}

// ------------------------------------------------------------ a million samples

// 10^6 samples with offsets, streamed from memory: the truth within 5 std,
// the std shrinking as 1/sqrt(N) against a dense fit of every 50th sample
// (which agrees within the std of the difference); bit-identical results on
// 1, 2 and 4 threads. Noise-free, the million rows keep the round-off floor.
TEST(NumericalRange, AMillionSamples) {
  const Fixture f = make(uniform(1.0, 0.1), true);
  const int n = 1000000, every = 50;
  Samples s = random_plan(f.model, n, 0.5, 13);
  SimulateOptions so;
  so.offset = f.offset;
  s.wrench = simulate_wrenches(f.model, s, so);
  {
    StreamOptions st;
    st.threads = 2;
    const IdentifySummary r = identify_streaming(f.model, f.base, s, {}, st);
    const double err = max_relative_error(r.value, f.truth);
    std::cout << "[ million ] noise-free: max relative error " << err << "\n";
    EXPECT_LT(err, 1e-12);
  }
  so.noise_force = 0.05;
  so.noise_moment = 0.005;
  so.seed = 13;
  s.wrench = simulate_wrenches(f.model, s, so);

  std::vector<IdentifySummary> runs;
  for (const int threads : {1, 2, 4}) {
    StreamOptions st;
    st.threads = threads;
    runs.push_back(identify_streaming(f.model, f.base, s, {}, st));
  }
  const IdentifySummary& r = runs.front();
  EXPECT_EQ(r.samples, n);
  const auto same_bits = [](const Eigen::MatrixXd& a, const Eigen::MatrixXd& b) {
    return a.rows() == b.rows() && a.cols() == b.cols() &&
           std::memcmp(a.data(), b.data(), sizeof(double) * a.size()) == 0;
  };
  for (size_t k = 1; k < runs.size(); ++k) {
    EXPECT_TRUE(same_bits(r.value, runs[k].value)) << "threads run " << k;
    EXPECT_TRUE(same_bits(r.stddev, runs[k].stddev)) << "threads run " << k;
    EXPECT_TRUE(same_bits(r.covariance, runs[k].covariance)) << "threads run " << k;
    EXPECT_TRUE(same_bits(r.sigma, runs[k].sigma)) << "threads run " << k;
    EXPECT_EQ(std::memcmp(&r.condition_number, &runs[k].condition_number, sizeof(double)), 0);
    EXPECT_EQ(std::memcmp(&r.chi2_per_dof, &runs[k].chi2_per_dof, sizeof(double)), 0);
  }

  Samples sub;
  sub.source = "subsample";
  const int m = n / every;
  sub.q.resize(m, s.q.cols());
  sub.gravity.resize(m, 3);
  sub.wrench.resize(m, 6);
  for (int i = 0; i < m; ++i) {
    sub.q.row(i) = s.q.row(i * every);
    sub.gravity.row(i) = s.gravity.row(i * every);
    sub.wrench.row(i) = s.wrench.row(i * every);
    sub.line.push_back(i * every + 2);
  }
  const IdentifySummary d = identify(f.model, f.base, sub);
  const Eigen::VectorXd z = (r.value - f.truth).cwiseQuotient(r.stddev);
  std::cout << "[ million ] noisy: max |error|/std " << z.cwiseAbs().maxCoeff() << ", relative std "
            << r.stddev.cwiseQuotient(f.truth.cwiseAbs()).minCoeff() << " .. "
            << r.stddev.cwiseQuotient(f.truth.cwiseAbs()).maxCoeff() << ", chi2/dof "
            << r.chi2_per_dof << "\n";
  for (int i = 0; i < f.base.num_unknowns(); ++i) {
    const std::string name = f.base.unknown_name(i);
    EXPECT_LT(std::abs(z[i]), 5.0) << name;
    // std ~ 1/sqrt(N): the subsample's is sqrt(50) times larger.
    EXPECT_NEAR(d.stddev[i] / r.stddev[i], std::sqrt(double(every)), 0.1 * std::sqrt(every))
        << name;
    // The subsample is part of the whole: their difference has variance
    // var_sub - var_full.
    const double diff_std = std::sqrt(d.stddev[i] * d.stddev[i] - r.stddev[i] * r.stddev[i]);
    EXPECT_LT(std::abs(d.value[i] - r.value[i]), 5 * diff_std) << name;
  }
  EXPECT_NEAR(r.chi2_per_dof, 1.0, 0.01);
  EXPECT_NEAR(r.sigma[0], 0.05, 0.05 * 0.01);
  EXPECT_NEAR(r.sigma[5], 0.005, 0.005 * 0.01);
}

}  // namespace
}  // namespace massid
