#include "massid/emulator/controller.hpp"

#include <algorithm>
#include <cmath>

namespace massid::emulator {

const char* to_string(SupervisorState state) {
  switch (state) {
    case SupervisorState::Running:
      return "running";
    case SupervisorState::Stopping:
      return "stopping";
    case SupervisorState::Stopped:
      return "stopped";
  }
  return "?";
}

const char* to_string(StopReason reason) {
  switch (reason) {
    case StopReason::None:
      return "none";
    case StopReason::LegLimit:
      return "leg limit";
    case StopReason::Workspace:
      return "workspace";
    case StopReason::TrackingError:
      return "tracking error";
  }
  return "?";
}

EmulatorData::EmulatorData(const EmulatorModel& model) : identified(model.identified) {
  reset(model, *this);
}

void reset(const EmulatorModel& model, EmulatorData& data) {
  data.command = model.geometry.home;
  data.legs = leg_lengths(model.geometry, data.command);
  data.command_twist.setZero();
  data.command_acceleration.setZero();
  data.spacecraft = state_at_rest(model.spacecraft, model.geometry.home * model.platform_T_sensor);
  data.gravity_sensor.setZero();
  data.gravity_wrench.setZero();
  data.compensated.setZero();
  data.tare.setZero();
  data.state = SupervisorState::Running;
  data.reason = StopReason::None;
  data.stop = StopDetail{};
  data.time = 0.0;
}

namespace {

// Shrinks a speed by what the deceleration removes in one period.
void decelerate(Eigen::Ref<Eigen::Vector3d> v, double rate, double dt) {
  const double speed = v.norm();
  v *= speed > rate * dt ? (speed - rate * dt) / speed : 0.0;
}

// Where the platform ends if it brakes now at the supervisor's decelerations:
// half the current speed over the braking time (constant deceleration).
Eigen::Isometry3d stopping_pose(const EmulatorModel& model, const Eigen::Isometry3d& pose,
                                const Twist& twist) {
  const SupervisorOptions& s = model.supervisor;
  Twist d;
  d.head<3>() = twist.head<3>() * (0.5 * twist.head<3>().norm() / s.linear_deceleration);
  d.tail<3>() = twist.tail<3>() * (0.5 * twist.tail<3>().norm() / s.angular_deceleration);
  return apply_twist(pose, d);
}

StopReason violation(const EmulatorModel& model, const Eigen::Isometry3d& pose,
                     StopDetail& detail) {
  const PlatformGeometry& g = model.geometry;
  if (!within_workspace(g, pose)) {
    // The limit exceeded by the largest fraction.
    const Eigen::Vector3d t = translation_from_home(g, pose).cwiseAbs();
    const double tilt = tilt_from_home(g, pose);
    detail = {3, tilt, g.workspace.max_tilt};
    double worst = tilt / g.workspace.max_tilt;
    for (int k = 0; k < 3; ++k)
      if (t[k] / g.workspace.max_translation[k] > worst)
        worst = t[k] / g.workspace.max_translation[k],
        detail = {k, t[k], g.workspace.max_translation[k]};
    return StopReason::Workspace;
  }
  const LegVector legs = leg_lengths(g, pose);
  const double margin = model.supervisor.leg_margin;
  if (!legs_within_limits(g, legs, margin)) {
    double worst = 0.0;
    for (int i = 0; i < kNumLegs; ++i) {
      const double below = g.leg_min[i] + margin - legs[i], above = legs[i] - g.leg_max[i] + margin;
      if (below > worst) worst = below, detail = {i, legs[i], g.leg_min[i] + margin};
      if (above > worst) worst = above, detail = {i, legs[i], g.leg_max[i] - margin};
    }
    return StopReason::LegLimit;
  }
  return StopReason::None;
}

}  // namespace

namespace {

// w_g = predict_gravity(q, R_ws^T g_w): the mechanism's gravity wrench in the
// current sensor frame (without the offset).
void gravity_wrench(const EmulatorModel& model, EmulatorData& data,
                    const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Isometry3d& platform) {
  const Eigen::Matrix3d R_ws = platform.linear() * model.platform_T_sensor.linear();
  data.gravity_sensor = R_ws.transpose() * model.gravity_world;
  data.gravity_wrench = model.compensate_gravity ? model.identified.predict_gravity(
                                                       data.identified, q, data.gravity_sensor)
                                                 : Wrench::Zero();
}

// What is left of the measured wrench: measured - w_g - offset (the identified
// model's compensate), or the raw wrench without compensation.
Wrench left_over(const EmulatorModel& model, const EmulatorData& data, const Wrench& measured) {
  return model.compensate_gravity ? model.identified.compensate(measured, data.gravity_wrench)
                                  : measured;
}

}  // namespace

void tare(const EmulatorModel& model, EmulatorData& data, const Wrench& measured,
          const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Isometry3d& platform) {
  gravity_wrench(model, data, q, platform);
  data.tare = left_over(model, data, measured);
}

void control_step(const EmulatorModel& model, EmulatorData& data, const Wrench& measured,
                  const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Isometry3d& platform) {
  data.time += model.dt;

  // Gravity compensation with gravity rotated into the current sensor frame.
  gravity_wrench(model, data, q, platform);
  data.compensated = left_over(model, data, measured) - data.tare;

  if (data.state == SupervisorState::Running) {
    // Tracking: the platform must follow the previous command.
    const Eigen::Vector3d dp = platform.translation() - data.command.translation();
    const double angle =
        Eigen::AngleAxisd(platform.linear().transpose() * data.command.linear()).angle();
    if (dp.norm() > model.supervisor.max_tracking_error ||
        angle > model.supervisor.max_tracking_angle) {
      data.state = SupervisorState::Stopping;
      data.reason = StopReason::TrackingError;
      data.stop = dp.norm() > model.supervisor.max_tracking_error
                      ? StopDetail{0, dp.norm(), model.supervisor.max_tracking_error}
                      : StopDetail{1, angle, model.supervisor.max_tracking_angle};
    }
  }

  if (data.state == SupervisorState::Running) {
    // Admittance: the spacecraft under the robot's dynamic wrench.
    SpacecraftState next = data.spacecraft;
    step(model.spacecraft, next, data.compensated, model.dt);
    const Eigen::Isometry3d interface = interface_pose(model.spacecraft, next);
    const Eigen::Isometry3d command = interface * model.platform_T_sensor.inverse();
    const Twist it = interface_twist(model.spacecraft, next);
    const Eigen::Vector3d r = command.translation() - interface.translation();
    Twist twist;
    twist.tail<3>() = it.tail<3>();
    twist.head<3>() = it.head<3>() + it.tail<3>().cross(r);
    // Acceleration of the platform origin: a_c + alpha x r_c + w x (w x r_c),
    // r_c from the centre of mass, all in the world (= platform base) frame.
    const SpacecraftAcceleration a = acceleration(model.spacecraft, next, data.compensated);
    const Eigen::Matrix3d R_wb = next.orientation.toRotationMatrix();
    const Eigen::Vector3d w = R_wb * next.angular_velocity, alpha = R_wb * a.angular;
    const Eigen::Vector3d rc = command.translation() - next.position;
    Twist accel;
    accel.head<3>() = a.linear + alpha.cross(rc) + w.cross(w.cross(rc));
    accel.tail<3>() = alpha;
    // Stop before a limit: the pose where braking from here would end must be safe.
    StopDetail detail;
    const StopReason reason = violation(model, stopping_pose(model, command, twist), detail);
    if (reason == StopReason::None) {
      data.spacecraft = next;
      data.command = command;
      data.command_twist = twist;
      data.command_acceleration = accel;
    } else {
      data.state = SupervisorState::Stopping;
      data.reason = reason;
      data.stop = detail;
    }
  }

  if (data.state == SupervisorState::Stopping) {
    // Brake smoothly from the last command's velocity: no jump in pose or speed.
    const Twist before = data.command_twist;
    decelerate(data.command_twist.head<3>(), model.supervisor.linear_deceleration, model.dt);
    decelerate(data.command_twist.tail<3>(), model.supervisor.angular_deceleration, model.dt);
    data.command_acceleration = (data.command_twist - before) / model.dt;
    data.command = apply_twist(data.command, data.command_twist * model.dt);
    if (data.command_twist.isZero(0.0)) data.state = SupervisorState::Stopped;
  }
  data.legs = leg_lengths(model.geometry, data.command);
}

}  // namespace massid::emulator
