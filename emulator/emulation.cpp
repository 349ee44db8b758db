#include "massid/emulator/emulation.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <future>
#include <numbers>

namespace massid::emulator {

namespace {

double angle_deg(const Eigen::Matrix3d& a, const Eigen::Matrix3d& b) {
  return Eigen::AngleAxisd(a.transpose() * b).angle() * 180 / std::numbers::pi;
}

// The free-floating reference's interface pose after each tick. It does not
// depend on the emulation, so it runs on its own thread beside the plant.
std::vector<Eigen::Isometry3d> run_reference(FreeFloatingReference& reference,
                                             const JointTrajectory& trajectory, int joints,
                                             int ticks, double dt) {
  std::vector<Eigen::Isometry3d> poses(static_cast<std::size_t>(ticks));
  Eigen::VectorXd q(joints), qd(joints), qdd(joints);
  for (int k = 0; k < ticks; ++k) {
    trajectory(k * dt, q, qd, qdd);
    reference.set_joint_command(q, qd, qdd);
    reference.advance(dt);
    poses[static_cast<std::size_t>(k)] = reference.interface_pose();
  }
  return poses;
}

// What the emulation and the reference alone share: the plants' options, the
// interface's pose at the start, the joint trajectory and the tick count.
struct RunSetup {
  PlantOptions plant;
  Eigen::Isometry3d interface0;
  JointTrajectory trajectory;
  int ticks = 0;

