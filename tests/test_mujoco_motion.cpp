// Cross-check of massid's wrench in motion (motion_regressor over
// ParameterLayout::full().nominal, forward_kinematics with velocities,
// accelerations, gravity and the sensor frame's motion) against MuJoCo's
// force/torque sensor.
//
// For every example robot the joints follow sums of sines (qpos, qvel, qacc
// analytic, motion_support.hpp). MuJoCo is driven along them by inverse
// dynamics: mj_inverse with the commanded qacc gives qfrc_inverse, which goes
// into qfrc_applied; mj_forward then reproduces the commanded qacc (checked to
// 1e-9 relative) and its <force>/<torque> sensors, on a site at the sensor
// link's origin, read the parent's wrench on the sensor link's subtree, which is
// negated to give the load on the sensor. massid gets the same q, qd, qdd, the
// gravity in sensor coordinates R_s^T g_world (g_world tilted, the mount pose
// non-trivial) and the sensor frame's motion.
//
//   Mount at rest: the sensor link is welded to a body fixed in the world in a
//     tilted pose (as test_mujoco.cpp). massid: FrameMotion zero.
//   Moving mount: the sensor link is welded (through a fixed offset) to a chain
//     of three slide and three hinge joints that massid's model does not have,
//     with its own sines for qpos, qvel, qacc. massid gets FrameTrajectory's
//     hand-derived motion of the sensor frame (omega, omega_dot, origin
//     acceleration, sensor coordinates); MuJoCo's pose of the sensor body is
//     checked against FrameTrajectory::pose first, which fixes the meaning of
//     MuJoCo's joints.
//
//   Sensor below movable joints: MuJoCo has the whole ur_like (from its root,
//     on the tilted mount) with the sensor site on one of its links; massid
//     has the URDF loaded with that link as the sensor link, the sensor
//     frame's orientation and motion from upstream_kinematics of the joints
//     above it, and gravity R^T R_mount^T g_world.
//
// The MuJoCo bodies come from massid's Model (generated MJCF, 17 digits, full
// inertia about the centre of mass: fullinertia), with the URDF's inertials and
// with random ones (off-diagonal inertia terms, mass on every link). MuJoCo's
// own diagonalisation of fullinertia (mju_eig3) is good to ~2e-7 relative
// only, which shows as ~1e-10 in the wrench: the generated models' principal
// axes and moments are set from Eigen's, exact to round-off. Or the bodies are
// MuJoCo's own import of the URDF copied into the generated model (as in
// test_mujoco.cpp; here the inertias are compared as well, since they enter
// the wrench in motion).
//
// Tolerance: |MuJoCo - massid| <= 1e-9 |w| + 1e-10 (N, N m, Euclidean norm of
// the 6-vector). Both sides are double-precision Newton-Euler with round-off
// near 1e-15 relative (observed <= 1.3e-15), and qacc is reproduced to ~1e-12
// relative; any modelling difference (a dropped Coriolis term, an inertia
// about the wrong point, a 6-digit rounding of a number) is orders of
// magnitude larger. Each case also checks that the motion changes the wrench
// by more than 1 % of |w| somewhere along the trajectory, so the comparison is
// not a static one in disguise.
#include <gtest/gtest.h>
#include <mujoco/mujoco.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <algorithm>
#include <iostream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"
#include "massid/core/parameters.hpp"
#include "massid/core/regressor.hpp"
#include "massid/io/urdf.hpp"
#include "motion_support.hpp"
#include "mujoco_support.hpp"
#include "tracker_support.hpp"

