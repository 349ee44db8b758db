// MuJoCo plants for the space emulator (target massid_emulator_mujoco; MuJoCo
// stays out of this header).
//
//   PlatformPlant          the lab: the robot of a massid::Model standing on its
//                          sensor link, which is fixed to the top of a Stewart
//                          platform, gravity on. The platform is one rigid body
//                          on a free joint, servoed to the commanded pose by a
//                          6-DOF PD law computed here before every MuJoCo step
//                          (a physical servo, not a mocap body: the arm feels
//                          the platform's accelerations, and the platform feels
//                          the arm). The legs are not modelled.
//   FreeFloatingReference  orbit: the same robot on a free-floating spacecraft
//                          body, zero gravity; what the emulator must reproduce.
//
// Both build MJCF text from the Model with 17 significant digits (robot_mjcf):
// link origins, joint axes, masses, centres of mass. massid::Model carries no
// inertia tensors: PlantOptions::link_inertia gives them, else every link gets
// an isotropic one (radius of gyration default_radius_of_gyration). No contacts,
// no constraints, no joint limits, no geoms. Integrator RK4 (explicit Euler
// drifts momentum, shared/notes/facts.md).
//
// Servos, both in acceleration units scaled by MuJoCo's joint-space inertia
// matrix M(q) and with the bias forces (gravity, Coriolis: qfrc_bias) fed
// forward, so one pair of gains suits every joint and every platform axis and
// the servo bandwidth does not depend on the load:
//
//   robot joint j:  tau_j = M_jj (joint_kp e_j + joint_kd e'_j) + bias_j
//   platform:       F     = M_pp (platform_kp e + platform_kd e') + bias_p
//
// M_jj is the diagonal entry of joint j (the composite inertia of the links
// below it about its axis), M_pp the 6x6 block of the platform's free joint
// (platform plus the arm as if locked, about the platform origin). The platform
// error e = [p_cmd - p (world); log(R^T R_cmd) (platform frame)], e' likewise
// from the velocities. Commands are extrapolated at their velocity between
// updates (first-order hold): target(t) = cmd + cmd_velocity (t - t_cmd).
//
// Timing of the servos. The joint servo is a digital controller at the MuJoCo
// rate: sampled at the start of each step, held over it. Its forces are
// internal to the robot and constant over the step, so the free-floating
// reference conserves momentum to RK4 accuracy (~1e-9 kg m/s over 5 s; with
// the servo re-evaluated at every RK4 stage it was ~1e-6). The platform servo
// is continuous (re-evaluated at every RK4 stage, a custom RK4 that mirrors
// mj_RungeKutta): held over a step it went unstable against the arm on the
// 23 kg ur_like, since M_pp (arm locked) far exceeds the platform's own inertia.
//
// Default gains: platform 40 Hz critically damped (kp = (2 pi 40)^2 = 63165
// s^-2, kd = 2 (2 pi 40) = 503 s^-1; stable up to 80 Hz at least), joints 15 Hz
// (kp = 8883 s^-2, kd = 188 s^-1). Measured (tests/test_mujoco_plant.cpp) with
// the arm swinging 0.5 rad at 0.8 Hz on every joint: a 0.05 m / 5 deg, 0.5 Hz
// sinusoid commanded at 1 kHz (finite-difference velocity) is tracked within
// 2.2e-5 m and 1.5e-4 rad (ur_like, 23.4 kg), 1.4e-5 m and 3e-5 rad (puma260).
// Cost: ~60-80 us per advance(1 ms) (2 steps) for ur_like on this machine.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "massid/emulator/spacecraft.hpp"
#include "massid/emulator/stewart_platform.hpp"
#include "massid/model.hpp"

