#include "massid/emulator/spacecraft.hpp"

#include <Eigen/Eigenvalues>
#include <cmath>
#include <string>

#include "massid/core/errors.hpp"

namespace massid::emulator {
namespace {

// Rotation vector (axis * angle, angle in [0, pi]) of a unit quaternion; smooth
// through the identity.
Eigen::Vector3d rotation_vector(const Eigen::Quaterniond& q) {
  const double sign = q.w() < 0.0 ? -1.0 : 1.0;
  const Eigen::Vector3d v = sign * q.vec();
  const double w = sign * q.w();
  const double n = v.norm();
  if (n < 1e-8) return (2.0 / w) * v;  // 2 atan(n/w)/n = 2/w (1 + O(n^2))
  return (2.0 * std::atan2(n, w) / n) * v;
}

// Time derivative of the state: the same layout as SpacecraftState, the
// quaternion rate as the coefficients of q'.
struct Derivative {
  Eigen::Vector3d position;
  Eigen::Vector4d orientation;  // (x, y, z, w) as Eigen's coeffs()
  Eigen::Vector3d linear_velocity;
  Eigen::Vector3d angular_velocity;
};

Derivative derivative(const SpacecraftParameters& p, const Eigen::Matrix3d& inertia_inverse,
                      const SpacecraftState& s, const Wrench& wrench_interface) {
  Derivative d;
  d.position = s.linear_velocity;
  // q' = 1/2 q (x) (0, w_b); q need not be unit within an RK4 step.
  const Eigen::Quaterniond omega(0.0, s.angular_velocity.x(), s.angular_velocity.y(),
                                 s.angular_velocity.z());
  d.orientation = 0.5 * (s.orientation * omega).coeffs();

  const Wrench w = wrench_interface + compliance_wrench(p, s);
  const Eigen::Matrix3d r_wb = s.orientation.normalized().toRotationMatrix();
  const Eigen::Matrix3d r_bi = p.body_T_interface.linear();
  const Eigen::Vector3d r = p.body_T_interface.translation();
  const Eigen::Vector3d f_body = r_bi * w.head<3>();
  const Eigen::Vector3d tau_body = r.cross(f_body) + r_bi * w.tail<3>();
  d.linear_velocity = (r_wb * f_body) / p.mass;
  const Eigen::Vector3d& wb = s.angular_velocity;
  d.angular_velocity = inertia_inverse * (tau_body - wb.cross(p.inertia * wb));
  return d;
}

// s + h * d, without renormalising the quaternion.
SpacecraftState advance(const SpacecraftState& s, const Derivative& d, double h) {
  SpacecraftState out;
  out.position = s.position + h * d.position;
  out.orientation.coeffs() = s.orientation.coeffs() + h * d.orientation;
  out.linear_velocity = s.linear_velocity + h * d.linear_velocity;
  out.angular_velocity = s.angular_velocity + h * d.angular_velocity;
  return out;
}

template <typename Derived>
bool finite(const Eigen::MatrixBase<Derived>& m) {
  return m.allFinite();
}

}  // namespace

void validate(const SpacecraftParameters& p) {
  if (!(std::isfinite(p.mass) && p.mass > 0.0))
    throw InputError("spacecraft: mass must be positive and finite, got " + std::to_string(p.mass));
  if (!finite(p.inertia)) throw InputError("spacecraft: inertia has a non-finite entry");
  if ((p.inertia - p.inertia.transpose()).cwiseAbs().maxCoeff() >
      1e-9 * (1.0 + p.inertia.cwiseAbs().maxCoeff()))
    throw InputError("spacecraft: inertia is not symmetric");
  const Eigen::Vector3d moments =
      Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(p.inertia, Eigen::EigenvaluesOnly)
          .eigenvalues();  // ascending
  if (!(moments[0] > 0.0)) throw InputError("spacecraft: inertia is not positive definite");
  if (moments[0] + moments[1] < moments[2] * (1.0 - 1e-9))
    throw InputError("spacecraft: principal moments of inertia violate the triangle inequality");
  if (!finite(p.body_T_interface.matrix()) || !p.body_T_interface.linear().isUnitary(1e-9))
    throw InputError("spacecraft: body_T_interface is not a rigid transform");
  if (!finite(p.world_T_anchor.matrix()) || !p.world_T_anchor.linear().isUnitary(1e-9))
    throw InputError("spacecraft: world_T_anchor is not a rigid transform");
  if (!finite(p.stiffness) || !finite(p.damping))
    throw InputError("spacecraft: stiffness or damping has a non-finite entry");
}

SpacecraftState state_at_rest(const SpacecraftParameters& params,
                              const Eigen::Isometry3d& world_T_interface) {
  const Eigen::Isometry3d world_T_body = world_T_interface * params.body_T_interface.inverse();
  SpacecraftState s;
  s.position = world_T_body.translation();
  s.orientation = Eigen::Quaterniond(world_T_body.linear()).normalized();
  return s;
}

Eigen::Isometry3d body_pose(const SpacecraftState& state) {
  Eigen::Isometry3d t = Eigen::Isometry3d::Identity();
  t.linear() = state.orientation.normalized().toRotationMatrix();
  t.translation() = state.position;
  return t;
}

Eigen::Isometry3d interface_pose(const SpacecraftParameters& params, const SpacecraftState& state) {
  return body_pose(state) * params.body_T_interface;
}

Twist interface_twist(const SpacecraftParameters& params, const SpacecraftState& state) {
  const Eigen::Matrix3d r_wb = state.orientation.normalized().toRotationMatrix();
  const Eigen::Vector3d& r = params.body_T_interface.translation();
  Twist t;
  t.head<3>() = state.linear_velocity + r_wb * state.angular_velocity.cross(r);
  t.tail<3>() = r_wb * state.angular_velocity;
  return t;
}

Wrench compliance_wrench(const SpacecraftParameters& params, const SpacecraftState& state) {
  if (params.stiffness.isZero(0.0) && params.damping.isZero(0.0)) return Wrench::Zero();
  const Eigen::Isometry3d world_T_interface = interface_pose(params, state);
  const Eigen::Matrix3d r_wa = params.world_T_anchor.linear();
  const Eigen::Matrix3d r_ai = r_wa.transpose() * world_T_interface.linear();
  Eigen::Matrix<double, 6, 1> displacement;
  displacement.head<3>() =
      r_wa.transpose() * (world_T_interface.translation() - params.world_T_anchor.translation());
  displacement.tail<3>() = rotation_vector(Eigen::Quaterniond(r_ai));
  const Twist twist_world = interface_twist(params, state);
  Eigen::Matrix<double, 6, 1> rate;
  rate.head<3>() = r_wa.transpose() * twist_world.head<3>();
  rate.tail<3>() = r_wa.transpose() * twist_world.tail<3>();
  const Eigen::Matrix<double, 6, 1> w_anchor =
      -(params.stiffness * displacement) - params.damping * rate;
  Wrench w;
  w.head<3>() = r_ai.transpose() * w_anchor.head<3>();
  w.tail<3>() = r_ai.transpose() * w_anchor.tail<3>();
  return w;
}

SpacecraftAcceleration acceleration(const SpacecraftParameters& params,
                                    const SpacecraftState& state, const Wrench& wrench_interface) {
  const Derivative d = derivative(params, params.inertia.inverse(), state, wrench_interface);
  SpacecraftAcceleration a;
  a.linear = d.linear_velocity;
  a.angular = d.angular_velocity;
  return a;
}

void step(const SpacecraftParameters& params, SpacecraftState& state,
          const Wrench& wrench_interface, double dt) {
  const Eigen::Matrix3d inertia_inverse = params.inertia.inverse();
  const Derivative k1 = derivative(params, inertia_inverse, state, wrench_interface);
  const Derivative k2 =
      derivative(params, inertia_inverse, advance(state, k1, 0.5 * dt), wrench_interface);
  const Derivative k3 =
      derivative(params, inertia_inverse, advance(state, k2, 0.5 * dt), wrench_interface);
  const Derivative k4 =
      derivative(params, inertia_inverse, advance(state, k3, dt), wrench_interface);
  const double h = dt / 6.0;
  state.position += h * (k1.position + 2.0 * k2.position + 2.0 * k3.position + k4.position);
  state.orientation.coeffs() +=
      h * (k1.orientation + 2.0 * k2.orientation + 2.0 * k3.orientation + k4.orientation);
  state.orientation.normalize();
  state.linear_velocity += h * (k1.linear_velocity + 2.0 * k2.linear_velocity +
                                2.0 * k3.linear_velocity + k4.linear_velocity);
  state.angular_velocity += h * (k1.angular_velocity + 2.0 * k2.angular_velocity +
                                 2.0 * k3.angular_velocity + k4.angular_velocity);
}

Eigen::Vector3d linear_momentum(const SpacecraftParameters& params, const SpacecraftState& state) {
  return params.mass * state.linear_velocity;
}

Eigen::Vector3d angular_momentum(const SpacecraftParameters& params, const SpacecraftState& state) {
  return state.orientation.normalized().toRotationMatrix() *
         (params.inertia * state.angular_velocity);
}

Eigen::Vector3d angular_momentum(const SpacecraftParameters& params, const SpacecraftState& state,
                                 const Eigen::Vector3d& point) {
  return angular_momentum(params, state) +
         (state.position - point).cross(params.mass * state.linear_velocity);
}

double kinetic_energy(const SpacecraftParameters& params, const SpacecraftState& state) {
  return 0.5 * params.mass * state.linear_velocity.squaredNorm() +
         0.5 * state.angular_velocity.dot(params.inertia * state.angular_velocity);
}

}  // namespace massid::emulator