namespace {

using namespace massid::mujoco_test;
using massid::test::FrameTrajectory;
using massid::test::SineTrajectory;
using massid::test::Wrench6;

constexpr double kRelative = 1e-9;                     // of |w|
constexpr double kAbsolute = 1e-10;                    // N, N m floor
constexpr double kQaccRelative = 1e-9;                 // commanded vs reproduced qacc
constexpr int kInstants = 40;                          // sample times per trajectory
const Eigen::Vector3d kGravityWorld(0.8, -0.5, -9.7);  // tilted on purpose
const char* const kMountJoints[6] = {"massid_s1", "massid_s2", "massid_s3",
                                     "massid_r1", "massid_r2", "massid_r3"};

// A body of the mount chain: a small mass (MuJoCo wants one on moving bodies);
// it is above the sensor and does not enter the reading.
void emit_mount_body(const std::string& name, const std::string& pose, const char* type,
                     const Eigen::Vector3d& axis, const std::string& joint, const std::string& pad,
                     std::ostringstream& x) {
  x << pad << "<body name=\"" << name << "\"" << pose << ">\n"
    << pad << "  <inertial pos=\"0 0 0\" mass=\"0.5\" diaginertia=\"0.01 0.01 0.01\"/>\n"
    << pad << "  <joint name=\"" << joint << "\" type=\"" << type << "\" axis=\"" << vec(axis)
    << "\" pos=\"0 0 0\"/>\n";
}

// The body of link `index` and its subtree; the force/torque site on link `site`.
void emit_link(const massid::Model& model, int index, int depth, int site, std::ostringstream& x) {
  const massid::Link& link = model.links[static_cast<std::size_t>(index)];
  const std::string pad(static_cast<std::size_t>(2 * depth), ' ');
  x << pad << "<body name=\"" << link.name << "\" pos=\"" << vec(link.origin.translation())
    << "\" quat=\"" << quat(link.origin.linear()) << "\">\n";
  if (link.type != massid::JointType::Fixed) {
    x << pad << "  <joint name=\"" << link.joint << "\" type=\""
      << (link.type == massid::JointType::Revolute ? "hinge" : "slide") << "\" axis=\""
      << vec(link.axis) << "\" pos=\"0 0 0\"/>\n";
  }
  if (link.mass > 0.0) {
    const Eigen::Matrix3d& I = link.inertia;  // about the centre of mass, link frame
    x << pad << "  <inertial pos=\"" << vec(link.com) << "\" mass=\"" << num(link.mass)
      << "\" fullinertia=\"" << num(I(0, 0)) << " " << num(I(1, 1)) << " " << num(I(2, 2)) << " "
      << num(I(0, 1)) << " " << num(I(0, 2)) << " " << num(I(1, 2)) << "\"/>\n";
  }
  if (index == site) x << pad << "  <site name=\"ft\" pos=\"0 0 0\" quat=\"1 0 0 0\"/>\n";
  for (int child = 0; child < model.num_links(); ++child) {
    if (model.links[static_cast<std::size_t>(child)].parent == index) {
      emit_link(model, child, depth + 1, site, x);
    }
  }
  x << pad << "</body>\n";
}

// MJCF of the measured bodies, welded to "massid_mount": fixed in the world at
// the frame's pose, or at the end of the frame's slide and hinge chain. The
// force/torque sensors sit on link `site` (the sensor link unless told).
std::string mjcf_in_motion(const massid::Model& model, const FrameTrajectory& frame, bool moving,
                           int site = 0) {
  std::ostringstream x;
  x << "<mujoco model=\"" << model.name << "\">\n"
    << "  <compiler angle=\"radian\" inertiafromgeom=\"false\"/>\n"
    << "  <option gravity=\"" << vec(kGravityWorld) << "\"/>\n"
    << "  <worldbody>\n";
  int depth = 2;
  if (moving) {
    const auto pad = [&] { return std::string(static_cast<std::size_t>(2 * depth), ' '); };
    const std::string base =
        " pos=\"" + vec(frame.base.translation()) + "\" quat=\"" + quat(frame.base.linear()) + "\"";
    emit_mount_body("massid_platform", base, "slide", frame.slide[0], kMountJoints[0], pad(), x);
    ++depth;
    for (int k = 1; k < 6; ++k, ++depth) {
      emit_mount_body(std::string("massid_body") + std::to_string(k), "", k < 3 ? "slide" : "hinge",
                      k < 3 ? frame.slide[static_cast<std::size_t>(k)]
                            : frame.hinge[static_cast<std::size_t>(k - 3)],
                      kMountJoints[k], pad(), x);
    }
    x << pad() << "<body name=\"massid_mount\" pos=\"" << vec(frame.offset.translation())
      << "\" quat=\"" << quat(frame.offset.linear()) << "\">\n";
  } else {
    const Eigen::Isometry3d pose = frame.pose(0.0);
    x << "    <body name=\"massid_mount\" pos=\"" << vec(pose.translation()) << "\" quat=\""
      << quat(pose.linear()) << "\">\n";
  }
  emit_link(model, 0, depth + 1, site, x);
  for (int d = moving ? depth : 2; d >= 2; --d)
    x << std::string(static_cast<std::size_t>(2 * d), ' ') << "</body>\n";
  x << "  </worldbody>\n"
    << "  <sensor>\n"
    << "    <force name=\"ft_force\" site=\"ft\"/>\n"
    << "    <torque name=\"ft_torque\" site=\"ft\"/>\n"
    << "  </sensor>\n"
    << "</mujoco>\n";
  return x.str();
}

// MuJoCo diagonalises fullinertia iteratively (mju_eig3) to ~1e-7 relative
// only, which would show as ~1e-10 relative in the wrench of a link whose
// inertia has off-diagonal terms. Its principal moments and axes are replaced
// by Eigen's (round-off accurate). Returns MuJoCo's own relative error.
double exact_principal_axes(const massid::Model& model, mjModel* m) {
  double error = 0.0;
  for (const massid::Link& link : model.links) {
    if (!(link.mass > 0.0)) continue;
    const int b = id_of(m, mjOBJ_BODY, link.name);
    mjtNum* iq = m->body_iquat + 4 * b;
    mjtNum* id = m->body_inertia + 3 * b;
    const Eigen::Matrix3d R = Eigen::Quaterniond(iq[0], iq[1], iq[2], iq[3]).toRotationMatrix();
    const Eigen::Matrix3d I =
        R * Eigen::Map<const Eigen::Vector3d>(id).asDiagonal() * R.transpose();
    error = std::max(error, (I - link.inertia).norm() / link.inertia.norm());
    const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(link.inertia);
    Eigen::Matrix3d V = eig.eigenvectors();
    if (V.determinant() < 0.0) V.col(2) *= -1.0;
    const Eigen::Quaterniond q(V);
    iq[0] = q.w();
    iq[1] = q.x();
    iq[2] = q.y();
    iq[3] = q.z();
    for (int k = 0; k < 3; ++k) id[k] = eig.eigenvalues()[k];
  }
  return error;
}

struct MotionRobot {
  const char* name;
  const char* urdf;
};

void PrintTo(const MotionRobot& robot, std::ostream* os) { *os << robot.name; }

class MujocoMotion : public ::testing::TestWithParam<MotionRobot> {
 protected:
  void SetUp() override {
    urdf_path_ = std::string(MASSID_SOURCE_DIR) + "/" + GetParam().urdf;
    model_ = massid::load_urdf(urdf_path_);
    ASSERT_EQ(model_.sensor_link(), "sensor");
  }

