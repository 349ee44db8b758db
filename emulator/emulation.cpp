#include "massid/emulator/emulation.hpp"

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

}  // namespace

EmulationSummary run_emulation(const Model& model, const Predictor& predictor,
                               const EmulationOptions& o, bool compensate,
                               std::vector<TraceRow>* trace) {
  const auto start = std::chrono::steady_clock::now();
  EmulatorModel em;
  em.predictor = predictor;
  em.spacecraft = o.spacecraft;
  em.geometry = o.geometry;
  em.platform_T_sensor = o.platform_T_sensor;
  em.gravity_world = o.plant.gravity;
  em.dt = 1.0 / o.rate;
  em.supervisor = o.supervisor;
  em.compensate_gravity = compensate;
  EmulatorData data(em);

  // Both MuJoCo models are compiled here, on one thread.
  PlantOptions plant_options = o.plant;
  plant_options.platform_T_sensor = o.platform_T_sensor;
  PlatformPlant plant(model, o.geometry, plant_options);
  const Eigen::Isometry3d interface0 = o.geometry.home * o.platform_T_sensor;
  FreeFloatingReference reference(model, o.spacecraft, interface0, plant_options);

  const JointTrajectory trajectory =
      o.trajectory ? o.trajectory : smooth_maneuver(model, o.duration);
  const int n = model.num_joints();
  Eigen::VectorXd q(n), qd(n), qdd(n);
  trajectory(0.0, q, qd, qdd);
  plant.set_joints(q);
  reference.set_joints(q);
  const int ticks = static_cast<int>(std::lround(o.duration * o.rate));
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
    s.reference_excursion_m =
        std::max(s.reference_excursion_m, (ref[k].translation() - interface0.translation()).norm());
    s.reference_excursion_deg =
        std::max(s.reference_excursion_deg, angle_deg(interface0.linear(), ref[k].linear()));
    if (trace) (*trace)[trace->size() - ref.size() + k].reference = ref[k];
  }
  s.position_error_rms_m = std::sqrt(sum_p2 / std::max(1, ticks));
  s.attitude_error_rms_deg = std::sqrt(sum_a2 / std::max(1, ticks));
  s.control_step_ns = 1e9 * step_seconds / std::max(1, ticks);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s;
}

}  // namespace massid::emulator
