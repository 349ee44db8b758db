#include "massid/emulator/emulation.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>

namespace massid::emulator {

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

  PlantOptions plant_options = o.plant;
  plant_options.platform_T_sensor = o.platform_T_sensor;
  PlatformPlant plant(model, o.geometry, plant_options);
  const Eigen::Isometry3d interface0 = o.geometry.home * o.platform_T_sensor;
  FreeFloatingReference reference(model, o.spacecraft, interface0, plant_options);

  const JointTrajectory trajectory =
      o.trajectory ? o.trajectory : smooth_maneuver(model, o.duration);
  Eigen::VectorXd q(model.num_joints()), qd(model.num_joints()), qdd(model.num_joints());
  trajectory(0.0, q, qd, qdd);
  plant.set_joints(q);
  reference.set_joints(q);

  if (compensate && o.tare)
    tare(em, data, plant.measured_wrench(), plant.joint_positions(), plant.platform_pose());

  EmulationSummary s;
  double sum_p2 = 0.0, sum_a2 = 0.0, step_seconds = 0.0;
  const int ticks = static_cast<int>(std::lround(o.duration * o.rate));
  SupervisorState previous = SupervisorState::Running;
  for (int k = 0; k < ticks; ++k) {
    const double t = k * em.dt;
    trajectory(t, q, qd, qdd);
    plant.set_joint_command(q, qd, qdd);
    reference.set_joint_command(q, qd, qdd);
    const Wrench measured = plant.measured_wrench();
    const auto t0 = std::chrono::steady_clock::now();
    control_step(em, data, measured, plant.joint_positions(), plant.platform_pose());
    step_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    if (data.state != SupervisorState::Running && previous == SupervisorState::Running)
      ++s.supervisor_stops;
    previous = data.state;
    plant.set_platform_command(data.command, data.command_twist, data.command_acceleration);
    plant.advance(em.dt);
    reference.advance(em.dt);

    const Eigen::Isometry3d emulated = plant.sensor_pose();
    const Eigen::Isometry3d ref = reference.interface_pose();
    const double dp = (emulated.translation() - ref.translation()).norm();
    const double da = Eigen::AngleAxisd(emulated.linear().transpose() * ref.linear()).angle() *
                      180 / std::numbers::pi;
    s.position_error_max_m = std::max(s.position_error_max_m, dp);
    s.attitude_error_max_deg = std::max(s.attitude_error_max_deg, da);
    sum_p2 += dp * dp;
    sum_a2 += da * da;
    s.reference_excursion_m =
        std::max(s.reference_excursion_m, (ref.translation() - interface0.translation()).norm());
    s.reference_excursion_deg =
        std::max(s.reference_excursion_deg,
                 Eigen::AngleAxisd(interface0.linear().transpose() * ref.linear()).angle() * 180 /
                     std::numbers::pi);
    if (trace)
      trace->push_back({t + em.dt, data.command, plant.platform_pose(), ref, data.legs, measured,
                        data.compensated, data.state});
  }
  s.position_error_rms_m = std::sqrt(sum_p2 / std::max(1, ticks));
  s.attitude_error_rms_deg = std::sqrt(sum_a2 / std::max(1, ticks));
  s.control_step_ns = 1e9 * step_seconds / std::max(1, ticks);
  s.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return s;
}

}  // namespace massid::emulator