  // Drives `m` along the trajectories and compares with massid for `model`.
  void run(mjModel* m, const massid::Model& model, const FrameTrajectory& frame, bool moving,
           const SineTrajectory& joints, const std::string& variant) {
    ASSERT_EQ(m->nq, model.num_joints() + (moving ? 6 : 0));
    ASSERT_EQ(m->nv, m->nq);
    std::vector<int> adr;  // qpos = qvel address of massid's joints
    for (const massid::Joint& joint : model.joints)
      adr.push_back(m->jnt_qposadr[id_of(m, mjOBJ_JOINT, joint.name)]);
    std::vector<int> mount_adr;
    if (moving)
      for (const char* name : kMountJoints)
        mount_adr.push_back(m->jnt_qposadr[id_of(m, mjOBJ_JOINT, name)]);
    const int force = id_of(m, mjOBJ_SENSOR, "ft_force");
    const int torque = id_of(m, mjOBJ_SENSOR, "ft_torque");
    ASSERT_EQ(m->sensor_type[force], mjSENS_FORCE);
    ASSERT_EQ(m->sensor_type[torque], mjSENS_TORQUE);
    const int sensor_body = id_of(m, mjOBJ_BODY, model.sensor_link());
    ASSERT_EQ(m->body_jntnum[sensor_body], 0);
    // Nothing but gravity and the applied joint forces.
    m->opt.disableflags |= mjDSBL_CONSTRAINT | mjDSBL_CONTACT | mjDSBL_PASSIVE | mjDSBL_ACTUATION;
    for (int k = 0; k < m->nv; ++k) {
      ASSERT_EQ(m->dof_damping[k], 0.0);
      ASSERT_EQ(m->dof_armature[k], 0.0);
      ASSERT_EQ(m->dof_frictionloss[k], 0.0);
    }
    for (int k = 0; k < 3; ++k) ASSERT_EQ(m->opt.gravity[k], kGravityWorld[k]);

    massid::KinematicsData kin(model);
    Eigen::MatrixXd Y(6, massid::ParameterLayout::full().size(model));
    const Eigen::VectorXd pi = massid::ParameterLayout::full().nominal(model);
    DataPtr d(mj_makeData(m));
    double max_rel = 0.0, max_abs = 0.0, max_w = 0.0, max_dyn = 0.0, max_qacc = 0.0, max_pose = 0.0;
    for (int i = 0; i < kInstants; ++i) {
      const double t = 0.0731 * i;
      const Eigen::VectorXd q = joints.q(t), qd = joints.qd(t), qdd = joints.qdd(t);
      mj_resetData(m, d.get());
      for (int j = 0; j < model.num_joints(); ++j) {
        const int a = adr[static_cast<std::size_t>(j)];
        d->qpos[a] = q[j];
        d->qvel[a] = qd[j];
        d->qacc[a] = qdd[j];
      }
      if (moving) {
        const Eigen::VectorXd x = frame.dofs.q(t), xd = frame.dofs.qd(t), xdd = frame.dofs.qdd(t);
        for (int k = 0; k < 6; ++k) {
          const int a = mount_adr[static_cast<std::size_t>(k)];
          d->qpos[a] = x[k];
          d->qvel[a] = xd[k];
          d->qacc[a] = xdd[k];
        }
      }
      const Eigen::VectorXd qacc = Eigen::Map<const Eigen::VectorXd>(d->qacc, m->nv);
      mj_inverse(m, d.get());
      mju_copy(d->qfrc_applied, d->qfrc_inverse, m->nv);
      mj_forward(m, d.get());
      const double qacc_error =
          (Eigen::Map<const Eigen::VectorXd>(d->qacc, m->nv) - qacc).norm() / (1.0 + qacc.norm());
      max_qacc = std::max(max_qacc, qacc_error);
      ASSERT_LT(qacc_error, kQaccRelative) << variant << " t = " << t;

      // MuJoCo's sensor frame is FrameTrajectory's.
      const Eigen::Isometry3d Ts = frame.pose(t);
      const Eigen::Map<const Eigen::Matrix<mjtNum, 3, 3, Eigen::RowMajor>> xmat(d->xmat +
                                                                                9 * sensor_body);
      const Eigen::Map<const Eigen::Vector3d> xpos(d->xpos + 3 * sensor_body);
      const double pose_error =
          std::max((xmat - Ts.linear()).norm(), (xpos - Ts.translation()).norm());
      max_pose = std::max(max_pose, pose_error);
      ASSERT_LT(pose_error, 1e-12) << variant << " t = " << t;

      Wrench6 mujoco;
      for (int k = 0; k < 3; ++k) {
        mujoco[k] = -d->sensordata[m->sensor_adr[force] + k];
        mujoco[3 + k] = -d->sensordata[m->sensor_adr[torque] + k];
      }
      const Eigen::Vector3d g = Ts.linear().transpose() * kGravityWorld;
      massid::forward_kinematics(model, kin, q, qd, qdd, g, frame.motion(t));
      massid::motion_regressor(model, kin, Y);
      const Wrench6 w = Y * pi;
      // The same pose at rest: how much the motion contributes.
      const Eigen::VectorXd zero = Eigen::VectorXd::Zero(model.num_joints());
      massid::forward_kinematics(model, kin, q, zero, zero, g, massid::FrameMotion{});
      massid::motion_regressor(model, kin, Y);
      const Wrench6 w_rest = Y * pi;

      const double e = (mujoco - w).norm();
      max_abs = std::max(max_abs, e);
      max_rel = std::max(max_rel, e / w.norm());
      max_w = std::max(max_w, w.norm());
      max_dyn = std::max(max_dyn, (w - w_rest).norm() / w.norm());
      EXPECT_LE(e, kRelative * w.norm() + kAbsolute)
          << variant << " t = " << t << "\nMuJoCo " << mujoco.transpose() << "\nmassid "
          << w.transpose();
    }
    std::cout << "[ mujoco   ] " << GetParam().name << " (" << variant << "): instants "
              << kInstants << ", max |w| " << num(max_w) << ", max |MuJoCo - massid| "
              << num(max_abs) << ", max relative " << num(max_rel) << ", max |w - w_at_rest|/|w| "
              << num(max_dyn) << ", max qacc error " << num(max_qacc) << ", max pose error "
              << num(max_pose) << "\n";
    RecordProperty(variant + "_max_relative", num(max_rel));
    // Not a static comparison in disguise (a robot without joints on a fixed
    // mount is static).
    if (moving || model.num_joints() > 0) {
      EXPECT_GT(max_dyn, 0.01) << variant;
    }
  }

