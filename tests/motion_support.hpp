// Shared helpers of the motion tests (test_motion_regressor.cpp,
// test_mujoco_motion.cpp), written from the URDF model's fields alone: none of
// massid's kinematics or regressor code is used here.
//
//   SineTrajectory   q(t) = offset + sum_k a_k sin(f_k t + phi_k) per degree of
//                    freedom, with its analytic first and second derivatives.
//   FrameTrajectory  an analytic moving sensor frame (a platform with three
//                    slides then three hinges, then a fixed offset) with its
//                    pose in the world and its motion in sensor coordinates.
//   link_poses       forward kinematics by composing Isometry3d transforms.
//   momentum_wrench  the wrench that the measured bodies exert on the sensor,
//                    from finite differences in time of their momenta.
#pragma once

#include <Eigen/Geometry>
#include <array>
#include <cmath>
#include <functional>
#include <random>
#include <vector>

#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"

namespace massid::test {

using Wrench6 = Eigen::Matrix<double, 6, 1>;

inline Eigen::Matrix3d skew3(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

// The vector of the antisymmetric part of S (S = [w]x gives w).
inline Eigen::Vector3d vee(const Eigen::Matrix3d& S) {
  return 0.5 * Eigen::Vector3d(S(2, 1) - S(1, 2), S(0, 2) - S(2, 0), S(1, 0) - S(0, 1));
}

// Per degree of freedom j: x_j(t) = offset_j + sum_k amp(j,k) sin(freq(j,k) t + phase(j,k)).
struct SineTrajectory {
  Eigen::VectorXd offset;
  Eigen::MatrixXd amp, freq, phase;

  int size() const { return static_cast<int>(offset.size()); }

  // `scale[j]`: amplitude of each of the `terms` sines of dof j; frequencies
  // uniform in [0.5, max_freq] rad/s, phases uniform.
  static SineTrajectory random(const Eigen::VectorXd& offset, const Eigen::VectorXd& scale,
                               std::mt19937_64& rng, double max_freq = 3.0, int terms = 3) {
    std::uniform_real_distribution<double> u(0.0, 1.0);
    SineTrajectory s;
    s.offset = offset;
    const Eigen::Index n = offset.size();
    s.amp.resize(n, terms);
    s.freq.resize(n, terms);
    s.phase.resize(n, terms);
    for (Eigen::Index j = 0; j < n; ++j) {
      for (int k = 0; k < terms; ++k) {
        s.amp(j, k) = scale[j] * (0.5 + u(rng)) / terms;
        s.freq(j, k) = 0.5 + (max_freq - 0.5) * u(rng);
        s.phase(j, k) = 6.283185307179586 * u(rng);
      }
    }
    return s;
  }
  // Held at `value`: all derivatives zero.
  static SineTrajectory constant(const Eigen::VectorXd& value) {
    SineTrajectory s;
    s.offset = value;
    s.amp = s.freq = s.phase = Eigen::MatrixXd::Zero(value.size(), 1);
    return s;
  }

  Eigen::VectorXd q(double t) const {
    return offset +
           (amp.array() * (freq.array() * t + phase.array()).sin()).rowwise().sum().matrix();
  }
  Eigen::VectorXd qd(double t) const {
    return (amp.array() * freq.array() * (freq.array() * t + phase.array()).cos())
        .rowwise()
        .sum()
        .matrix();
  }
  Eigen::VectorXd qdd(double t) const {
    return -(amp.array() * freq.array().square() * (freq.array() * t + phase.array()).sin())
                .rowwise()
                .sum()
                .matrix();
  }
};

// A trajectory of the model's joints: revolute joints swing ~0.9 rad about a
// random angle, prismatic ones ~0.08 m about the middle of their range.
inline SineTrajectory joint_trajectory(const std::vector<Joint>& joints, std::mt19937_64& rng,
                                       double max_freq = 3.0) {
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  const Eigen::Index n = static_cast<Eigen::Index>(joints.size());
  Eigen::VectorXd offset(n), scale(n);
  for (Eigen::Index j = 0; j < n; ++j) {
    const Joint& joint = joints[static_cast<std::size_t>(j)];
    if (joint.type == JointType::Prismatic) {
      offset[j] = joint.limited ? 0.5 * (joint.lower + joint.upper) : 0.0;
      scale[j] = 0.08;
    } else {
      offset[j] = 2.0 * u(rng);
      scale[j] = 0.9;
    }
  }
  return SineTrajectory::random(offset, scale, rng, max_freq);
}

// The sensor frame in an inertial (world) frame: a platform at `base`, moved
// by three slides along fixed axes (in the base frame), then turned by three
// hinges (hinge i about its axis in the frame after hinge i-1), then the
// fixed `offset` to the sensor frame:
//   p_h = p0 + Q0 (s1 u1 + s2 u2 + s3 u3),  R_h = Q0 A1 A2 A3,  A_i = exp(th_i [a_i])
//   R_s = R_h R_m,  p_s = p_h + R_h p_m.
// dofs: s1, s2, s3, th1, th2, th3 (the order of the MuJoCo joints of the mount).
struct FrameTrajectory {
  Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
  std::array<Eigen::Vector3d, 3> slide{Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                       Eigen::Vector3d::UnitZ()};
  std::array<Eigen::Vector3d, 3> hinge{Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(),
                                       Eigen::Vector3d::UnitZ()};
  Eigen::Isometry3d offset = Eigen::Isometry3d::Identity();
  SineTrajectory dofs = SineTrajectory::constant(Eigen::VectorXd::Zero(6));

  // Non-trivial geometry; moving or held at a random tilted pose.
  static FrameTrajectory random(std::mt19937_64& rng, bool moving) {
    std::normal_distribution<double> n;
    const auto unit = [&] { return Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized(); };
    FrameTrajectory f;
    f.base.linear() = Eigen::AngleAxisd(0.7, Eigen::Vector3d(1.0, 2.0, 3.0).normalized()).matrix();
    f.base.translation() = Eigen::Vector3d(0.3, -0.2, 0.5);
    for (auto& a : f.slide) a = unit();
    for (auto& a : f.hinge) a = unit();
    f.offset.linear() =
        Eigen::AngleAxisd(-1.1, Eigen::Vector3d(-0.4, 0.5, 0.2).normalized()).matrix();
    f.offset.translation() = Eigen::Vector3d(0.05, 0.12, -0.08);
    Eigen::VectorXd off(6), scale(6);
    std::uniform_real_distribution<double> u(-1.0, 1.0);
    for (int k = 0; k < 3; ++k) {
      off[k] = 0.1 * u(rng);
      off[3 + k] = 1.5 * u(rng);
      scale[k] = 0.15;     // m
      scale[3 + k] = 0.6;  // rad
    }
    f.dofs = moving ? SineTrajectory::random(off, scale, rng, 2.5) : SineTrajectory::constant(off);
    return f;
  }

  Eigen::Matrix3d hinge_rotation(int i, double th) const {
    return Eigen::AngleAxisd(th, hinge[static_cast<std::size_t>(i)]).toRotationMatrix();
  }

  // World pose of the sensor frame at time t.
  Eigen::Isometry3d pose(double t) const {
    const Eigen::VectorXd x = dofs.q(t);
    Eigen::Isometry3d T = base;
    T.translation() += base.linear() * (x[0] * slide[0] + x[1] * slide[1] + x[2] * slide[2]);
    T.linear() =
        base.linear() * hinge_rotation(0, x[3]) * hinge_rotation(1, x[4]) * hinge_rotation(2, x[5]);
    return T * offset;
  }

  // The sensor frame's motion in sensor coordinates (kinematics.hpp's
  // FrameMotion): body angular velocity w = vee(R^T dR/dt), its derivative,
  // and R^T d2p/dt2. Derived by hand (header).
  FrameMotion motion(double t) const {
    const Eigen::VectorXd x = dofs.q(t), xd = dofs.qd(t), xdd = dofs.qdd(t);
    const Eigen::Matrix3d A2 = hinge_rotation(1, x[4]), A3 = hinge_rotation(2, x[5]);
    const Eigen::Matrix3d Rh = base.linear() * hinge_rotation(0, x[3]) * A2 * A3;
    const Eigen::Vector3d &a1 = hinge[0], &a2 = hinge[1], &a3 = hinge[2];
    // Hinge axes in the last hinge frame.
    const Eigen::Vector3d b1 = A3.transpose() * A2.transpose() * a1, b2 = A3.transpose() * a2;
    const Eigen::Vector3d w = b1 * xd[3] + b2 * xd[4] + a3 * xd[5];
    // d/dt A^T = -th' [a] A^T.
    const Eigen::Vector3d db1 =
        -xd[5] * a3.cross(b1) - xd[4] * (A3.transpose() * a2.cross(A2.transpose() * a1));
    const Eigen::Vector3d db2 = -xd[5] * a3.cross(b2);
    const Eigen::Vector3d dw = b1 * xdd[3] + b2 * xdd[4] + a3 * xdd[5] + db1 * xd[3] + db2 * xd[4];
    const Eigen::Vector3d pdd_slide =
        base.linear() * (xdd[0] * slide[0] + xdd[1] * slide[1] + xdd[2] * slide[2]);
    const Eigen::Vector3d pm = offset.translation();
    const Eigen::Vector3d a_h = Rh.transpose() * pdd_slide + dw.cross(pm) + w.cross(w.cross(pm));
    const Eigen::Matrix3d RmT = offset.linear().transpose();
    FrameMotion m;
    m.omega = RmT * w;
    m.omega_dot = RmT * dw;
    m.accel = RmT * a_h;
    return m;
  }
};

// Link poses in the model's sensor frame: T_l = T_parent * origin_l * motion_l(q).
inline std::vector<Eigen::Isometry3d> link_poses(const Model& model, const Eigen::VectorXd& q) {
  std::vector<Eigen::Isometry3d> T(static_cast<std::size_t>(model.num_links()));
  for (int l = 0; l < model.num_links(); ++l) {
    const Link& link = model.links[static_cast<std::size_t>(l)];
    if (link.parent < 0) {
      T[static_cast<std::size_t>(l)].setIdentity();
      continue;
    }
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    if (link.type == JointType::Revolute) {
      motion.rotate(Eigen::AngleAxisd(q[link.joint_index], link.axis));
    } else if (link.type == JointType::Prismatic) {
      motion.translate(q[link.joint_index] * link.axis);
    }
    T[static_cast<std::size_t>(l)] =
        T[static_cast<std::size_t>(link.parent)] * link.origin * motion;
  }
  return T;
}

// A rigid body: mass, centre of mass and inertia about it, in its own frame.
struct Body {
  double mass = 0.0;
  Eigen::Vector3d com = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about the centre of mass
};

inline std::vector<Body> bodies_of(const Model& model) {
  std::vector<Body> b;
  for (const Link& l : model.links) b.push_back({l.mass, l.com, l.inertia});
  return b;
}

// Everything at one instant: the world poses of the sensor frame and of the
// bodies (in the order of the Body list).
struct Snapshot {
  Eigen::Isometry3d sensor;
  std::vector<Eigen::Isometry3d> bodies;
};
using SnapshotFn = std::function<Snapshot(double)>;

// The wrench [f; m] that the bodies exert on the sensor at time t, in the
// sensor frame, moment about the sensor origin: weight minus the rate of change
// of momentum. World frame, fixed point O = world origin:
//   F   = sum m (g - c'')
//   M_O = sum [ c x m (g - c'') - d/dt (R I_c R^T w) ]   (d/dt m c x c' = m c x c'')
//   M_s = M_O - p_s x F,  then both rotated by R_s^T.
// c'' by the five-point second difference of the centre of mass; w from
// vee(R' R^T) with R' by the five-point first difference; d/dt of the spin
// momentum R I_c R^T w by the five-point first difference again (nine instants
// t + k h, k = -4..4). Only positions enter.
inline Wrench6 momentum_wrench(const std::vector<Body>& bodies, const SnapshotFn& at,
                               const Eigen::Vector3d& g_world, double t, double h) {
  std::array<Snapshot, 9> s;
  for (int k = -4; k <= 4; ++k) s[static_cast<std::size_t>(k + 4)] = at(t + k * h);
  const auto S = [&](int k) -> const Snapshot& { return s[static_cast<std::size_t>(k + 4)]; };
  Eigen::Vector3d F = Eigen::Vector3d::Zero(), M = Eigen::Vector3d::Zero();
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const Body& body = bodies[b];
    const auto c = [&](int k) -> Eigen::Vector3d { return S(k).bodies[b] * body.com; };
    const auto R = [&](int k) -> Eigen::Matrix3d { return S(k).bodies[b].linear(); };
    const Eigen::Vector3d cdd =
        (-c(2) + 16.0 * c(1) - 30.0 * c(0) + 16.0 * c(-1) - c(-2)) / (12.0 * h * h);
    const auto spin = [&](int k) -> Eigen::Vector3d {
      const Eigen::Matrix3d Rd =
          (R(k - 2) - 8.0 * R(k - 1) + 8.0 * R(k + 1) - R(k + 2)) / (12.0 * h);
      const Eigen::Vector3d w = vee(Rd * R(k).transpose());
      return R(k) * body.inertia * R(k).transpose() * w;
    };
    const Eigen::Vector3d dspin =
        (spin(-2) - 8.0 * spin(-1) + 8.0 * spin(1) - spin(2)) / (12.0 * h);
    const Eigen::Vector3d f = body.mass * (g_world - cdd);
    F += f;
    M += c(0).cross(f) - dspin;
  }
  const Eigen::Isometry3d& Ts = S(0).sensor;
  M -= Ts.translation().cross(F);
  Wrench6 w;
  w << Ts.linear().transpose() * F, Ts.linear().transpose() * M;
  return w;
}

// Motion of a frame from finite differences of its world pose (body
// coordinates): w = vee(R^T R'), dw = d/dt w, a = R^T p''. Five-point stencils.
inline FrameMotion frame_motion_by_differences(const std::function<Eigen::Isometry3d(double)>& pose,
                                               double t, double h) {
  const auto omega = [&](double tc) -> Eigen::Vector3d {
    const Eigen::Matrix3d Rd = (pose(tc - 2 * h).linear() - 8.0 * pose(tc - h).linear() +
                                8.0 * pose(tc + h).linear() - pose(tc + 2 * h).linear()) /
                               (12.0 * h);
    return vee(pose(tc).linear().transpose() * Rd);
  };
  const auto p = [&](double tc) -> Eigen::Vector3d { return pose(tc).translation(); };
  FrameMotion m;
  m.omega = omega(t);
  m.omega_dot =
      (omega(t - 2 * h) - 8.0 * omega(t - h) + 8.0 * omega(t + h) - omega(t + 2 * h)) / (12.0 * h);
  m.accel = pose(t).linear().transpose() *
            (-p(t + 2 * h) + 16.0 * p(t + h) - 30.0 * p(t) + 16.0 * p(t - h) - p(t - 2 * h)) /
            (12.0 * h * h);
  return m;
}

// Random inertials on every link (the sensor link too): mass 0.3..3 kg, centre
// of mass within 0.25 m, inertia about it with off-diagonal terms (random
// principal axes, principal moments obeying the triangle inequality).
inline Model with_random_inertials(Model model, std::mt19937_64& rng) {
  std::uniform_real_distribution<double> u(0.0, 1.0);
  std::normal_distribution<double> n;
  for (Link& link : model.links) {
    link.mass = 0.3 + 2.7 * u(rng);
    link.com = 0.25 * u(rng) * Eigen::Vector3d(n(rng), n(rng), n(rng)).normalized();
    const double a = 0.002 + 0.02 * u(rng), b = 0.002 + 0.02 * u(rng);
    const double c = std::abs(a - b) + (a + b - std::abs(a - b)) * (0.1 + 0.8 * u(rng));
    const Eigen::Matrix3d Q =
        Eigen::Quaterniond(n(rng), n(rng), n(rng), n(rng)).normalized().toRotationMatrix();
    link.inertia = Q * Eigen::Vector3d(a, b, c).asDiagonal() * Q.transpose();
    link.has_inertial = true;
  }
  return model;
}

}  // namespace massid::test
