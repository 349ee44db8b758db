// The space emulator's control step (the paper's Figure 4): each tick
//
//   g_s   = R_ws^T g_w                       gravity in the current sensor frame
//   w_g   = predict_gravity(q, g_s)          identified gravity wrench (IdentifiedModel)
//   w_c   = w_measured - w_g - offset        the robot's dynamic wrench on its base
//   x    <- RK4 step of the spacecraft under w_c at the interface (= sensor frame)
//   T_cmd = T_interface(x) * sensor_T_platform,   l = IK(T_cmd)
//   with the command's twist and acceleration for the platform servo's feed-forward
//
// and a supervisor that brings the platform smoothly to rest before a leg,
// workspace or tracking limit is violated.
//
// EmulatorModel is immutable; EmulatorData is the workspace. control_step()
// does not allocate.
#pragma once

#include <Eigen/Geometry>
#include <string>

#include "massid/emulator/spacecraft.hpp"
#include "massid/emulator/stewart_platform.hpp"
#include "massid/live/identified_model.hpp"

namespace massid::emulator {

enum class SupervisorState { Running, Stopping, Stopped };
enum class StopReason { None, LegLimit, Workspace, TrackingError };
const char* to_string(SupervisorState state);
const char* to_string(StopReason reason);

struct SupervisorOptions {
  double leg_margin = 0.01;           // m kept from every leg's stroke ends
  double max_tracking_error = 0.005;  // m, commanded vs measured platform origin
  double max_tracking_angle = 0.02;   // rad, commanded vs measured platform attitude
  double linear_deceleration = 0.5;   // m/s^2 while stopping
  double angular_deceleration = 1.0;  // rad/s^2 while stopping
};

struct EmulatorModel {
  // The identified model (static or dynamic parameters: its gravity-only
  // prediction, identified_model.hpp) and its offset.
  IdentifiedModel identified;
  SpacecraftParameters spacecraft;
  PlatformGeometry geometry;  // base frame = world: level, gravity along gravity_world
  Eigen::Isometry3d platform_T_sensor =
      Eigen::Isometry3d::Identity();  // sensor on the platform top
  Eigen::Vector3d gravity_world{0.0, 0.0, -9.80665};
  double dt = 0.001;  // control period, s
  SupervisorOptions supervisor;
  bool compensate_gravity = true;  // false: feed the raw measured wrench (for comparison)
};

// What the supervisor stopped for, in numbers (no allocation in the control
// step). Workspace: `index` 0..2 the base-frame axis x, y, z of the
// translation from home (value |p - p_home| in m), 3 the rotation from home
// (rad); leg limit: `index` the leg 0..5, value its length and limit the end
// of its stroke less the margin (m); tracking error: index 0 position (m), 1
// attitude (rad). For workspace and leg limits the pose checked is where
// braking from the next command would end (stopping distance included).
struct StopDetail {
  int index = -1;
  double value = 0.0, limit = 0.0;
};

// Workspace and state of the emulator, grouped by the stage that writes it.
struct EmulatorData {
  explicit EmulatorData(const EmulatorModel& model);
  // gravity compensation
  IdentifiedModelData identified;          // the identified model's workspace
  Eigen::Vector3d gravity_sensor;          // g in the current sensor frame, m/s^2
  Wrench gravity_wrench = Wrench::Zero();  // predicted w_g, sensor frame
  Wrench tare = Wrench::Zero();            // w_0 from tare(): residual at rest, subtracted
  Wrench compensated = Wrench::Zero();     // w_c = measured - w_g - offset - w_0
  // admittance
  SpacecraftState spacecraft;  // emulated spacecraft
  // command
  Eigen::Isometry3d command;            // base_T_platform commanded
  LegVector legs;                       // leg lengths of the command, m
  Twist command_twist = Twist::Zero();  // [v of platform origin; w], base frame
  // [a of platform origin; dw/dt], base frame: the spacecraft's acceleration at
  // the command under the wrench just applied, for the servo's feed-forward.
  Twist command_acceleration = Twist::Zero();
  // supervisor
  SupervisorState state = SupervisorState::Running;
  StopReason reason = StopReason::None;
  StopDetail stop;
  double time = 0.0;  // s since start
};

// Resets data to the start: platform at home, spacecraft at rest there.
void reset(const EmulatorModel& model, EmulatorData& data);

// Tares the compensated wrench: with the arm at rest, what the measured wrench
// and the gravity model disagree by (the model's error at this pose, the
// sensor's offset) is stored in data.tare and subtracted from then on, as a
// lab zeroes its sensor before a run. Call it before the first control_step.
void tare(const EmulatorModel& model, EmulatorData& data, const Wrench& measured,
          const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Isometry3d& platform);

// One control tick. measured: sensor wrench (massid convention); q: joint
// positions; platform: measured base_T_platform (from the legs' forward
// kinematics or a tracker).
void control_step(const EmulatorModel& model, EmulatorData& data, const Wrench& measured,
                  const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Isometry3d& platform);

}  // namespace massid::emulator
