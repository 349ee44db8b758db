#include "massid/core/kinematics.hpp"

#include <fmt/format.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include "core/argument_checks.hpp"
#include "massid/core/errors.hpp"

namespace massid {
namespace {

// One joint of the recursion: the child's pose in its parent (R, t) at q.
struct JointPose {
  Eigen::Matrix3d R;
  Eigen::Vector3d t;
};

JointPose joint_pose(JointType type, const Eigen::Isometry3d& origin, const Eigen::Vector3d& axis,
                     double q) {
  JointPose j{origin.linear(), origin.translation()};
  if (type == JointType::Revolute) {
    const double s = std::sin(q), c = std::cos(q);
    // An axis +-e_i (most URDFs): the rotation turns the other two columns.
    for (int i = 0; i < 3; ++i) {
      const int u = (i + 1) % 3, v = (i + 2) % 3;
      if (std::abs(axis[i]) != 1.0 || axis[u] != 0.0 || axis[v] != 0.0) continue;
      const double ss = axis[i] * s;
      const Eigen::Vector3d cu = j.R.col(u), cv = j.R.col(v);
      j.R.col(u) = c * cu + ss * cv;
      j.R.col(v) = c * cv - ss * cu;
      return j;
    }
    j.R = j.R * Eigen::AngleAxisd(q, axis).toRotationMatrix();
  } else if (type == JointType::Prismatic) {
    j.t += j.R * (q * axis);
  }
  return j;
}

// The child's motion from its parent's (header: the forward recursion).
void propagate_motion(JointType type, const Eigen::Vector3d& s, const JointPose& j, double qd,
                      double qdd, const Eigen::Vector3d& wp, const Eigen::Vector3d& dwp,
                      const Eigen::Vector3d& ap, Eigen::Vector3d& w, Eigen::Vector3d& dw,
                      Eigen::Vector3d& a) {
  const auto Rt = j.R.transpose();
  w.noalias() = Rt * wp;
  dw.noalias() = Rt * dwp;
  const Eigen::Vector3d at = ap + dwp.cross(j.t) + wp.cross(wp.cross(j.t));
  a.noalias() = Rt * at;
  if (type == JointType::Revolute) {
    w += s * qd;
    dw += s * qdd + w.cross(s * qd);
  } else if (type == JointType::Prismatic) {
    a += s * qdd + 2.0 * w.cross(s * qd);
  }
}

template <bool kMotion>
void recursion(const Model& model, KinematicsData& data, const Eigen::Ref<const Eigen::VectorXd>& q,
               const double* qd, const double* qdd) {
  data.rotation[0].setIdentity();
  data.position[0].setZero();
  for (int l = 1; l < model.num_links(); ++l) {
    const Link& link = model.links[l];
    const int p = link.parent, j = link.joint_index;
    // A mimic joint follows its master: scale q_master + offset (1 and 0 otherwise).
    const double qj = j >= 0 ? link.joint_scale * q[j] + link.joint_offset : 0.0;
    const JointPose jp = joint_pose(link.type, link.origin, link.axis, qj);
    const Eigen::Matrix3d& Rp = data.rotation[p];
    data.rotation[l].noalias() = Rp * jp.R;
    data.position[l].noalias() = data.position[p] + Rp * jp.t;
    if constexpr (kMotion)
      propagate_motion(link.type, link.axis, jp, j >= 0 ? link.joint_scale * qd[j] : 0.0,
                       j >= 0 ? link.joint_scale * qdd[j] : 0.0, data.omega[p], data.omega_dot[p],
                       data.accel[p], data.omega[l], data.omega_dot[l], data.accel[l]);
  }
}

}  // namespace

KinematicsData::KinematicsData(const Model& model)
    : rotation(model.links.size(), Eigen::Matrix3d::Identity()),
      position(model.links.size(), Eigen::Vector3d::Zero()),
      omega(model.links.size(), Eigen::Vector3d::Zero()),
      omega_dot(model.links.size(), Eigen::Vector3d::Zero()),
      accel(model.links.size(), Eigen::Vector3d::Zero()) {}

void forward_kinematics(const Model& model, KinematicsData& data,
                        const Eigen::Ref<const Eigen::VectorXd>& q) {
  detail::check_size("forward_kinematics", "q", q.size(), model.num_joints(), "the model's joints");
  detail::check_size("forward_kinematics", "data", static_cast<Eigen::Index>(data.rotation.size()),
                     model.num_links(), "a workspace for the model's links");
  recursion<false>(model, data, q, nullptr, nullptr);
}

void forward_kinematics(const Model& model, KinematicsData& data,
                        const Eigen::Ref<const Eigen::VectorXd>& q,
                        const Eigen::Ref<const Eigen::VectorXd>& qd,
                        const Eigen::Ref<const Eigen::VectorXd>& qdd,
                        const Eigen::Vector3d& gravity, const FrameMotion& sensor) {
  const int n = model.num_joints();
  detail::check_size("forward_kinematics", "q", q.size(), n, "the model's joints");
  detail::check_size("forward_kinematics", "qd", qd.size(), n, "the model's joints");
  detail::check_size("forward_kinematics", "qdd", qdd.size(), n, "the model's joints");
  detail::check_size("forward_kinematics", "data", static_cast<Eigen::Index>(data.rotation.size()),
                     model.num_links(), "a workspace for the model's links");
  data.omega[0] = sensor.omega;
  data.omega_dot[0] = sensor.omega_dot;
  data.accel[0] = sensor.accel - gravity;
  recursion<true>(model, data, q, qd.data(), qdd.data());
}

Eigen::Vector3d fixed_sensor_gravity(const Model& model, const Eigen::Vector3d& root_gravity) {
  if (model.num_upstream_joints() > 0) {
    std::string names;
    for (const Joint& j : model.upstream_joints) names += (names.empty() ? "" : ", ") + j.name;
    throw InputError(fmt::format(
        "{}: sensor link '{}' is below movable joints ({}): gravity in its frame turns with "
        "them and is no single level vector; use the varying gravity model",
        model.source, model.sensor_link(), names));
  }
  const Eigen::VectorXd none(0);
  return upstream_kinematics(model, none, none, none).rotation.transpose() * root_gravity;
}

namespace {

// The sensor's pose from a log's pose columns (Model::pose), as every reader
// leaves them (normalise_pose: a matrix turned into a quaternion): qu the
// orientation qx,qy,qz,qw (world from sensor), then x,y,z when given; qdu,
// qddu their derivatives (empty: at rest). Body-frame rates of a quaternion
// q: omega = 2 Im(q* (x) qd) / |q|^2 and omega_dot = 2 Im(q* (x) qdd) / |q|^2
// (the real part of q* (x) qd is half |q|^2's rate, and d/dt Im(q* (x) qd) =
// Im(q* (x) qdd): qd* (x) qd is real; the filter's smoothed q is a unit
// quaternion only to its rounding, hence the division). The origin's
// acceleration without gravity in the sensor frame is R^T xdd.
SensorPose pose_kinematics(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& qu,
                           const Eigen::Ref<const Eigen::VectorXd>& qdu,
                           const Eigen::Ref<const Eigen::VectorXd>& qddu) {
  SensorPose out;
  const bool moving = qdu.size() > 0;
  const bool position =
      model.num_upstream_joints() > (model.pose == SensorPoseColumns::Quaternion ? 4 : 9);
  // Im(a* (x) b) for quaternions x,y,z,w: a_w b_v - b_w a_v - a_v x b_v.
  const auto im_conj_product = [](const double* a, const double* b) {
    const Eigen::Vector3d av(a[0], a[1], a[2]), bv(b[0], b[1], b[2]);
    return Eigen::Vector3d(a[3] * bv - b[3] * av - av.cross(bv));
  };
  const Eigen::Quaterniond q(qu[3], qu[0], qu[1], qu[2]);
  out.rotation = q.normalized().toRotationMatrix();
  if (moving) {
    if (!position)
      throw InputError(
          "the sensor's pose has no position columns x,y,z: in motion its origin's acceleration "
          "is unknown; add x,y,z (m, world frame)");
    const double n2 = q.squaredNorm();
    out.motion.omega = 2.0 / n2 * im_conj_product(qu.data(), qdu.data());
    out.motion.omega_dot = 2.0 / n2 * im_conj_product(qu.data(), qddu.data());
    out.motion.accel = out.rotation.transpose() * Eigen::Vector3d(qddu.segment<3>(4));
  }
  return out;
}

}  // namespace

std::string normalise_pose(SensorPoseColumns pose, int size, double* qu) {
  constexpr double tol = kPoseTolerance;
  if (pose == SensorPoseColumns::Quaternion) {
    const double n = std::sqrt(qu[0] * qu[0] + qu[1] * qu[1] + qu[2] * qu[2] + qu[3] * qu[3]);
    if (!(std::abs(n - 1.0) <= tol))
      return fmt::format(
          "columns qx,qy,qz,qw: the quaternion ({:.6g}, {:.6g}, {:.6g}, {:.6g}) has norm {:.6g}, "
          "not 1 (|norm - 1| > {:g}): not an orientation",
          qu[0], qu[1], qu[2], qu[3], n, tol);
    for (int k = 0; k < 4; ++k) qu[k] /= n;
  } else if (pose == SensorPoseColumns::Matrix) {
    using RowMajor3 = Eigen::Matrix<double, 3, 3, Eigen::RowMajor>;
    const Eigen::Matrix3d R = Eigen::Map<const RowMajor3>(qu);
    const double orth = (R.transpose() * R - Eigen::Matrix3d::Identity()).cwiseAbs().maxCoeff();
    const double det = R.determinant();
    if (!(orth <= tol) || !(std::abs(det - 1.0) <= 3 * tol))
      return fmt::format(
          "columns r11..r33: the matrix is not a rotation (R^T R - 1 up to {:.3g}, det R = {:.6g}; "
          "a rotation has 0 and 1, within {:g})",
          orth, det, tol);
    // As a quaternion: the filter then smooths and differentiates its four
    // slowly varying numbers (a matrix's nine are products of them, with
    // twice the frequencies), as for a quaternion given.
    const Eigen::Quaterniond q = Eigen::Quaterniond(R).normalized();
    double out[12] = {q.x(), q.y(), q.z(), q.w(), 0, 0, 0, 0, 0, 0, 0, 0};
    if (size > 9) std::copy_n(qu + 9, 3, out + 4);
    std::copy_n(out, size, qu);
  }
  return "";
}

void continue_pose_sign(SensorPoseColumns pose, const double* previous, double* qu, double* qdu,
                        double* qddu) {
  if (pose == SensorPoseColumns::None) return;
  const double dot =
      previous[0] * qu[0] + previous[1] * qu[1] + previous[2] * qu[2] + previous[3] * qu[3];
  if (dot < 0)
    for (double* v : {qu, qdu, qddu})
      if (v)
        for (int k = 0; k < 4; ++k) v[k] = -v[k];
}

SensorPose upstream_kinematics(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& qu,
                               const Eigen::Ref<const Eigen::VectorXd>& qdu,
                               const Eigen::Ref<const Eigen::VectorXd>& qddu) {
  const int nu = model.num_upstream_joints();
  detail::check_size("upstream_kinematics", "qu", qu.size(), nu, "the joints above the sensor");
  if (qdu.size() > 0 || qddu.size() > 0) {
    detail::check_size("upstream_kinematics", "qdu", qdu.size(), nu, "the joints above the sensor");
    detail::check_size("upstream_kinematics", "qddu", qddu.size(), nu,
                       "the joints above the sensor");
  }
  if (model.pose != SensorPoseColumns::None) return pose_kinematics(model, qu, qdu, qddu);
  SensorPose out;
  const bool moving = qdu.size() > 0;
  Eigen::Vector3d w = Eigen::Vector3d::Zero(), dw = w, a = w;
  for (const ChainStep& step : model.upstream) {
    const int j = step.joint_index;
    const JointPose jp = joint_pose(step.type, step.origin, step.axis,
                                    j >= 0 ? step.joint_scale * qu[j] + step.joint_offset : 0.0);
    out.rotation = out.rotation * jp.R;
    if (moving) {
      Eigen::Vector3d wc, dwc, ac;
      propagate_motion(step.type, step.axis, jp, j >= 0 ? step.joint_scale * qdu[j] : 0.0,
                       j >= 0 ? step.joint_scale * qddu[j] : 0.0, w, dw, a, wc, dwc, ac);
      w = wc;
      dw = dwc;
      a = ac;
    }
  }
  out.motion = {w, dw, a};
  return out;
}

void upstream_link_poses(const Model& model, const Eigen::Ref<const Eigen::VectorXd>& qu,
                         std::vector<Eigen::Isometry3d>& out) {
  detail::check_size("upstream_link_poses", "qu", qu.size(), model.num_upstream_joints(),
                     "the joints above the sensor");
  out.resize(model.upstream.size());  // none for a pose from columns (Model::pose)
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (size_t k = 0; k < model.upstream.size(); ++k) {
    const ChainStep& step = model.upstream[k];
    const int j = step.joint_index;
    const JointPose jp = joint_pose(step.type, step.origin, step.axis,
                                    j >= 0 ? step.joint_scale * qu[j] + step.joint_offset : 0.0);
    T.translation() = T.linear() * jp.t + T.translation();  // T = T [R t; 0 1], as Eigen multiplies
    T.linear() = T.linear() * jp.R;
    out[k] = T;
  }
}

void upstream_sensor_frame(const Model& model, const double* qu, const double* qdu,
                           const double* qddu, const Eigen::Vector3d& root_gravity, double* gravity,
                           double* sensor_motion) {
  using Map = Eigen::Map<const Eigen::VectorXd>;
  const int nu = model.num_upstream_joints();
  const Map none(qu, 0);
  const SensorPose pose = sensor_motion
                              ? upstream_kinematics(model, Map(qu, nu), Map(qdu, nu), Map(qddu, nu))
                              : upstream_kinematics(model, Map(qu, nu), none, none);
  if (gravity) Eigen::Map<Eigen::Vector3d>{gravity} = pose.rotation.transpose() * root_gravity;
  if (sensor_motion) {
    Eigen::Map<Eigen::Vector3d>{sensor_motion} = pose.motion.omega;
    Eigen::Map<Eigen::Vector3d>{sensor_motion + 3} = pose.motion.omega_dot;
    Eigen::Map<Eigen::Vector3d>{sensor_motion + 6} = pose.motion.accel;
  }
}

double reach(const Model& model) {
  KinematicsData kin(model);
  std::mt19937_64 rng(20261202);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  Eigen::VectorXd q(model.num_joints());
  double out = 0.0;
  for (int trial = 0; trial < 256; ++trial) {
    for (int j = 0; j < model.num_joints(); ++j) {
      const Joint& jt = model.joints[j];
      q[j] = jt.limited ? jt.lower + (jt.upper - jt.lower) * u(rng) : jt.generic_position(u(rng));
    }
    forward_kinematics(model, kin, q);
    for (int l = 0; l < model.num_links(); ++l) {
      out = std::max(out, kin.position[l].norm());
      if (model.links[l].mass > 0)
        out = std::max(out, (kin.position[l] + kin.rotation[l] * model.links[l].com).norm());
    }
  }
  return out;
}

}  // namespace massid
