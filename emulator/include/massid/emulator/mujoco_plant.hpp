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
// link origins, joint axes, masses, centres of mass and the URDF's inertia
// tensors (a link without a usable one gets an isotropic inertia of radius of
// gyration default_radius_of_gyration). No contacts, no constraints (a mimic
// joint's <equality> is in the MJCF but disabled), no joint limits, no geoms. Integrator RK4
// (explicit Euler drifts momentum), in a custom loop that mirrors mj_RungeKutta and evaluates both
// servos at every Runge-Kutta stage (continuous-time servos).
//
// Servos, both in acceleration units with MuJoCo's joint-space inertia matrix
// M(q) and the bias forces qfrc_bias (gravity, Coriolis) fed forward, so one
// pair of gains suits every robot:
//
//   platform (free joint): F = M_pp (a_cmd + kp e + kd e') + bias_p
//     M_pp the 6x6 block of the free joint (platform plus the arm as if
//     locked): a stiff industrial servo. The arm's reaction is a disturbance
//     it rejects. e = [p_target - p (world); log(R^T R_target) (platform
//     frame)], e' likewise from the velocities.
//   joints (computed torque): the joint accelerations are exactly
//     a = qdd_cmd + kp e + kd e', whatever the base does: with the base's
//     applied force fixed, a_b = M_bb^-1 (F_b - bias_b - M_bj a) and
//     tau = M_jb a_b + M_jj a + bias_j. Plant and reference then move their
//     joints identically: the only difference between the two is the base.
//   mimic joints (URDF <mimic>): a MuJoCo joint each, in the same computed
//     torque with its master's actual state as the target:
//     a = s a_master + kp (s q_master + o - q) + kd (s qd_master - qd). Set on
//     their masters (constructor, set_joints), they stay there to rounding
//     (the error obeys e'' + kd e' + kp e = 0 from zero, and RK4 keeps such a
//     linear invariant), so the sensor reads what massid's model of them
//     predicts. An equality constraint would be soft (solref), drift, and need
//     MuJoCo's constraint solver in the loop.
//
// Commands are held to second order between updates: target(t) = cmd +
// velocity tau + acceleration tau^2 / 2 (tau since the command), with the
// acceleration fed forward. This matters: with first-order hold the servo's
// acceleration jumps by kd * acceleration * period at every command and decays
// in between, a sawtooth at the command rate; a force sensor read at the
// command instants sees its peaks, a bias of about 10 % of the arm's dynamic
// wrench that the admittance model integrates into a drift.
//
// Default gains: platform 40 Hz critically damped (kp = (2 pi 40)^2 = 63165
// s^-2, kd = 2 (2 pi 40) = 503 s^-1), joints 15 Hz (kp = 8883 s^-2, kd = 188
// s^-1). Default step 1 ms (one step per control tick at 1 kHz).

#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <memory>
#include <string>
#include <vector>

#include "massid/core/model.hpp"
#include "massid/emulator/spacecraft.hpp"
#include "massid/emulator/stewart_platform.hpp"

namespace massid::emulator {

struct PlantOptions {
  double timestep = 0.001;                      // MuJoCo step (s), RK4
  Eigen::Vector3d gravity{0.0, 0.0, -9.80665};  // world (PlatformPlant only)
  // The robot's sensor link frame on the platform top (PlatformPlant only).
  Eigen::Isometry3d platform_T_sensor = Eigen::Isometry3d::Identity();
  double platform_mass = 20.0;  // kg, com at the platform origin
  Eigen::Matrix3d platform_inertia = Eigen::Vector3d(0.65, 0.65, 1.25).asDiagonal();  // kg m^2
  double platform_kp = 63165.0;  // s^-2, see the header comment
  double platform_kd = 503.0;    // s^-1
  double joint_kp = 8883.0;      // s^-2
  double joint_kd = 188.0;       // s^-1
  // Links whose URDF inertia MuJoCo cannot take (missing, singular, or
  // violating the triangle inequality) get mass * radius^2 about every axis.
  double default_radius_of_gyration = 0.05;  // m
};

// The MJCF body name of a URDF link: the link's name, except names MuJoCo or
// the plants use themselves ("world", MuJoCo's world body, as in ROS
// descriptions whose root link is "world"; "massid_platform",
// "massid_spacecraft"), which get the prefix "massid_link_". Internal only:
// users and files keep the URDF names.
std::string mjcf_body_name(const std::string& link);

// The MJCF joint name of a URDF joint: its name, except the plants' own free
// joints' names ("massid_platform_free", "massid_spacecraft_free"), which get
// the prefix "massid_joint_".
std::string mjcf_joint_name(const std::string& joint);

// The robot's bodies as MJCF <body> elements (17 significant digits), the
// sensor link's body first with a site "massid_ft" at its origin; `indent`
// spaces before each line. The sensor link's body gets pos/quat `parent_T_sensor`.
// Every movable link has a hinge or slide joint named after its URDF joint, a
// mimic joint's link too (MimicJoint::name).
std::string robot_mjcf(const Model& model, const PlantOptions& options,
                       const Eigen::Isometry3d& parent_T_sensor, int indent);

// The model's mimic joints as an MJCF <equality> element, one
// <joint joint1="MIMIC" joint2="MASTER" polycoef="OFFSET MULTIPLIER 0 0 0"/>
// each (q_mimic = offset + multiplier q_master); "" without mimic joints.
// The plants include it, so that the MJCF says what it is, but run with
// constraints disabled: their servo drives each mimic joint onto its master
// exactly (see the header comment), which a soft equality constraint would not.
std::string mimic_equalities_mjcf(const Model& model, int indent);

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
  // And an acceleration [a of the origin; dw/dt] (base frame), fed forward and
  // used to hold the target to second order until the next command.
  void set_platform_command(const Eigen::Isometry3d& base_T_platform, const Twist& twist,
                            const Twist& acceleration);
  // Joint targets, Model::joints order (mimic joints follow their masters):
  // position, velocity and (optional, else zero) acceleration, held to second
  // order until the next command.
  void set_joint_command(const Eigen::VectorXd& q, const Eigen::VectorXd& qd);
  void set_joint_command(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                         const Eigen::VectorXd& qdd);
  // Teleports the joints (initial condition): zero joint velocity, command = q,
  // mimic joints at multiplier q_master + offset.
  void set_joints(const Eigen::VectorXd& q);
  // MuJoCo steps until the time has advanced by dt (rounded to whole steps).
  void advance(double dt);

  // The load's wrench on the sensor (massid convention: MuJoCo's reading
  // negated), sensor frame, moment about the sensor origin, at the current
  // state under the servo forces now in effect (inertial forces included).
  Wrench measured_wrench() const;
  Eigen::Isometry3d platform_pose() const;   // reached base_T_platform
  Twist platform_twist() const;              // [v of its origin; w], base frame
  Eigen::Isometry3d sensor_pose() const;     // world_T_sensor
  Eigen::VectorXd joint_positions() const;   // Model::joints (no mimic joints)
  Eigen::VectorXd joint_velocities() const;  // Model::joints
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
  void set_joint_command(const Eigen::VectorXd& q, const Eigen::VectorXd& qd,
                         const Eigen::VectorXd& qdd);
  void set_joints(const Eigen::VectorXd& q);  // body keeps its pose; everything at rest
  void advance(double dt);

  Eigen::Isometry3d interface_pose() const;  // world_T_interface (sensor frame)
  // The robot's wrench on the spacecraft at the interface (massid convention,
  // sensor frame): what an ideal emulator's sensor would read.
  Wrench interface_wrench() const;
  Twist interface_twist() const;  // [v of its origin; w], world frame
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