  RunSetup(const Model& model, const EmulationOptions& o)
      : plant(o.plant),
        interface0(o.geometry.home * o.platform_T_sensor),
        trajectory(o.trajectory ? o.trajectory : smooth_maneuver(model, o.duration)),
        ticks(static_cast<int>(std::lround(o.duration * o.rate))) {
    plant.platform_T_sensor = o.platform_T_sensor;
  }
  // The joint positions at t = 0.
  Eigen::VectorXd start(int joints) const {
    Eigen::VectorXd q(joints), qd(joints), qdd(joints);
    trajectory(0.0, q, qd, qdd);
    return q;
  }
};

// How far the reference's interface poses get from the start.
Excursion excursion_of(const std::vector<Eigen::Isometry3d>& poses,
                       const Eigen::Isometry3d& interface0) {
  Excursion e;
  for (const Eigen::Isometry3d& pose : poses) {
    e.position_m = std::max(e.position_m, (pose.translation() - interface0.translation()).norm());
    e.angle_rad = std::max(
        e.angle_rad, Eigen::AngleAxisd(interface0.linear().transpose() * pose.linear()).angle());
  }
  return e;
}

}  // namespace

EmulationSummary run_emulation(const Model& model, const IdentifiedModel& identified,
                               const EmulationOptions& o, bool compensate,
                               std::vector<TraceRow>* trace) {
  const auto start = std::chrono::steady_clock::now();
  EmulatorModel em;
  em.identified = identified;
  em.spacecraft = o.spacecraft;
  em.geometry = o.geometry;
  em.platform_T_sensor = o.platform_T_sensor;
  em.gravity_world = o.plant.gravity;
  em.dt = 1.0 / o.rate;
  em.supervisor = o.supervisor;
  em.compensate_gravity = compensate;
  EmulatorData data(em);

  // Both MuJoCo models are compiled here, on one thread.
  const RunSetup setup(model, o);
  PlatformPlant plant(model, o.geometry, setup.plant);
  FreeFloatingReference reference(model, o.spacecraft, setup.interface0, setup.plant);
  const JointTrajectory& trajectory = setup.trajectory;
  const int n = model.num_joints(), ticks = setup.ticks;
  Eigen::VectorXd q = setup.start(n), qd(n), qdd(n);
  plant.set_joints(q);
  reference.set_joints(q);
  std::future<std::vector<Eigen::Isometry3d>> reference_poses =
      std::async(std::launch::async, run_reference, std::ref(reference), std::cref(trajectory), n,
                 ticks, em.dt);

  if (compensate && o.tare)
    tare(em, data, plant.measured_wrench(), plant.joint_positions(), plant.platform_pose());

  EmulationSummary s;
  double step_seconds = 0.0;
  std::vector<Eigen::Isometry3d> emulated(static_cast<std::size_t>(ticks));
  SupervisorState previous = SupervisorState::Running;
  for (int k = 0; k < ticks; ++k) {
    const double t = k * em.dt;
    trajectory(t, q, qd, qdd);
    plant.set_joint_command(q, qd, qdd);
    const Wrench measured = plant.measured_wrench();
    const auto t0 = std::chrono::steady_clock::now();
    control_step(em, data, measured, plant.joint_positions(), plant.platform_pose());
    step_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (data.state != SupervisorState::Running && previous == SupervisorState::Running) {
      if (s.supervisor_stops++ == 0) {
        s.first_stop_s = t + em.dt;
        s.stop_reason = data.reason;
        s.stop_detail = data.stop;
      }
    }
    previous = data.state;
    plant.set_platform_command(data.command, data.command_twist, data.command_acceleration);
    plant.advance(em.dt);
    emulated[static_cast<std::size_t>(k)] = plant.sensor_pose();
    if (trace)
      trace->push_back({t + em.dt, data.command, plant.platform_pose(), Eigen::Isometry3d(),
                        data.legs, measured, data.compensated, data.state});
  }

  const std::vector<Eigen::Isometry3d> ref = reference_poses.get();
  double sum_p2 = 0.0, sum_a2 = 0.0;
  for (std::size_t k = 0; k < ref.size(); ++k) {
    const double dp = (emulated[k].translation() - ref[k].translation()).norm();
    const double da = angle_deg(emulated[k].linear(), ref[k].linear());
    s.position_error_max_m = std::max(s.position_error_max_m, dp);
    s.attitude_error_max_deg = std::max(s.attitude_error_max_deg, da);
    sum_p2 += dp * dp;
    sum_a2 += da * da;
    if (trace) (*trace)[trace->size() - ref.size() + k].reference = ref[k];
  }
  const Excursion excursion = excursion_of(ref, setup.interface0);
  s.reference_excursion_m = excursion.position_m;
  s.reference_excursion_deg = excursion.angle_rad * 180 / std::numbers::pi;
  s.position_error_rms_m = std::sqrt(sum_p2 / std::max(1, ticks));
  s.attitude_error_rms_deg = std::sqrt(sum_a2 / std::max(1, ticks));
  s.control_step_ns = 1e9 * step_seconds / std::max(1, ticks);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s;
}

Excursion reference_excursion(const Model& model, const EmulationOptions& o) {
  const RunSetup setup(model, o);
  FreeFloatingReference reference(model, o.spacecraft, setup.interface0, setup.plant);
  const int n = model.num_joints();
  reference.set_joints(setup.start(n));
  return excursion_of(run_reference(reference, setup.trajectory, n, setup.ticks, 1.0 / o.rate),
                      setup.interface0);
}

SpacecraftSizing size_spacecraft(const Model& model, const EmulationOptions& options,
                                 double fraction) {
  EmulationOptions o = options;
  SpacecraftSizing s;
  const double max_m = fraction * o.geometry.workspace.max_translation.minCoeff();
  const double max_rad = fraction * o.geometry.workspace.max_tilt;
  for (int doubling = 0; doubling <= 10; ++doubling) {
    s.factor = std::ldexp(1.0, doubling);
    o.spacecraft.mass = 50.0 * s.factor;
    o.spacecraft.inertia = Eigen::Matrix3d::Identity() * 5.0 * s.factor;
    s.spacecraft = o.spacecraft;
    s.excursion = reference_excursion(model, o);
    if (s.excursion.position_m <= max_m && s.excursion.angle_rad <= max_rad) break;
  }
  return s;
}

std::string describe_stop(const EmulationSummary& s, const EmulationOptions& o,
                          EmulatorSpeller spell) {
  if (s.supervisor_stops == 0) return "";
  const StopDetail& d = s.stop_detail;
  constexpr double deg = 180.0 / std::numbers::pi;
  const char* axes = "xyz";
  std::string what;
  switch (s.stop_reason) {
    case StopReason::Workspace:
      what = d.index == 3 ? fmt::format(
                                "braking would end {:.3g} deg from home, beyond the platform "
                                "workspace's {:.3g} deg",
                                d.value * deg, d.limit * deg)
                          : fmt::format(
                                "braking would end {:.3g} m from home along {}, beyond the "
                                "platform workspace's {:.3g} m",
                                d.value, axes[std::clamp(d.index, 0, 2)], d.limit);
      break;
    case StopReason::LegLimit:
      what = fmt::format(
          "leg {} would reach {:.5g} m, {:.3g} mm past {:.5g} m (its stroke end "
          "less the {:.3g} m margin)",
          d.index + 1, d.value, 1e3 * std::abs(d.value - d.limit), d.limit,
          o.supervisor.leg_margin);
      break;
    case StopReason::TrackingError:
      what = d.index == 1 ? fmt::format(
                                "the platform was {:.3g} deg off its command, limit "
                                "{:.3g} deg",
                                d.value * deg, d.limit * deg)
                          : fmt::format(
                                "the platform was {:.3g} m off its command, limit "
                                "{:.3g} m",
                                d.value, d.limit);
      break;
    case StopReason::None:
      return "";
  }
  const double ws_m = o.geometry.workspace.max_translation.minCoeff();
  const double ws_deg = o.geometry.workspace.max_tilt * deg;
  using Setting = EmulatorSetting;
  const std::string heavier =
      fmt::format("a heavier spacecraft ({}, {})", spell(Setting::SpacecraftMass),
                  spell(Setting::SpacecraftInertia));
  const std::string trajectory = spell(Setting::Trajectory);
  const std::string larger = fmt::format("a larger platform ({})", spell(Setting::Platform));
  std::string fix;
  if (s.stop_reason == StopReason::TrackingError)
    fix = fmt::format("the platform servo cannot follow: a slower trajectory ({}), {}", trajectory,
                      heavier);
  else if (s.reference_excursion_m > ws_m || s.reference_excursion_deg > ws_deg)
    fix = fmt::format(
        "the free-floating reference itself moves {:.3g} m and {:.3g} deg, more than the "
        "workspace ({:.3g} m, {:.3g} deg): {}, a gentler trajectory ({}) or {}",
        s.reference_excursion_m, s.reference_excursion_deg, ws_m, ws_deg, heavier, trajectory,
        larger);
  else
    fix = fmt::format(
        "the reference fits the workspace ({:.3g} m, {:.3g} deg of {:.3g} m, {:.3g} deg), so "
        "the emulation's own error drove the platform there: a wrong or missing gravity "
        "model; else {} or {}",
        s.reference_excursion_m, s.reference_excursion_deg, ws_m, ws_deg, heavier, larger);
  return fmt::format("{}; to fix: {}", what, fix);
}

}  // namespace massid::emulator
