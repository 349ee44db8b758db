// Physically consistent parameters (physical.hpp) from identified base
// parameters. Every check is made here from the returned ten parameters per
// link: the pseudo-inertia is built and eigen-decomposed in the test, the
// inertia about the centre of mass and its principal moments likewise, and
// the mismatch is K pi against the identified values and std.
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>

#include "massid/core/errors.hpp"
#include "massid/core/simulate.hpp"
#include "massid/design/excitation.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/identification.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/identify/params_json.hpp"
#include "massid/identify/physical.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/urdf.hpp"
#include "test_support.hpp"

namespace massid {
namespace {

using test::kLevel;

// One link's ten parameters as (m, h, I about the origin).
struct Body {
  double m;
  Eigen::Vector3d h;
  Eigen::Matrix3d I;
};
Body body_of(const Eigen::VectorXd& pi, int link) {
  const Eigen::VectorXd p = pi.segment(10 * link, 10);
  Body b;
  b.m = p[0];
  b.h = p.segment(1, 3);
  b.I << p[4], p[5], p[6], p[5], p[7], p[8], p[6], p[8], p[9];
  return b;
}

// The checks of a real body, independently of the library: m > 0, the
// pseudo-inertia [[1/2 tr(I) 1 - I, h], [h^T, m]] has no eigenvalue below
// -1e-12 of its scale, and the principal moments about the centre of mass
// satisfy the triangle inequalities.
void expect_consistent(const Model& model, const Eigen::VectorXd& pi) {
  ASSERT_EQ(pi.size(), 10 * model.num_links());
  for (int l = 0; l < model.num_links(); ++l) {
    SCOPED_TRACE(model.links[l].name);
    const Body b = body_of(pi, l);
    if (pi.segment<10>(10 * l).isZero(0.0)) continue;  // a massless frame (PhysicalLink::unseen)
    EXPECT_GT(b.m, 0.0);
    Eigen::Matrix4d J = Eigen::Matrix4d::Zero();
    J.topLeftCorner<3, 3>() = 0.5 * b.I.trace() * Eigen::Matrix3d::Identity() - b.I;
    J.block<3, 1>(0, 3) = b.h;
    J.block<1, 3>(3, 0) = b.h.transpose();
    J(3, 3) = b.m;
    const Eigen::Vector4d lambda = Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d>(J).eigenvalues();
    EXPECT_GE(lambda[0], -1e-12 * J.trace());
    const Eigen::Vector3d c = b.h / b.m;
    const Eigen::Matrix3d Ic =
        b.I - b.m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
    const Eigen::Vector3d d = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(Ic).eigenvalues();
    // Round-off of the parallel-axis subtraction: relative to I about the origin.
    const double tol = 1e-12 * (b.I.norm() + d.cwiseAbs().maxCoeff());
    EXPECT_GE(d[0], -tol);
    EXPECT_LE(d[2], d[0] + d[1] + tol);
  }
}

// The standard parameters in the base's layout (4 or 10 per link).
Eigen::VectorXd in_layout(const Model& model, const BaseParameters& base,
                          const Eigen::VectorXd& full) {
  const int per = base.layout.per_link();
  Eigen::VectorXd out(per * model.num_links());
  for (int l = 0; l < model.num_links(); ++l) out.segment(per * l, per) = full.segment(10 * l, per);
  return out;
}

// Largest |K pi - value| / std over the mass base parameters.
double worst_mismatch(const Model& model, const BaseParameters& base, const IdentifySummary& fit,
                      const Eigen::VectorXd& full) {
  const Eigen::VectorXd d = base.K * in_layout(model, base, full) - fit.value.head(base.num_mass());
  return d.cwiseQuotient(fit.stddev.head(base.num_mass())).cwiseAbs().maxCoeff();
}

struct MotionFit {
  Model model;
  BaseParameters base;
  IdentifySummary fit;
};

// ur_like on a level platform with an offset, simulated with noise.
MotionFit motion_fit(double duration, double rate, double noise, std::uint64_t seed,
                     const ExcitationLimits& limits = {}) {
  MotionFit out{load_urdf(test::examples()[1].urdf), {}, {}};
  const FourierTrajectory tr = random_fourier_trajectory(out.model, 5, 10.0, seed, limits);
  Samples s = sample_trajectory(tr, duration, rate, kLevel);
  SimulateOptions so;
  so.dynamic = true;
  so.noise_force = noise;
  so.noise_moment = noise / 10;
  so.seed = seed;
  so.offset << 2.0, -1.0, 3.0, 0.2, -0.1, 0.05;
  s.wrench = simulate_wrenches(out.model, s, so);
  out.base = find_base_parameters(out.model, motion_base_options(s, true));
  out.fit = identify(out.model, out.base, s);
  return out;
}

TEST(Physical, WellExcitedLogIsReproducedWithinItsStdByConsistentBodies) {
  const MotionFit f = motion_fit(20.0, 250.0, 0.1, 11);
  const PhysicalSummary p = fit_physical(f.model, f.base, f.fit);
  expect_consistent(f.model, p.standard);
  EXPECT_LT(worst_mismatch(f.model, f.base, f.fit, p.standard), 1.0);
  EXPECT_NEAR(std::abs(p.worst_mismatch), worst_mismatch(f.model, f.base, f.fit, p.standard), 1e-9);
  EXPECT_TRUE(p.consistent());
  EXPECT_FALSE(p.static_layout);
  ASSERT_EQ(p.links.size(), f.model.links.size());
  // The summary's per-link fields agree with the ten parameters.
  for (int l = 0; l < f.model.num_links(); ++l) {
    const Body b = body_of(p.standard, l);
    EXPECT_NEAR(p.links[l].mass, b.m, 1e-12 * b.m);
    if (b.m > 0) {
      EXPECT_LT((p.links[l].com - b.h / b.m).norm(), 1e-12);
    }
  }
  // The sensor link has no <inertial>: its prior is the tiny body, which the
  // data leave alone: a massless frame, all ten zero.
  EXPECT_TRUE(p.links[0].prior_body);
  EXPECT_TRUE(p.links[0].unseen);
  EXPECT_TRUE(p.standard.head<10>().isZero(0.0));
  EXPECT_FALSE(p.links[1].prior_body);
  EXPECT_FALSE(p.links[1].unseen);
}

// Directions the data cannot see keep the URDF's values: on a level platform
// with offsets, the links that never move (plate, base) show nothing (their
// K columns are zero), so all ten of theirs are the URDF's.
TEST(Physical, WhatTheDataCannotSeeKeepsTheUrdfsValues) {
  const MotionFit f = motion_fit(20.0, 250.0, 0.1, 11);
  const PhysicalSummary p = fit_physical(f.model, f.base, f.fit);
  const Eigen::VectorXd nominal = ParameterLayout::full().nominal(f.model);
  int unseen = 0;
  for (int l = 0; l < f.model.num_links(); ++l) {
    if (!f.model.links[l].has_inertial) continue;
    if (f.base.K.middleCols(10 * l, 10).cwiseAbs().maxCoeff() > 1e-12) continue;
    // The fixed child that took the massless sensor link's body (PhysicalLink::unseen).
    if (f.model.links[l].parent == 0 && p.links[0].unseen) continue;
    ++unseen;
    SCOPED_TRACE(f.model.links[l].name);
    const double m = nominal[10 * l];
    for (int k = 0; k < 10; ++k) EXPECT_NEAR(p.standard[10 * l + k], nominal[10 * l + k], 1e-6 * m);
  }
  EXPECT_GE(unseen, 1);  // base (the plate took the massless sensor link's body)
}

// A seen direction moved far from the URDF: the data wins over the prior.
TEST(Physical, TheDataOverridesThePriorWhereItSees) {
  MotionFit f = motion_fit(20.0, 250.0, 0.1, 11);
  const int tool = f.model.find_link("tool");
  const Eigen::VectorXd nominal = ParameterLayout::full().nominal(f.model);
  // The tool 0.3 kg heavier at its centre of mass (a consistent change).
  Eigen::VectorXd shift = Eigen::VectorXd::Zero(nominal.size());
  const Eigen::Vector3d c = f.model.links[tool].com;
  shift.segment(10 * tool, 10) << 0.3, 0.3 * c, 0.3 * (c.squaredNorm() - c.x() * c.x()),
      -0.3 * c.x() * c.y(), -0.3 * c.x() * c.z(), 0.3 * (c.squaredNorm() - c.y() * c.y()),
      -0.3 * c.y() * c.z(), 0.3 * (c.squaredNorm() - c.z() * c.z());
  f.fit.value.head(f.base.num_mass()) += f.base.K * shift;
  const PhysicalSummary p = fit_physical(f.model, f.base, f.fit);
  expect_consistent(f.model, p.standard);
  EXPECT_LT(worst_mismatch(f.model, f.base, f.fit, p.standard), 1.0);
}

// Noise far beyond the sensor's on a short log where the shoulder hardly
// moves: the unconstrained estimate is no body at all, the result still is.
TEST(Physical, NoisyShortPoorlyExcitingLogStillGivesRealBodies) {
  ExcitationLimits limits;
  limits.joint_acceleration.assign(6, 0.0);
  limits.joint_acceleration[0] = 0.01;
  const MotionFit f = motion_fit(3.0, 200.0, 20.0, 5, limits);
  const PhysicalSummary p = fit_physical(f.model, f.base, f.fit);
  expect_consistent(f.model, p.standard);
  EXPECT_TRUE(p.consistent());
}

// An estimate a thousand std off in every base parameter (an overconfident
// fit of bad data): no real bodies reproduce it; the result is real bodies
// still, and its mismatch says how far it had to go.
TEST(Physical, ImplausibleEstimateGivesRealBodiesAndSaysHowFar) {
  MotionFit f = motion_fit(20.0, 250.0, 0.1, 11);
  std::mt19937_64 rng(3);
  std::normal_distribution<double> n01;
  for (int i = 0; i < f.base.num_mass(); ++i) f.fit.value[i] += 1e3 * f.fit.stddev[i] * n01(rng);
  const PhysicalSummary p = fit_physical(f.model, f.base, f.fit);
  expect_consistent(f.model, p.standard);
  EXPECT_GT(std::abs(p.worst_mismatch), 1.0);
  EXPECT_TRUE(p.consistent());
}

// Static identification: masses > 0 and first moments reproducing the
// static base parameters; the inertia about each centre of mass is the URDF's.
TEST(Physical, StaticLayoutGivesMassesAndCentresOfMass) {
  const test::Example ex = test::examples()[0];  // puma260
  const Model model = load_urdf(ex.urdf);
  Samples s = test::load_plan(model, ex.plan);
  SimulateOptions so;
  so.noise_force = 0.05;
  so.noise_moment = 0.005;
  so.seed = 4;
  s.wrench = simulate_wrenches(model, s, so);
  const BaseParameters base = find_base_parameters(model);
  const IdentifySummary fit = identify(model, base, s);
  const PhysicalSummary p = fit_physical(model, base, fit);
  EXPECT_TRUE(p.static_layout);
  expect_consistent(model, p.standard);
  EXPECT_LT(worst_mismatch(model, base, fit, p.standard), 1.0);
  for (int l = 0; l < model.num_links(); ++l) {
    if (!model.links[l].has_inertial || !(model.links[l].mass > 0)) continue;
    // The fixed child that took the massless sensor link's body (PhysicalLink::unseen).
    if (model.links[l].parent == 0 && p.links[0].unseen) continue;
    SCOPED_TRACE(model.links[l].name);
    const Body b = body_of(p.standard, l);
    const Eigen::Vector3d c = b.h / b.m;
    const Eigen::Matrix3d Ic =
        b.I - b.m * (c.squaredNorm() * Eigen::Matrix3d::Identity() - c * c.transpose());
    EXPECT_LT((Ic - model.links[l].inertia).norm(), 1e-6 * model.links[l].inertia.norm() + 1e-12);
  }
}

// A static estimate with a negative total mass: every mass still positive.
TEST(Physical, StaticNegativeTotalMassStillGivesPositiveMasses) {
  const test::Example ex = test::examples()[0];
  const Model model = load_urdf(ex.urdf);
  Samples s = test::load_plan(model, ex.plan);
  s.wrench = simulate_wrenches(model, s, {});
  const BaseParameters base = find_base_parameters(model);
  IdentifySummary fit = identify(model, base, s, [] {
    IdentifyOptions o;
    o.sigma_force = 0.05;
    o.sigma_moment = 0.005;
    return o;
  }());
  ASSERT_GE(base.total_mass, 0);
  fit.value[base.total_mass] = -1.0;
  const PhysicalSummary p = fit_physical(model, base, fit);
  expect_consistent(model, p.standard);
  for (const PhysicalLink& l : p.links)
    if (!l.unseen) {
      EXPECT_GT(l.mass, 0.0);  // a massless frame's body is its neighbour's
    }
  EXPECT_EQ(p.worst, base.total_mass);
}

// The params file's "physical" section read back: the same ten parameters per
// link, and K pi_phys as the values a prediction uses (the offsets the file's).
TEST(Physical, ParamsFileAndRecordRoundTrip) {
  const MotionFit f = motion_fit(20.0, 250.0, 0.1, 11);
  const PhysicalSummary p = fit_physical(f.model, f.base, f.fit);
  const std::filesystem::path dir = std::filesystem::temp_directory_path();
  const std::string params = (dir / "massid_test_physical_params.json").string();
  std::ofstream(params) << params_json(f.model, f.base, &f.fit, &p);
  const ParamsFile file = read_params(params);
  ASSERT_EQ(file.physical.size(), f.model.links.size());
  for (const ParamsFile::PhysicalEntry& e : file.physical) {
    const int l = f.model.find_link(e.link);
    ASSERT_GE(l, 0) << e.link;
    EXPECT_EQ(e.params, p.standard.segment<10>(10 * l)) << e.link;
  }
  const Eigen::VectorXd v = physical_values_in_basis(file, f.model, f.base);
  const Eigen::VectorXd pi = in_layout(f.model, f.base, p.standard);
  for (int i = 0; i < f.base.num_mass(); ++i)
    EXPECT_NEAR(v[i], f.base.K.row(i).dot(pi), 1e-9 * (1 + std::abs(v[i])));
  EXPECT_LT((v.tail(6) - f.fit.value.tail(6)).norm(), 1e-9);
  // Without the section: an InputError naming it.
  std::ofstream(params) << params_json(f.model, f.base, &f.fit);
  EXPECT_THROW(physical_values_in_basis(read_params(params), f.model, f.base), InputError);
  std::filesystem::remove(params);

  // The identification record (identify --report) carries it bit for bit.
  Identification ident;
  ident.model = f.model;
  ident.base = f.base;
  ident.summary = f.fit;
  ident.physical = p;
  const std::string record = (dir / "massid_test_physical.cbor").string();
  write_identification(record, ident);
  const Identification back = read_identification(record);
  std::filesystem::remove(record);
  ASSERT_TRUE(back.physical.has_value());
  EXPECT_EQ(back.physical->standard, p.standard);
  EXPECT_EQ(back.physical->mismatch, p.mismatch);
  EXPECT_EQ(back.physical->links.size(), p.links.size());
  EXPECT_EQ(back.physical->links[0].prior_body, p.links[0].prior_body);
  EXPECT_EQ(back.physical->iterations, p.iterations);
}

TEST(Physical, SummaryOfAnotherModelIsAnInputError) {
  const MotionFit f = motion_fit(20.0, 250.0, 0.1, 11);
  IdentifySummary wrong = f.fit;
  wrong.value.conservativeResize(3);
  EXPECT_THROW(fit_physical(f.model, f.base, wrong), InputError);
}

}  // namespace
}  // namespace massid
