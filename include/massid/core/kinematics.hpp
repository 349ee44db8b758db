// Forward kinematics of the measured links in the sensor frame, with their
// motion when the joints move (one recursion for rest and motion).
//
// Positions (paper eqs. 20-23), link l with parent p, joint frame J = origin_l:
//   T_l(q) = T_p(q) * origin_l * motion_l(q_l)
// motion is a rotation about the joint axis s (revolute) or a translation
// along it (prismatic); the sensor link's frame is the sensor frame (T = 1).
//
// Motion (link-frame coordinates; R = R_pl the rotation of l in p, t the
// origin of l in p, all at q; Luh, Walker & Paul's forward recursion):
//   w_l  = R^T w_p + s qd                                     (revolute)
//   dw_l = R^T dw_p + s qdd + w_l x s qd                      (revolute)
//   a_l  = R^T (a_p + dw_p x t + w_p x (w_p x t))
//          + s qdd + 2 w_l x s qd                             (prismatic terms)
// a is the acceleration of the link origin MINUS gravity (gravity as a
// fictitious upward acceleration of the sensor frame): a_0 = a_sensor - g.
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "massid/core/model.hpp"

namespace massid {

// Motion of the sensor frame itself, in sensor-frame coordinates (a moving
// platform, or joints above the sensor link). Zero: the sensor is at rest.
struct FrameMotion {
  Eigen::Vector3d omega = Eigen::Vector3d::Zero();      // angular velocity, rad/s
  Eigen::Vector3d omega_dot = Eigen::Vector3d::Zero();  // angular acceleration, rad/s^2
  Eigen::Vector3d accel = Eigen::Vector3d::Zero();  // origin acceleration without gravity, m/s^2
};

// Workspace of forward_kinematics. Sized once by the constructor; the
// algorithms never allocate.
struct KinematicsData {
  explicit KinematicsData(const Model& model);
  // Position stage:
  std::vector<Eigen::Matrix3d> rotation;  // [num_links] R_l: link frame -> sensor frame
  std::vector<Eigen::Vector3d> position;  // [num_links] p_l: link origin in the sensor frame
  // Motion stage (only forward_kinematics with velocities fills it), link frame:
  std::vector<Eigen::Vector3d> omega;      // [num_links] angular velocity w_l, rad/s
  std::vector<Eigen::Vector3d> omega_dot;  // [num_links] angular acceleration dw_l, rad/s^2
  std::vector<Eigen::Vector3d> accel;      // [num_links] origin acceleration minus gravity, m/s^2
};

// Positions only. q: [num_joints] joint positions, in Model::joints order.
void forward_kinematics(const Model& model, KinematicsData& data,
                        const Eigen::Ref<const Eigen::VectorXd>& q);

// Positions and motion. q, qd, qdd: [num_joints]; gravity: [3] in the sensor
// frame; sensor: the sensor frame's own motion.
void forward_kinematics(const Model& model, KinematicsData& data,
                        const Eigen::Ref<const Eigen::VectorXd>& q,
                        const Eigen::Ref<const Eigen::VectorXd>& qd,
                        const Eigen::Ref<const Eigen::VectorXd>& qdd,
                        const Eigen::Vector3d& gravity, const FrameMotion& sensor = {});

// The sensor frame's orientation and motion from the joints above it
// (Model::upstream, root at rest): R [3x3] sensor -> root, and its motion in
// the sensor frame. qu, qdu, qddu: [num_upstream_joints] (qdu, qddu may be
// empty: at rest).
struct SensorPose {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();  // sensor frame -> root frame
  FrameMotion motion;
};
SensorPose upstream_kinematics(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& qu,
                               const Eigen::Ref<const Eigen::VectorXd>& qdu,
                               const Eigen::Ref<const Eigen::VectorXd>& qddu);

// The pose in the URDF root frame of the child link of every step of the
// chain above the sensor link (Model::upstream, root first: the last is the
// sensor frame) at the upstream joints' positions qu [num_upstream_joints].
// out is resized to Model::upstream's size.
void upstream_link_poses(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& qu,
                         std::vector<Eigen::Isometry3d>& out);

// Gravity in the sensor frame for `root_gravity` in the URDF root frame, when
// the chain above the sensor link (Model::upstream) has no movable joint: its
// fixed rotation applied (the root gravity as it is when the sensor link is
// the root). InputError naming the movable joints otherwise: gravity in the
// sensor frame then turns with them and is no single vector.
Eigen::Vector3d fixed_sensor_gravity(const Model& model, const Eigen::Vector3d& root_gravity);

// Gravity and the sensor frame's motion from the joints above the sensor link,
// or from a log's pose columns (Model::pose, with_sensor_pose: qu the pose as
// normalise_pose leaves it, qdu and qddu its derivatives; InputError in
// motion without x,y,z),
// the one computation of every reader, the compensator and the C interface.
// qu [num_upstream_joints]; gravity [3], when not null: R^T root_gravity in
// the sensor frame; sensor_motion [9], when not null: wx wy wz, dwx dwy dwz,
// ax ay az (samples.hpp), qdu and qddu [num_upstream_joints] then being the
// joints' velocities and accelerations (else unused: at rest).
void upstream_sensor_frame(const Model& model, const double* qu, const double* qdu,
                           const double* qddu, const Eigen::Vector3d& root_gravity, double* gravity,
                           double* sensor_motion);

// A log's sensor pose (`pose`: Model::pose): its values qu [size] as read
// (Model::upstream_joints order) checked and made what upstream_sensor_frame
// takes: a quaternion normalised; a matrix r11..r33 turned into the
// quaternion qx,qy,qz,qw, then x,y,z when given, then zeros (the motion
// filter smooths and differentiates those). In place. "" when good; else why
// not, naming the columns (the caller adds the file and line): a quaternion
// whose norm is off 1 by more than kPoseTolerance, a matrix farther than that
// from a rotation. Nothing to do for None.
constexpr double kPoseTolerance = 1e-3;
std::string normalise_pose(SensorPoseColumns pose, int size, double* qu);

// q and -q are one rotation: the quaternion qu [4] of a normalised pose
// (normalise_pose) negated when it points away from the previous row's, so
// that the motion filter smooths and differentiates a continuous signal; its
// given rates qdu, qddu [4] (when not null) with it. Nothing for None.
void continue_pose_sign(SensorPoseColumns pose, const double* previous, double* qu,
                        double* qdu = nullptr, double* qddu = nullptr);

// The robot's size: the largest distance from the sensor origin of a link
// origin or centre of mass over 256 configurations spread over the joints'
// ranges (limits where given, else a full turn or +-1 m; a fixed seed: a
// property of the model). 0 for a model whose links all sit at the origin.
double reach(const Model& model);

}  // namespace massid
