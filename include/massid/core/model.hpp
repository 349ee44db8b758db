// The kinematic model of the measured bodies: the sensor link and its subtree,
// loaded from a URDF. Immutable once built; algorithms take it by const&.
#pragma once

#include <Eigen/Geometry>
#include <string>
#include <utility>
#include <vector>

namespace massid {

enum class JointType { Fixed, Revolute, Prismatic };

// A measured link and the joint that connects it to its parent link.
struct Link {
  std::string name;
  int parent = -1;                    // index in Model::links; -1 for the sensor link
  std::string joint;                  // URDF joint from the parent ("" for the sensor link)
  JointType type = JointType::Fixed;  // revolute covers URDF "continuous" too
  int joint_index = -1;               // index in Model::joints, -1 when fixed
  // The joint's position is joint_scale q[joint_index] + joint_offset: 1 and 0
  // for an independent joint; a URDF mimic joint follows its master
  // (joint_index) with the mimic's multiplier and offset (Model::mimics).
  double joint_scale = 1.0;
  double joint_offset = 0.0;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // parent frame -> joint frame, q = 0
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();           // unit joint axis, joint frame
  // Nominal inertial from the URDF (used by `simulate`, never by `predict`).
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();  // centre of mass in the link frame
  // Rotational inertia about the com, link frame, kg m^2 (only the emulator's
  // dynamic simulation uses it; static wrenches do not depend on it).
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();
  bool has_inertial = false;
  // Bounding spheres of the link's primitive <collision> shapes (box, cylinder,
  // sphere): centre in the link frame, radius (m). Meshes are not read:
  // collision_meshes counts them (design then checks the link's origin and
  // centre of mass only).
  struct Sphere {
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    double radius = 0.0;
  };
  std::vector<Sphere> collision;
  int collision_meshes = 0;
};

// A movable joint (revolute, continuous or prismatic) of the measured subtree.
struct Joint {
  std::string name;
  JointType type = JointType::Revolute;
  bool continuous = false;
  double lower = 0.0, upper = 0.0;  // limits (rad or m); unlimited when !limited
  bool limited = false;
  // The URDF's own limits; lower/upper are narrower when a mimic joint's
  // limits allow less of the master's range (MimicJoint).
  double urdf_lower = 0.0, urdf_upper = 0.0;
  double velocity_limit = 0.0;  // URDF <limit velocity>, rad/s or m/s; 0 when not given
  int link = -1;                // the child link it moves, index in Model::links

  // Position at fraction u in [0, 1] of the joint's generic range: a full turn
  // [-pi, pi] for revolute joints, the limits (else [-1, 1] m) for prismatic ones.
  double generic_position(double u) const;
};

// A URDF mimic joint of the measured subtree: q = multiplier q_master + offset.
// It has no column in any file and no entry in Model::joints; its link moves
// with the master (Link::joint_index, joint_scale, joint_offset), and its own
// limits narrow the master's (Joint::lower/upper, the URDF's in urdf_lower/upper).
struct MimicJoint {
  std::string name;
  std::string master;  // URDF name of the master joint (in Model::joints)
  double multiplier = 1.0, offset = 0.0;
  int link = -1;  // the child link it moves, index in Model::links
};

// One joint of the chain from the URDF root link down to the sensor link.
struct ChainStep {
  std::string joint;  // URDF joint name
  JointType type = JointType::Fixed;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // parent frame -> joint frame, q = 0
  Eigen::Vector3d axis = Eigen::Vector3d::UnitZ();           // unit joint axis, joint frame
  int joint_index = -1;                          // index in Model::upstream_joints, -1 when fixed
  double joint_scale = 1.0, joint_offset = 0.0;  // a mimic joint: as Link's
};

// The sensor's pose given by a log instead of the joints above the sensor
// link (with_sensor_pose).
enum class SensorPoseColumns { None, Quaternion, Matrix };

struct Model {
  std::string name;                // URDF robot name
  std::string source;              // file it was loaded from, for messages
  std::vector<Link> links;         // depth-first from the sensor link: parent index < own index
  std::vector<Joint> joints;       // movable joints, in the order of their links
  std::vector<MimicJoint> mimics;  // mimic joints below the sensor link
  // What the loader noticed and worked around (file:line: what, what was done).
  std::vector<std::string> warnings;
  // Joints held still at a position (hold_joints): fixed in this model.
  std::vector<std::pair<std::string, double>> held;
  // Above the sensor link (a wrist sensor): the chain from the URDF root link,
  // root first, whose last step's child is the sensor link, and its movable
  // joints (Joint::link = -1). Empty when the sensor link is the URDF root.
  // They give the sensor frame's orientation and motion (kinematics.hpp).
  std::string root_link;  // the URDF root link
  std::vector<ChainStep> upstream;
  std::vector<Joint> upstream_joints;
  // A log's pose columns instead of that chain (with_sensor_pose): not None,
  // upstream is empty and upstream_joints are the pose's columns.
  SensorPoseColumns pose = SensorPoseColumns::None;

  int num_links() const { return static_cast<int>(links.size()); }
  int num_joints() const { return static_cast<int>(joints.size()); }
  const std::string& sensor_link() const { return links.front().name; }
  int find_link(const std::string& name) const;   // -1 if absent
  int find_joint(const std::string& name) const;  // -1 if absent
  int num_upstream_joints() const { return static_cast<int>(upstream_joints.size()); }
  double nominal_total_mass() const;  // sum of the URDF link masses
};

// The model with some joints held still at the given positions (rad or m):
// they become fixed joints, so the base parameters are those such an
// experiment can determine (the paper held the PUMA's wrist). InputError for a
// name that is not a movable joint of the model.
Model hold_joints(Model model, const std::vector<std::pair<std::string, double>>& held);

// The columns of the sensor's pose in the world frame (interface.md, "The
// sensor's pose instead of joints"): the orientation, world from sensor, as a
// unit quaternion or a rotation matrix (row-major), then the origin (m).
constexpr const char* kPoseQuaternion[4] = {"qx", "qy", "qz", "qw"};
constexpr const char* kPoseMatrix[9] = {"r11", "r12", "r13", "r21", "r22",
                                        "r23", "r31", "r32", "r33"};
constexpr const char* kPosePosition[3] = {"x", "y", "z"};

// The model with the sensor's pose read from columns instead of the joints
// above the sensor link: Model::upstream emptied, Model::upstream_joints the
// pose's columns (kPoseQuaternion or kPoseMatrix, then kPosePosition when
// `position`), each a joint without limits. Every reader then binds them as
// it binds upstream joints, the motion filter differentiates them as it does
// joints, and upstream_sensor_frame turns them into gravity and the sensor
// frame's motion. Model::pose says which.
Model with_sensor_pose(Model model, SensorPoseColumns pose, bool position);

}  // namespace massid
