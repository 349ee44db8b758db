// The emulator in simulation: the control step (controller.hpp) driving the
// MuJoCo plant (the robot on its sensor on a servo-driven platform, gravity
// on), against the free-floating reference (the same robot on the spacecraft,
// no gravity), with the same joint trajectory. The error between the two
// interface (sensor frame) poses is how well the platform emulates orbit.
#pragma once

#include <string>

#include "massid/core/errors.hpp"
#include "massid/core/model.hpp"
#include "massid/emulator/controller.hpp"
#include "massid/emulator/joint_trajectory.hpp"
#include "massid/emulator/mujoco_plant.hpp"

namespace massid::emulator {

struct EmulationOptions {
  double duration = 10.0;  // s
  double rate = 1000.0;    // control rate, Hz
  SpacecraftParameters spacecraft;
  PlatformGeometry geometry = default_geometry();
  Eigen::Isometry3d platform_T_sensor = Eigen::Isometry3d::Identity();
  SupervisorOptions supervisor;
  PlantOptions plant;
  JointTrajectory trajectory;  // empty: smooth_maneuver(model, duration)
  bool tare = true;            // tare() at the start, arm at rest (only when compensating)
};

struct EmulationSummary {
  double position_error_max_m = 0.0, position_error_rms_m = 0.0;
  double attitude_error_max_deg = 0.0, attitude_error_rms_deg = 0.0;
  double reference_excursion_m = 0.0, reference_excursion_deg = 0.0;
  int supervisor_stops = 0;
  double first_stop_s = -1.0;  // time the supervisor first stopped, -1: never
  StopReason stop_reason = StopReason::None;
  StopDetail stop_detail;        // the limit and by how much (controller.hpp)
  double seconds = 0.0;          // wall-clock time of the run
  double control_step_ns = 0.0;  // mean wall-clock time of control_step
};

// One trace row per control tick (optional).
struct TraceRow {
  double t;
  Eigen::Isometry3d command, reached,
      reference;  // platform (base frame), reference interface (world)
  LegVector legs;
  Wrench measured, compensated;
  SupervisorState state;
};

// identified: the gravity model to compensate with (static or dynamic
// parameters: IdentifiedModel::predict_gravity, and its offset);
// compensate=false feeds the raw wrench. trace, when given, receives every tick.
EmulationSummary run_emulation(const Model& model, const IdentifiedModel& identified,
                               const EmulationOptions& options, bool compensate,
                               std::vector<TraceRow>* trace = nullptr);

// How far the free-floating reference alone (the robot on options.spacecraft,
// following the trajectory, or smooth_maneuver) moves its interface from the
// start: the largest distance (m) and rotation (rad). The platform must
// reproduce this, so it must fit in the workspace.
struct Excursion {
  double position_m = 0.0, angle_rad = 0.0;
};
Excursion reference_excursion(const Model& model, const EmulationOptions& options);

// The default spacecraft sized to the robot: 50 kg and 5 kg m^2 about every
// axis (a 0.32 m radius of gyration), both doubled until the reference's
// excursion stays within `fraction` of the workspace (translation: the
// smallest per-axis limit; rotation: max_tilt), at most 2^10 times.
// A light robot keeps 50 kg; a UR5 (21 kg) on the default maneuver gets 400 kg.
struct SpacecraftSizing {
  SpacecraftParameters spacecraft;
  double factor = 1.0;  // on 50 kg and 5 kg m^2
  Excursion excursion;  // of the reference on the sized spacecraft
};
SpacecraftSizing size_spacecraft(const Model& model, const EmulationOptions& options,
                                 double fraction = 0.5);

// The emulator's settings that describe_stop names as fixes, spelled by the
// caller in its own terms (the CLI: its options), as the library's hints are
// (massid/errors.hpp).
enum class EmulatorSetting {
  SpacecraftMass,     // the emulated spacecraft's mass, kg
  SpacecraftInertia,  // its principal inertia, kg m^2
  Trajectory,         // the joint trajectory to run
  Platform,           // the platform's geometry
};
using EmulatorSpeller = std::string (*)(EmulatorSetting);

// One line on why a run stopped: which limit (workspace axis, leg, tracking),
// the value against the limit, and the settings that would help, named by
// `spell`. "" when the run did not stop.
std::string describe_stop(const EmulationSummary& summary, const EmulationOptions& options,
                          EmulatorSpeller spell);

}  // namespace massid::emulator