  void run_generated(const massid::Model& model, bool moving, std::uint64_t seed,
                     const std::string& variant) {
    std::mt19937_64 rng(seed);
    const SineTrajectory joints = massid::test::joint_trajectory(model.joints, rng);
    const FrameTrajectory frame = FrameTrajectory::random(rng, moving);
    TempDir dir(std::string("motion_") + GetParam().name + "_" + std::to_string(seed));
    const fs::path path = dir.path() / "model.xml";
    write_text(path, mjcf_in_motion(model, frame, moving));
    ModelPtr m = load_mujoco(path);
    const int sensor_body = id_of(m.get(), mjOBJ_BODY, model.sensor_link());
    EXPECT_NEAR(m->body_subtreemass[sensor_body], model.nominal_total_mass(), 1e-12);
    const double diagonalisation = exact_principal_axes(model, m.get());
    std::cout << "[ mujoco   ] " << GetParam().name << " (" << variant
              << "): MuJoCo's diagonalisation of fullinertia, relative error "
              << num(diagonalisation) << " (replaced by Eigen's)\n";
    run(m.get(), model, frame, moving, joints, variant);
  }

  std::string urdf_path_;
  massid::Model model_;
};

TEST_P(MujocoMotion, GeneratedMjcfMountAtRest) {
  run_generated(model_, false, 61, "generated, mount at rest");
}

TEST_P(MujocoMotion, GeneratedMjcfMovingMount) {
  run_generated(model_, true, 62, "generated, moving mount");
}

TEST_P(MujocoMotion, GeneratedMjcfRandomInertialsMovingMount) {
  std::mt19937_64 rng(63);
  const massid::Model model = massid::test::with_random_inertials(model_, rng);
  run_generated(model, true, 64, "generated, random inertials, moving mount");
}

TEST_P(MujocoMotion, ImportedUrdfMovingMount) {
  std::mt19937_64 rng(65);
  const SineTrajectory joints = massid::test::joint_trajectory(model_.joints, rng);
  const FrameTrajectory frame = FrameTrajectory::random(rng, true);
  TempDir dir(std::string("motion_") + GetParam().name + "_imported");
  const fs::path urdf = dir.path() / "robot.urdf";
  write_text(urdf, urdf_for_mujoco(read_text(urdf_path_)));
  ModelPtr imported = load_mujoco(urdf);
  const fs::path path = dir.path() / "model.xml";
  write_text(path, mjcf_in_motion(model_, frame, true));
  ModelPtr m = load_mujoco(path);
  const double change = copy_imported_numbers(model_, imported.get(), m.get());
  // The inertia about the centre of mass in the link frame, as MuJoCo read it.
  double inertia_change = 0.0;
  for (const massid::Link& link : model_.links) {
    const int b = id_of(imported.get(), mjOBJ_BODY, link.name);
    const mjtNum* iq = imported->body_iquat + 4 * b;
    const Eigen::Matrix3d R = Eigen::Quaterniond(iq[0], iq[1], iq[2], iq[3]).toRotationMatrix();
    const Eigen::Matrix3d I =
        R * Eigen::Map<const Eigen::Vector3d>(imported->body_inertia + 3 * b).asDiagonal() *
        R.transpose();
    inertia_change = std::max(inertia_change, (I - link.inertia).cwiseAbs().maxCoeff());
  }
  std::cout << "[ mujoco   ] " << GetParam().name
            << ": largest difference between MuJoCo's and massid's reading of the URDF "
            << num(change) << " (inertias " << num(inertia_change) << ")\n";
  EXPECT_LT(change, 1e-12);
  EXPECT_LT(inertia_change, 1e-12);
  run(m.get(), model_, frame, true, joints, "imported, moving mount");
}

INSTANTIATE_TEST_SUITE_P(
    Examples, MujocoMotion,
    ::testing::Values(MotionRobot{"puma260", "examples/puma260/puma260.urdf"},
                      MotionRobot{"ur_like", "examples/ur_like/ur_like.urdf"},
                      MotionRobot{"branching", "examples/branching/branching.urdf"},
                      MotionRobot{"wrist_tool", "examples/wrist_tool/wrist_tool.urdf"}),
    [](const ::testing::TestParamInfo<MotionRobot>& info) { return std::string(info.param.name); });

// ---------------------------------------------------------------------------
// A sensor below movable joints: MuJoCo's model is the whole ur_like (loaded at
// its root, on the tilted mount at rest) with the force/torque site on one of
// its links; massid's is the URDF loaded with that link as the sensor link,
// whose frame's orientation and motion come from upstream_kinematics, gravity
// from R^T g_root with g_root = R_mount^T g_world.

class MujocoWristSensor : public ::testing::TestWithParam<const char*> {};

TEST_P(MujocoWristSensor, UpstreamJointsMatchMujoco) {
  const std::string path = std::string(MASSID_SOURCE_DIR) + "/examples/ur_like/ur_like.urdf";
  const massid::Model root = massid::load_urdf(path);
  const massid::Model wrist = massid::load_urdf(path, GetParam());
  ASSERT_EQ(wrist.num_joints() + wrist.num_upstream_joints(), root.num_joints());
  std::mt19937_64 rng(71);
  const SineTrajectory joints = massid::test::joint_trajectory(root.joints, rng);
  const FrameTrajectory frame = FrameTrajectory::random(rng, false);
  TempDir dir(std::string("motion_wrist_") + GetParam());
  const fs::path file = dir.path() / "model.xml";
  write_text(file, mjcf_in_motion(root, frame, false, root.find_link(GetParam())));
  ModelPtr m = load_mujoco(file);
  m->opt.disableflags |= mjDSBL_CONSTRAINT | mjDSBL_CONTACT | mjDSBL_PASSIVE | mjDSBL_ACTUATION;
  ASSERT_EQ(m->nv, root.num_joints());
  const int sensor_body = id_of(m.get(), mjOBJ_BODY, GetParam());
  EXPECT_NEAR(m->body_subtreemass[sensor_body], wrist.nominal_total_mass(), 1e-12);
  exact_principal_axes(root, m.get());
  const int force = id_of(m.get(), mjOBJ_SENSOR, "ft_force");
  const int torque = id_of(m.get(), mjOBJ_SENSOR, "ft_torque");
  // qpos addresses of the wrist model's joints and of its upstream joints.
  const auto addresses = [&](const std::vector<massid::Joint>& list) {
    std::vector<int> a;
    for (const massid::Joint& j : list)
      a.push_back(m->jnt_qposadr[id_of(m.get(), mjOBJ_JOINT, j.name)]);
    return a;
  };
  const std::vector<int> own = addresses(wrist.joints), up = addresses(wrist.upstream_joints);
  const std::vector<int> all = addresses(root.joints);
  const auto pick = [](const mjtNum* x, const std::vector<int>& a) {
    Eigen::VectorXd y(static_cast<Eigen::Index>(a.size()));
    for (std::size_t k = 0; k < a.size(); ++k) y[static_cast<Eigen::Index>(k)] = x[a[k]];
    return y;
  };
  const Eigen::Isometry3d mount = frame.pose(0.0);
  const Eigen::Vector3d g_root = mount.linear().transpose() * kGravityWorld;
  massid::KinematicsData kin(wrist);
  Eigen::MatrixXd Y(6, massid::ParameterLayout::full().size(wrist));
  const Eigen::VectorXd pi = massid::ParameterLayout::full().nominal(wrist);
  DataPtr d(mj_makeData(m.get()));
  double max_rel = 0.0, max_w = 0.0, max_rot = 0.0;
  for (int i = 0; i < kInstants; ++i) {
    const double t = 0.0731 * i;
    const Eigen::VectorXd q = joints.q(t), qd = joints.qd(t), qdd = joints.qdd(t);
    mj_resetData(m.get(), d.get());
    for (int j = 0; j < root.num_joints(); ++j) {
      const int a = all[static_cast<std::size_t>(j)];
      d->qpos[a] = q[j];
      d->qvel[a] = qd[j];
      d->qacc[a] = qdd[j];
    }
    const Eigen::VectorXd qacc = Eigen::Map<const Eigen::VectorXd>(d->qacc, m->nv);
    mj_inverse(m.get(), d.get());
    mju_copy(d->qfrc_applied, d->qfrc_inverse, m->nv);
    mj_forward(m.get(), d.get());
    ASSERT_LT((Eigen::Map<const Eigen::VectorXd>(d->qacc, m->nv) - qacc).norm(),
              kQaccRelative * (1.0 + qacc.norm()));
    const massid::SensorPose pose =
        massid::upstream_kinematics(wrist, pick(d->qpos, up), pick(d->qvel, up), pick(d->qacc, up));
    // The sensor link's orientation in the world: mount * upstream rotation.
    const Eigen::Map<const Eigen::Matrix<mjtNum, 3, 3, Eigen::RowMajor>> xmat(d->xmat +
                                                                              9 * sensor_body);
    const double rot = (xmat - mount.linear() * pose.rotation).norm();
    max_rot = std::max(max_rot, rot);
    ASSERT_LT(rot, 1e-12) << "t = " << t;
    Wrench6 mujoco;
    for (int k = 0; k < 3; ++k) {
      mujoco[k] = -d->sensordata[m->sensor_adr[force] + k];
      mujoco[3 + k] = -d->sensordata[m->sensor_adr[torque] + k];
    }
    massid::forward_kinematics(wrist, kin, pick(d->qpos, own), pick(d->qvel, own),
                               pick(d->qacc, own), pose.rotation.transpose() * g_root, pose.motion);
    massid::motion_regressor(wrist, kin, Y);
    const Wrench6 w = Y * pi;
    const double e = (mujoco - w).norm();
    max_rel = std::max(max_rel, e / w.norm());
    max_w = std::max(max_w, w.norm());
    EXPECT_LE(e, kRelative * w.norm() + kAbsolute)
        << "t = " << t << "\nMuJoCo " << mujoco.transpose() << "\nmassid " << w.transpose();
  }
  std::cout << "[ mujoco   ] ur_like, sensor at " << GetParam() << " ("
            << wrist.num_upstream_joints() << " joints above it): max |w| " << num(max_w)
            << ", max relative |MuJoCo - massid| " << num(max_rel) << ", max rotation error "
            << num(max_rot) << "\n";
}

INSTANTIATE_TEST_SUITE_P(UrLike, MujocoWristSensor,
                         ::testing::Values("base_link", "upper_arm_link", "wrist_2_link", "tool"),
                         [](const auto& info) { return std::string(info.param); });

// ---------------------------------------------------------------------------
// The tracker's test logs (tracker_support.hpp: massid's simulator, plus an
// object grasped and put down, drifting offsets, a contact and noise) against
// MuJoCo: the whole ur_like at its root, level gravity, with and without the
// object welded to the tool, the force/torque site on the sensor link
// (wrist_3_link, or the base link for a base sensor). Each checked row's
// reading is MuJoCo's (with the object while it is held) + the offsets + the
// contact, the world-fixed force at the tool's tip taken through MuJoCo's own
// poses of the tool and the sensor, + the noise the log recorded; it must
// equal the log's wrench to round-off.

class MujocoTrackerLog : public ::testing::TestWithParam<bool> {};

TEST_P(MujocoTrackerLog, LogIsMujocosReadingPlusOffsetsContactAndNoise) {
  namespace tt = massid::tracker_test;
  const bool wrist = GetParam();
  const tt::TrackerLog log = tt::tracker_log(wrist, 3);
  const massid::Samples& s = log.samples;
  const std::string path = std::string(MASSID_SOURCE_DIR) + "/examples/ur_like/ur_like.urdf";
  const massid::Model plain = massid::load_urdf(path);
  const massid::Model with = massid::load_urdf_string(tt::object_urdf(path), "", "ur_like+object");
  const int site = wrist ? plain.find_link("wrist_3_link") : 0;
  const std::string sensor_name = plain.links[static_cast<std::size_t>(site)].name;
  TempDir dir(std::string("tracker_") + (wrist ? "wrist" : "base"));
  std::mt19937_64 rng(5);
  const FrameTrajectory frame = FrameTrajectory::random(rng, false);
  struct Sim {
    ModelPtr m;
    DataPtr d;
  };
  const auto make = [&](const massid::Model& model, const char* name) {
    const fs::path file = dir.path() / name;
    write_text(file, mjcf_in_motion(model, frame, false, site));
    Sim sim{load_mujoco(file), nullptr};
    mjModel* m = sim.m.get();
    m->opt.disableflags |= mjDSBL_CONSTRAINT | mjDSBL_CONTACT | mjDSBL_PASSIVE | mjDSBL_ACTUATION;
    // The log's world: the arm's root at the origin, level gravity.
    const int mount = id_of(m, mjOBJ_BODY, "massid_mount");
    mju_zero(m->body_pos + 3 * mount, 3);
    mju_unit4(m->body_quat + 4 * mount);
    for (int k = 0; k < 3; ++k) m->opt.gravity[k] = massid::test::kLevel[k];
    exact_principal_axes(model, m);
    sim.d.reset(mj_makeData(m));
    return sim;
  };
  Sim sims[2] = {make(plain, "plain.xml"), make(with, "object.xml")};
  EXPECT_NEAR(sims[1].m->body_subtreemass[id_of(sims[1].m.get(), mjOBJ_BODY, sensor_name)] -
                  sims[0].m->body_subtreemass[id_of(sims[0].m.get(), mjOBJ_BODY, sensor_name)],
              tt::kObjectMass, 1e-12);
  const std::vector<massid::Joint>& joints = wrist ? log.plain.upstream_joints : log.plain.joints;
  const Eigen::MatrixXd& Q = wrist ? s.q_upstream : s.q;
  const Eigen::MatrixXd& Qd = wrist ? s.qd_upstream : s.qd;
  const Eigen::MatrixXd& Qdd = wrist ? s.qdd_upstream : s.qdd;
  ASSERT_EQ(static_cast<int>(joints.size()), 6);
  double worst = 0.0, largest = 0.0;
  int rows = 0, holding = 0, contact = 0;
  for (int i = 0; i < s.size(); i += 7) {
    const double t = s.time[i];
    Sim& sim = sims[tt::tracker_holding(t) ? 1 : 0];
    mjModel* m = sim.m.get();
    mjData* d = sim.d.get();
    mj_resetData(m, d);
    for (std::size_t j = 0; j < joints.size(); ++j) {
      const int a = m->jnt_qposadr[id_of(m, mjOBJ_JOINT, joints[j].name)];
      const auto c = static_cast<Eigen::Index>(j);
      d->qpos[a] = Q(i, c);
      d->qvel[a] = Qd(i, c);
      d->qacc[a] = Qdd(i, c);
    }
    const Eigen::VectorXd qacc = Eigen::Map<const Eigen::VectorXd>(d->qacc, m->nv);
    mj_inverse(m, d);
    mju_copy(d->qfrc_applied, d->qfrc_inverse, m->nv);
    mj_forward(m, d);
    ASSERT_LT((Eigen::Map<const Eigen::VectorXd>(d->qacc, m->nv) - qacc).norm(),
              kQaccRelative * (1.0 + qacc.norm()));
    const int force = id_of(m, mjOBJ_SENSOR, "ft_force");
    const int torque = id_of(m, mjOBJ_SENSOR, "ft_torque");
    Wrench6 expected;
    for (int k = 0; k < 3; ++k) {
      expected[k] = -d->sensordata[m->sensor_adr[force] + k];
      expected[3 + k] = -d->sensordata[m->sensor_adr[torque] + k];
    }
    expected += tt::tracker_offset(t);
    if (tt::tracker_in_contact(t)) {
      using RowMajor3 = Eigen::Matrix<mjtNum, 3, 3, Eigen::RowMajor>;
      const int tool = id_of(m, mjOBJ_BODY, "tool"), body = id_of(m, mjOBJ_BODY, sensor_name);
      const Eigen::Map<const RowMajor3> R_tool(d->xmat + 9 * tool), R_s(d->xmat + 9 * body);
      const Eigen::Map<const Eigen::Vector3d> p_tool(d->xpos + 3 * tool), p_s(d->xpos + 3 * body);
      const Eigen::Vector3d F = tt::tracker_contact_scale(t) * tt::kContactForce;
      const Eigen::Vector3d tip = p_tool + R_tool * tt::kContactPoint;
      const Eigen::Vector3d F_s = R_s.transpose() * F, r_s = R_s.transpose() * (tip - p_s);
      expected.head<3>() += F_s;
      expected.tail<3>() += r_s.cross(F_s);
      ++contact;
    }
    const Wrench6 logged = s.wrench.row(i).transpose() - log.noise.row(i).transpose();
    const double e = (logged - expected).norm();
    worst = std::max(worst, e / expected.norm());
    largest = std::max(largest, expected.norm());
    EXPECT_LE(e, kRelative * expected.norm() + kAbsolute)
        << "t = " << t << "\nMuJoCo " << expected.transpose() << "\nlog " << logged.transpose();
    ++rows;
    holding += tt::tracker_holding(t);
  }
  EXPECT_GT(holding, rows / 4);
  EXPECT_GT(contact, 100);
  std::cout << "[ mujoco   ] tracker log, " << (wrist ? "wrist" : "base") << " sensor: " << rows
            << " rows (" << holding << " holding the object, " << contact
            << " in contact), max |w| " << num(largest) << ", max relative |MuJoCo - log| "
            << num(worst) << "\n";
}

INSTANTIATE_TEST_SUITE_P(UrLike, MujocoTrackerLog, ::testing::Bool(), [](const auto& info) {
  return std::string(info.param ? "Wrist" : "Base");
});

}  // namespace
