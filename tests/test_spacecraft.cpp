// The spacecraft admittance model against closed-form rigid-body motion:
// conservation laws when free, Newton's and Euler's laws under a wrench at the
// interface, the compliant base's natural frequency and decay, and RK4's order.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <vector>

#include "massid/core/errors.hpp"
#include "massid/emulator/spacecraft.hpp"

namespace massid::emulator {
namespace {

Eigen::Matrix3d rotation(double angle, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(angle, axis.normalized()).toRotationMatrix();
}

// Asymmetric inertia, not aligned with the body axes.
Eigen::Matrix3d tumbling_inertia() {
  const Eigen::Matrix3d r = rotation(0.7, Eigen::Vector3d(1.0, -2.0, 0.5));
  return r * Eigen::Vector3d(1.1, 2.3, 3.0).asDiagonal() * r.transpose();
}

SpacecraftParameters tumbling_parameters() {
  SpacecraftParameters p;
  p.mass = 12.5;
  p.inertia = tumbling_inertia();
  p.body_T_interface.linear() = rotation(0.9, Eigen::Vector3d(0.3, 1.0, -0.4));
  p.body_T_interface.translation() = Eigen::Vector3d(0.25, -0.1, 0.4);
  return p;
}

SpacecraftState tumbling_state() {
  SpacecraftState s;
  s.position = Eigen::Vector3d(1.0, -2.0, 0.5);
  s.orientation = Eigen::Quaterniond(rotation(0.4, Eigen::Vector3d(-1.0, 0.2, 0.8)));
  s.linear_velocity = Eigen::Vector3d(0.1, -0.2, 0.3);
  s.angular_velocity = Eigen::Vector3d(0.5, 1.2, -0.3);  // near the intermediate axis
  return s;
}

Wrench wrench(const Eigen::Vector3d& f, const Eigen::Vector3d& m) {
  Wrench w;
  w << f, m;
  return w;
}

double distance(const SpacecraftState& a, const SpacecraftState& b) {
  const double dq = std::min((a.orientation.coeffs() - b.orientation.coeffs()).norm(),
                             (a.orientation.coeffs() + b.orientation.coeffs()).norm());
  return (a.position - b.position).norm() + dq + (a.linear_velocity - b.linear_velocity).norm() +
         (a.angular_velocity - b.angular_velocity).norm();
}

SpacecraftState simulate(const SpacecraftParameters& p, SpacecraftState s, const Wrench& w,
                         double duration, double dt) {
  const long n = std::lround(duration / dt);
  for (long k = 0; k < n; ++k) step(p, s, w, dt);
  return s;
}

TEST(Spacecraft, ValidateAcceptsAPhysicalBodyAndRejectsTheRest) {
  EXPECT_NO_THROW(validate(tumbling_parameters()));
  SpacecraftParameters p = tumbling_parameters();
  p.mass = 0.0;
  EXPECT_THROW(validate(p), InputError);
  p = tumbling_parameters();
  p.inertia(0, 1) += 0.1;
  EXPECT_THROW(validate(p), InputError);
  p = tumbling_parameters();
  p.inertia = Eigen::Vector3d(1.0, 1.0, 3.0).asDiagonal();  // 1 + 1 < 3
  EXPECT_THROW(validate(p), InputError);
  p = tumbling_parameters();
  p.inertia = Eigen::Vector3d(1.0, -1.0, 1.0).asDiagonal();
  EXPECT_THROW(validate(p), InputError);
  p = tumbling_parameters();
  p.stiffness(2, 2) = std::nan("");
  EXPECT_THROW(validate(p), InputError);
}

TEST(Spacecraft, StateAtRestPutsTheInterfaceWhereAsked) {
  const SpacecraftParameters p = tumbling_parameters();
  Eigen::Isometry3d world_T_interface = Eigen::Isometry3d::Identity();
  world_T_interface.linear() = rotation(2.0, Eigen::Vector3d(1.0, 1.0, 0.0));
  world_T_interface.translation() = Eigen::Vector3d(0.3, 0.2, 1.1);
  const SpacecraftState s = state_at_rest(p, world_T_interface);
  EXPECT_LT((interface_pose(p, s).matrix() - world_T_interface.matrix()).norm(), 1e-14);
  EXPECT_EQ(interface_twist(p, s), Twist::Zero());
  EXPECT_EQ(compliance_wrench(p, s), Wrench::Zero());
}

TEST(Spacecraft, InterfaceTwistIsTheDerivativeOfTheInterfacePose) {
  const SpacecraftParameters p = tumbling_parameters();
  const SpacecraftState s0 = tumbling_state();
  const double h = 1e-6;
  SpacecraftState sp = s0, sm = s0;
  step(p, sp, Wrench::Zero(), h);
  step(p, sm, Wrench::Zero(), -h);
  const Eigen::Isometry3d tp = interface_pose(p, sp), tm = interface_pose(p, sm);
  const Twist twist = interface_twist(p, s0);
  const Eigen::Vector3d v = (tp.translation() - tm.translation()) / (2 * h);
  const Eigen::Matrix3d dr = (tp.linear() - tm.linear()) / (2 * h);
  const Eigen::Matrix3d skew = dr * interface_pose(p, s0).linear().transpose();
  const Eigen::Vector3d w(skew(2, 1), skew(0, 2), skew(1, 0));
  EXPECT_LT((v - twist.head<3>()).norm(), 1e-8);
  EXPECT_LT((w - twist.tail<3>()).norm(), 1e-8);
}

// (1) Free floating: constant com velocity; momentum and energy conserved while
// the asymmetric body tumbles (w x I w at work).
TEST(Spacecraft, FreeFloatingConservesMomentumAndEnergy) {
  const SpacecraftParameters p = tumbling_parameters();
  const SpacecraftState s0 = tumbling_state();
  const Eigen::Vector3d p0 = linear_momentum(p, s0);
  const Eigen::Vector3d h0 = angular_momentum(p, s0);
  const Eigen::Vector3d h0_origin = angular_momentum(p, s0, Eigen::Vector3d::Zero());
  const double e0 = kinetic_energy(p, s0);
  SpacecraftState s = s0;
  const double dt = 1e-3;
  double max_dw = 0.0;
  for (int k = 1; k <= 10000; ++k) {
    step(p, s, Wrench::Zero(), dt);
    max_dw = std::max(max_dw, (s.angular_velocity - s0.angular_velocity).norm());
    if (k % 500 != 0) continue;
    const double t = k * dt;
    ASSERT_LT((s.position - (s0.position + t * s0.linear_velocity)).norm(), 1e-9) << t;
    ASSERT_LT((linear_momentum(p, s) - p0).norm(), 1e-9) << t;
    ASSERT_LT((angular_momentum(p, s) - h0).norm(), 1e-9) << t;
    ASSERT_LT((angular_momentum(p, s, Eigen::Vector3d::Zero()) - h0_origin).norm(), 1e-9) << t;
    ASSERT_LT(std::abs(kinetic_energy(p, s) - e0), 1e-9) << t;
    ASSERT_NEAR(s.orientation.norm(), 1.0, 1e-15);
  }
  EXPECT_GT(max_dw, 0.5);  // the body really tumbled
}

// (2) A constant force whose line of action passes through the com: pure
// translation, c(t) = c0 + 1/2 F/m t^2.
TEST(Spacecraft, ForceThroughTheComTranslates) {
  const SpacecraftParameters p = tumbling_parameters();
  SpacecraftState s0 = tumbling_state();
  s0.linear_velocity.setZero();
  s0.angular_velocity.setZero();
  // Along r (the com as seen from the interface), in the interface frame.
  const Eigen::Vector3d r = p.body_T_interface.translation();
  const Eigen::Vector3d f = -7.0 * (p.body_T_interface.linear().transpose() * r.normalized());
  const Eigen::Vector3d force_world =
      s0.orientation.toRotationMatrix() * p.body_T_interface.linear() * f;
  SpacecraftState s = s0;
  const double dt = 1e-3;
  for (int k = 1; k <= 2000; ++k) {
    step(p, s, wrench(f, Eigen::Vector3d::Zero()), dt);
    const double t = k * dt;
    ASSERT_LT((s.position - (s0.position + 0.5 * force_world / p.mass * t * t)).norm(), 1e-9) << t;
    ASSERT_LT((s.linear_velocity - force_world / p.mass * t).norm(), 1e-9) << t;
    ASSERT_LT(s.angular_velocity.norm(), 1e-12) << t;
  }
}

// (3) A force at the offset interface: angular acceleration I^-1 (r x f).
TEST(Spacecraft, OffsetForceProducesTheMomentArm) {
  const SpacecraftParameters p = tumbling_parameters();
  SpacecraftState s0 = tumbling_state();
  s0.angular_velocity.setZero();
  const Eigen::Vector3d f(3.0, -1.0, 2.0);  // interface frame
  const Eigen::Matrix3d r_bi = p.body_T_interface.linear();
  const Eigen::Vector3d r = p.body_T_interface.translation();
  const Eigen::Vector3d alpha = p.inertia.inverse() * r.cross(r_bi * f);
  const Eigen::Vector3d accel = s0.orientation.toRotationMatrix() * r_bi * f / p.mass;
  const double h = 1e-6;
  SpacecraftState s = s0;
  step(p, s, wrench(f, Eigen::Vector3d::Zero()), h);
  EXPECT_LT(((s.angular_velocity - s0.angular_velocity) / h - alpha).norm(), 1e-8 * alpha.norm());
  EXPECT_LT(((s.linear_velocity - s0.linear_velocity) / h - accel).norm(), 1e-8 * accel.norm());
  EXPECT_GT(alpha.norm(), 0.1);

  // acceleration() is the same Newton-Euler, with the gyroscopic term.
  const SpacecraftAcceleration a0 = acceleration(p, s0, wrench(f, Eigen::Vector3d::Zero()));
  EXPECT_LT((a0.angular - alpha).norm(), 1e-14);
  EXPECT_LT((a0.linear - accel).norm(), 1e-14);
  const SpacecraftState s1 = tumbling_state();
  const Eigen::Vector3d m(0.2, 0.1, -0.5);
  const Eigen::Vector3d& w = s1.angular_velocity;
  const SpacecraftAcceleration a1 = acceleration(p, s1, wrench(f, m));
  const Eigen::Vector3d alpha1 =
      p.inertia.inverse() * (r.cross(r_bi * f) + r_bi * m - w.cross(p.inertia * w));
  EXPECT_LT((a1.angular - alpha1).norm(), 1e-13);
}

// (4) A pure moment changes the angular momentum by moment x time and leaves
// the com at rest.
TEST(Spacecraft, MomentImpulseChangesAngularMomentum) {
  // About a principal axis from rest: the moment keeps its world direction.
  SpacecraftParameters p = tumbling_parameters();
  const Eigen::Matrix3d principal = rotation(0.7, Eigen::Vector3d(1.0, -2.0, 0.5));
  const Eigen::Vector3d m =
      p.body_T_interface.linear().transpose() * (1.5 * principal.col(1));  // interface frame
  SpacecraftState s0 = tumbling_state();
  s0.linear_velocity.setZero();
  s0.angular_velocity.setZero();
  const Eigen::Vector3d moment_world =
      s0.orientation.toRotationMatrix() * p.body_T_interface.linear() * m;
  SpacecraftState s = s0;
  const double dt = 1e-3;
  for (int k = 1; k <= 3000; ++k) {
    step(p, s, wrench(Eigen::Vector3d::Zero(), m), dt);
    const double t = k * dt;
    ASSERT_LT((angular_momentum(p, s) - moment_world * t).norm(), 1e-9) << t;
    ASSERT_LT((s.position - s0.position).norm(), 1e-15) << t;
    ASSERT_LT(linear_momentum(p, s).norm(), 1e-15) << t;
  }
  EXPECT_GT(s.angular_velocity.norm(), 1.0);

  // A short impulse in a generic direction, then free tumbling.
  const Eigen::Vector3d m2(0.6, -0.8, 0.4);
  SpacecraftState s2 = s0;
  const Eigen::Vector3d impulse_world =
      s0.orientation.toRotationMatrix() * p.body_T_interface.linear() * m2 * 1e-3;
  s2 = simulate(p, s2, wrench(Eigen::Vector3d::Zero(), m2), 1e-3, 1e-4);
  EXPECT_LT((angular_momentum(p, s2) - impulse_world).norm(), 1e-9);
  const Eigen::Vector3d after = angular_momentum(p, s2);
  s2 = simulate(p, s2, Wrench::Zero(), 5.0, 1e-3);
  EXPECT_LT((angular_momentum(p, s2) - after).norm(), 1e-15);
}

// Zero crossings (upwards) of samples x[k] taken every dt, linearly interpolated.
std::vector<double> upward_crossings(const std::vector<double>& x, double dt) {
  std::vector<double> t;
  for (std::size_t k = 1; k < x.size(); ++k)
    if (x[k - 1] < 0.0 && x[k] >= 0.0)
      t.push_back(dt * (static_cast<double>(k) - x[k] / (x[k] - x[k - 1])));
  return t;
}

double mean_period(const std::vector<double>& crossings) {
  return (crossings.back() - crossings.front()) / static_cast<double>(crossings.size() - 1);
}

// (5) Compliant base: a small displacement oscillates at sqrt(k/m) (and
// sqrt(k_r/I) in rotation), and damping makes it decay.
TEST(Spacecraft, CompliantBaseOscillatesAndDecays) {
  SpacecraftParameters p;
  p.mass = 50.0;
  p.inertia = Eigen::Vector3d(2.0, 3.0, 4.0).asDiagonal();
  p.body_T_interface.linear() = Eigen::Matrix3d::Identity();
  p.body_T_interface.translation().setZero();
  const double k = 2000.0, kr = 30.0;
  p.stiffness.diagonal() << k, k, k, kr, kr, kr;
  p.world_T_anchor.linear() = rotation(0.5, Eigen::Vector3d(0.0, 1.0, 1.0));
  p.world_T_anchor.translation() = Eigen::Vector3d(0.4, -0.3, 1.2);
  ASSERT_NO_THROW(validate(p));

  SpacecraftState rest = state_at_rest(p, p.world_T_anchor);
  EXPECT_LT(compliance_wrench(p, rest).norm(), 1e-12);
  SpacecraftState s0 = rest;
  s0.position += 1e-3 * p.world_T_anchor.linear().col(0);  // along the anchor's x
  s0.orientation = s0.orientation * Eigen::Quaterniond(rotation(1e-3, Eigen::Vector3d::UnitZ()));
  s0.orientation.normalize();

  const double dt = 1e-3;
  const auto run = [&](const SpacecraftParameters& params, std::vector<double>& x,
                       std::vector<double>& angle, std::vector<double>& energy) {
    SpacecraftState s = s0;
    for (int i = 0; i < 10000; ++i) {
      const Eigen::Isometry3d a_T_i = params.world_T_anchor.inverse() * interface_pose(params, s);
      x.push_back(a_T_i.translation().x());
      angle.push_back(Eigen::AngleAxisd(a_T_i.linear()).angle() *
                      Eigen::AngleAxisd(a_T_i.linear()).axis().z());
      energy.push_back(kinetic_energy(params, s) + 0.5 * k * a_T_i.translation().squaredNorm() +
                       0.5 * kr * angle.back() * angle.back());
      step(params, s, Wrench::Zero(), dt);
    }
  };

  // Undamped.
  std::vector<double> x, angle, energy;
  run(p, x, angle, energy);
  const double period = 2 * std::numbers::pi * std::sqrt(p.mass / k);
  const double period_r = 2 * std::numbers::pi * std::sqrt(p.inertia(2, 2) / kr);
  const std::vector<double> cx = upward_crossings(x, dt), ca = upward_crossings(angle, dt);
  ASSERT_GE(cx.size(), 5u);
  ASSERT_GE(ca.size(), 3u);
  EXPECT_NEAR(mean_period(cx), period, 0.01 * period);
  EXPECT_NEAR(mean_period(ca), period_r, 0.01 * period_r);
  EXPECT_NEAR(*std::max_element(x.begin(), x.end()), 1e-3, 1e-6);
  for (double e : energy) EXPECT_NEAR(e, energy.front(), 1e-6 * energy.front());

  // Damped: zeta = 0.05 in translation and rotation.
  const double zeta = 0.05;
  SpacecraftParameters pd = p;
  pd.damping.diagonal() << 2 * zeta * std::sqrt(k * p.mass) * Eigen::Vector3d::Ones(),
      2 * zeta * std::sqrt(kr * p.inertia(0, 0)), 2 * zeta * std::sqrt(kr * p.inertia(1, 1)),
      2 * zeta * std::sqrt(kr * p.inertia(2, 2));
  std::vector<double> xd, angled, energyd;
  run(pd, xd, angled, energyd);
  const std::vector<double> cxd = upward_crossings(xd, dt);
  ASSERT_GE(cxd.size(), 5u);
  const double damped_period = period / std::sqrt(1 - zeta * zeta);
  EXPECT_NEAR(mean_period(cxd), damped_period, 0.01 * damped_period);
  // Peak-to-peak decay over one damped period: exp(-2 pi zeta / sqrt(1 - zeta^2)).
  const double expected_ratio = std::exp(-2 * std::numbers::pi * zeta / std::sqrt(1 - zeta * zeta));
  const auto peak = [&](double t0) {  // max of xd over one period starting at t0
    double best = -1.0;
    const auto i0 = static_cast<std::size_t>(t0 / dt);
    for (std::size_t i = i0; i < i0 + static_cast<std::size_t>(damped_period / dt); ++i)
      best = std::max(best, xd[i]);
    return best;
  };
  EXPECT_NEAR(peak(cxd[1]) / peak(cxd[0]), expected_ratio, 0.01 * expected_ratio);
  for (std::size_t i = 1; i < energyd.size(); ++i)
    ASSERT_LE(energyd[i], energyd[i - 1] * (1 + 1e-12));
  EXPECT_LT(energyd.back(), 0.05 * energyd.front());
  // Rotation: the envelope 1e-3 exp(-zeta w_r t) bounds the last damped period's peak.
  const double rate_r = zeta * 2 * std::numbers::pi / period_r;
  const double period_rd = period_r / std::sqrt(1 - zeta * zeta);
  const double t_end = dt * static_cast<double>(angled.size() - 1);
  double last_peak = 0.0;
  for (auto i = static_cast<std::size_t>((t_end - period_rd) / dt); i < angled.size(); ++i)
    last_peak = std::max(last_peak, std::abs(angled[i]));
  EXPECT_GT(last_peak, 0.99e-3 * std::exp(-rate_r * t_end));
  EXPECT_LT(last_peak, 1.01e-3 * std::exp(-rate_r * (t_end - period_rd)));
  EXPECT_LT(last_peak, 0.4e-3);
}

// (6) RK4 is fourth order: halving dt divides the error by ~16.
TEST(Spacecraft, Rk4ConvergesAtFourthOrder) {
  SpacecraftParameters p = tumbling_parameters();
  SpacecraftState s0 = tumbling_state();
  s0.angular_velocity *= 2.5;  // fast tumbling
  const Wrench w = wrench(Eigen::Vector3d(3.0, -1.0, 2.0), Eigen::Vector3d(0.4, 0.2, -0.6));
  const double duration = 1.0;
  const SpacecraftState reference = simulate(p, s0, w, duration, 1e-4);
  std::vector<double> errors;
  for (double dt : {0.02, 0.01, 0.005})
    errors.push_back(distance(simulate(p, s0, w, duration, dt), reference));
  for (std::size_t i = 1; i < errors.size(); ++i) {
    const double ratio = errors[i - 1] / errors[i];
    EXPECT_GT(ratio, 13.0) << i;
    EXPECT_LT(ratio, 19.0) << i;
  }
  EXPECT_GT(errors.back(), 1e-10);  // well above round-off
  std::ostringstream text;
  text << std::scientific << errors[0] << ' ' << errors[1] << ' ' << errors[2];
  ::testing::Test::RecordProperty("rk4_errors", text.str());
}

}  // namespace
}  // namespace massid::emulator