namespace massid::emulator {

struct PlantOptions {
  double timestep = 0.0005;                     // MuJoCo step (s), RK4
  Eigen::Vector3d gravity{0.0, 0.0, -9.80665};  // world (PlatformPlant only)
  // The robot's sensor link frame on the platform top (PlatformPlant only).
  Eigen::Isometry3d platform_T_sensor = Eigen::Isometry3d::Identity();
  double platform_mass = 20.0;  // kg, com at the platform origin
  Eigen::Matrix3d platform_inertia = Eigen::Vector3d(0.65, 0.65, 1.25).asDiagonal();  // kg m^2
  double platform_kp = 63165.0;  // s^-2, see the header comment
  double platform_kd = 503.0;    // s^-1
  double joint_kp = 8883.0;      // s^-2
  double joint_kd = 188.0;       // s^-1
  // Inertia tensors about each link's com, link frame, in Model::links order;
  // empty: isotropic mass * default_radius_of_gyration^2.
  std::vector<Eigen::Matrix3d> link_inertia;
  double default_radius_of_gyration = 0.05;  // m
};

// The robot's bodies as MJCF <body> elements (17 significant digits), the
// sensor link's body first with a site "massid_ft" at its origin; `indent`
// spaces before each line. The sensor link's body gets pos/quat `parent_T_sensor`.
std::string robot_mjcf(const Model& model, const PlantOptions& options,
                       const Eigen::Isometry3d& parent_T_sensor, int indent);

// The MuJoCo model, data and servos behind both plants (mujoco_plant.cpp).
class MujocoSimulation;

class PlatformPlant {
 public:
  // Platform at geometry.home (the platform base frame is the world frame),
  // joints at 0, at rest, commands = that state. Throws InputError when MuJoCo
  // rejects the model or the options are invalid.
  PlatformPlant(const Model& model, const PlatformGeometry& geometry,
                const PlantOptions& options = {});
  ~PlatformPlant();
  PlatformPlant(PlatformPlant&&) noexcept;
  PlatformPlant& operator=(PlatformPlant&&) noexcept;

  // The platform's commanded pose (base frame). Without a twist, the command
  // velocity is the finite difference to the previous command over the
  // simulated time between them (kept when no time has passed).
  void set_platform_command(const Eigen::Isometry3d& base_T_platform);
  // With an explicit twist [v; w] (base frame: origin velocity, angular velocity).
  void set_platform_command(const Eigen::Isometry3d& base_T_platform, const Twist& twist);
  // Joint targets, Model::joints order.
  void set_joint_command(const Eigen::VectorXd& q, const Eigen::VectorXd& qd);
  // Teleports the joints (initial condition): zero joint velocity, command = q.
  void set_joints(const Eigen::VectorXd& q);
  // MuJoCo steps until the time has advanced by dt (rounded to whole steps).
  void advance(double dt);

  // The load's wrench on the sensor (massid convention: MuJoCo's reading
  // negated), sensor frame, moment about the sensor origin, at the current
  // state under the servo forces now in effect (inertial forces included).
  Wrench measured_wrench() const;
  Eigen::Isometry3d platform_pose() const;  // reached base_T_platform
  Twist platform_twist() const;             // [v of its origin; w], base frame
  Eigen::Isometry3d sensor_pose() const;    // world_T_sensor
  Eigen::VectorXd joint_positions() const;
  Eigen::VectorXd joint_velocities() const;
  double time() const;

 private:
  std::unique_ptr<MujocoSimulation> sim_;
};

class FreeFloatingReference {
 public:
  // The interface is the robot's sensor frame, starting at world_T_interface0.
  // The spacecraft body (mass, inertia about its com, com at the body-frame
  // origin) is welded to the sensor link through spacecraft.body_T_interface.
  // Zero gravity; options.gravity and platform_* are ignored. At rest, joints 0.
  FreeFloatingReference(const Model& model, const SpacecraftParameters& spacecraft,
                        const Eigen::Isometry3d& world_T_interface0,
                        const PlantOptions& options = {});
  ~FreeFloatingReference();
  FreeFloatingReference(FreeFloatingReference&&) noexcept;
  FreeFloatingReference& operator=(FreeFloatingReference&&) noexcept;

  void set_joint_command(const Eigen::VectorXd& q, const Eigen::VectorXd& qd);
  void set_joints(const Eigen::VectorXd& q);  // body keeps its pose; everything at rest
  void advance(double dt);

  Eigen::Isometry3d interface_pose() const;  // world_T_interface (sensor frame)
  Twist interface_twist() const;             // [v of its origin; w], world frame
  Eigen::VectorXd joint_positions() const;
  Eigen::VectorXd joint_velocities() const;
  double time() const;

  // Whole system (spacecraft + robot), world frame: linear momentum, angular
  // momentum about the system com, and the system com.
  Eigen::Vector3d linear_momentum() const;
  Eigen::Vector3d angular_momentum() const;
  Eigen::Vector3d center_of_mass() const;
  double total_mass() const;

 private:
  std::unique_ptr<MujocoSimulation> sim_;
};

}  // namespace massid::emulator
