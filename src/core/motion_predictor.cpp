#include "massid/core/motion_predictor.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <string>
#include <type_traits>

#include "core/argument_checks.hpp"
#include "core/body_tree.hpp"
#include "core/cross_matrix.hpp"
#include "core/motion_predictor_plan.hpp"
#include "core/sincos.hpp"
#include "core/vector_paths.hpp"
#include "massid/core/base_regressor.hpp"
#include "massid/core/errors.hpp"

// The four-lane helpers below (x86-64 only) pass 32-byte vectors by value;
// they are always inlined into the AVX2 function, so GCC's note that such a call's ABI depends
// on -mavx concerns no real call.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace massid {

namespace {

using detail::MotionPredictorPlan;
using detail::skew;

using detail::axis_to_z;
using detail::depth_first;

// A body whose joint axis is no axis of its parent's frame (header).
constexpr int kGeneralAxis = 3;

// Where body k's components start in an array of C per body (header).
constexpr int body_slot(int k, int C) { return (k >> 2) * 4 * C + (k & 3); }

// A rigid body before depth-first numbering.
struct InertialBody : detail::TreeBody {
  int axis = kGeneralAxis;  // 0, 1, 2: the joint axis is sign * e_axis of the parent's frame
  double sign = 1.0;
  double angle = 0.0;  // the body frame at q = 0: the parent's, turned about e_axis by this
  double mass = 0.0;
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();  // about the body origin
};

// For a link l whose body turns about axis m of its parent's frame (R: l's
// frame in that orientation): the angle about e_m that makes the axis of a
// movable link c attached to l (through fixed links) an axis of the turned
// frame, for the first such c whose axis is perpendicular to e_m; else 0.
double aligning_angle(const Model& model, int l, const Eigen::Matrix3d& R, int m) {
  const int i = (m + 1) % 3, j = (m + 2) % 3;
  for (int c = l + 1; c < model.num_links(); ++c) {
    const Link& child = model.links[c];
    if (child.type == JointType::Fixed) continue;
    Eigen::Matrix3d in_l = child.origin.linear();  // c's joint frame in l's frame
    int x = child.parent;
    while (x > l && model.links[x].type == JointType::Fixed) {
      in_l = model.links[x].origin.linear() * in_l;
      x = model.links[x].parent;
    }
    if (x != l) continue;
    const Eigen::Vector3d v = R * in_l * child.axis.normalized();
    if (std::abs(v[m]) < 1e-13) return std::atan2(v[j], v[i]);
  }
  return 0.0;
}

}  // namespace

MotionPredictor compile_motion_predictor(const Model& model, const BaseParameters& base,
                                         const Eigen::Ref<const Eigen::VectorXd>& values) {
  if (!base.motion())
    throw InputError(
        "the motion predictor takes dynamic (full-layout) base parameters; a static params file "
        "needs the gravity predictor (predictor.hpp)");
  detail::check_size("compile_motion_predictor", "values", values.size(), base.num_unknowns(),
                     "the base parameters, then the offsets");
  MotionPredictor out;
  out.num_joints = model.num_joints();
  auto plan = std::make_shared<MotionPredictorPlan>();
  MotionPredictorPlan& pred = *plan;
  const ParameterLayout& layout = base.layout;

  // Rigid bodies; in_body[l]: link l's frame in its body's frame (header).
  detail::BodyTree<InertialBody> tree = detail::fold_fixed_links<InertialBody>(
      model, [&](InertialBody& b, int l, const Eigen::Isometry3d& to_joint) -> Eigen::Matrix3d {
        // The axis in the parent body's frame: along one of its axes, the body
        // keeps the parent's orientation at q = 0 and turns about that axis.
        const Eigen::Vector3d s = to_joint.linear() * model.links[l].axis.normalized();
        int m = 0;
        s.cwiseAbs().maxCoeff(&m);
        const double sign = s[m] < 0.0 ? -1.0 : 1.0;
        if ((s - sign * Eigen::Vector3d::Unit(m)).norm() < 1e-12) {
          b.axis = m;
          b.sign = sign;
          b.rotation = axis_to_z(Eigen::Vector3d::Unit(m));  // only its z column (e_m) is used
          // The body frame may be turned about e_m by a constant angle: chosen
          // so that a child's axis is an axis of this body's frame too (a
          // mount yawed by 45 degrees, say), added to the joint angle.
          b.angle = aligning_angle(model, l, to_joint.linear(), m);
          return Eigen::AngleAxisd(-b.angle, Eigen::Vector3d::Unit(m)) * to_joint.linear();
        }
        const Eigen::Matrix3d C = axis_to_z(model.links[l].axis);
        b.rotation = to_joint.linear() * C;
        return C.transpose();  // link frame in the axis-aligned body frame
      });
  std::vector<InertialBody>& bodies = tree.bodies;
  const std::vector<int>& body_of = tree.body_of;
  const std::vector<Eigen::Isometry3d>& in_body = tree.in_body;

  // Representatives: pi'_c = value, back to standard coordinates (header).
  std::vector<Eigen::Matrix<double, 10, 1>> standard(model.num_links(),
                                                     Eigen::Matrix<double, 10, 1>::Zero());
  for (int i = 0; i < base.num_mass(); ++i) {
    const int c = base.column[i];
    const int l = layout.link_of(c), k = layout.kind_of(c);
    standard[l][k] += values[i];
    if (k == kMass && l != 0) standard[0][kMass] -= values[i];  // Y'(m_l) = Y(m_l) - Y(m_sensor)
  }
  // Fold each link into its body (header).
  for (int l = 0; l < model.num_links(); ++l) {
    const Eigen::Matrix<double, 10, 1>& p = standard[l];
    InertialBody& b = bodies[body_of[l]];
    const Eigen::Matrix3d& R = in_body[l].linear();
    const Eigen::Vector3d& t = in_body[l].translation();
    const double m = p[kMass];
    const Eigen::Vector3d Rh = R * p.segment<3>(kMx);
    Eigen::Matrix3d I;
    I << p[kIxx], p[kIxy], p[kIxz], p[kIxy], p[kIyy], p[kIyz], p[kIxz], p[kIyz], p[kIzz];
    const Eigen::Matrix3d T = skew(t), H = skew(Rh);
    b.mass += m;
    b.first_moment += Rh + m * t;
    b.inertia += R * I * R.transpose() - (T * H + H * T) - m * T * T;
  }

  // Depth-first numbering, then the structure of arrays.
  const std::vector<int> order = depth_first(bodies);
  std::vector<int> number(bodies.size());
  for (std::size_t k = 0; k < order.size(); ++k) number[order[k]] = static_cast<int>(k);
  const int nb = static_cast<int>(bodies.size());
  const int L = (nb + 3) / 4 * 4;
  out.num_bodies = pred.num_bodies = nb;
  pred.lanes = L;
  pred.parent.assign(nb, -1);
  pred.axis.assign(nb, kGeneralAxis);
  pred.general.assign(L / 4, 0);
  pred.joint.assign(L, 0);
  for (std::vector<double>* v : {&pred.revolute, &pred.angle, &pred.prismatic, &pred.slide})
    v->assign(L, 0.0);
  pred.axes.assign(9 * L, 0.0);
  pred.origin.assign(3 * L, 0.0);
  pred.inertial.assign(10 * L, 0.0);
  for (int k = 0; k < L; ++k)
    for (int i = 0; i < 3; ++i) pred.axes[body_slot(k, 9) + 4 * (4 * i)] = 1.0;  // identity
  for (int k = 0; k < nb; ++k) {
    const InertialBody& b = bodies[order[k]];
    if (k > 0) {
      pred.parent[k] = number[b.parent];
      pred.axis[k] = b.axis;
      if (b.axis == kGeneralAxis) pred.general[k / 4] = 1;
      pred.joint[k] = b.joint;
      // The joint's position is scale q + offset (a mimic joint; 1 and 0 otherwise).
      const double sigma = b.sign * b.joint_scale;
      pred.revolute[k] = b.type == JointType::Revolute ? sigma : 0.0;
      pred.prismatic[k] = b.type == JointType::Prismatic ? sigma : 0.0;
      pred.angle[k] = b.angle + (b.type == JointType::Revolute ? b.sign * b.joint_offset : 0.0);
      pred.slide[k] = b.type == JointType::Prismatic ? b.sign * b.joint_offset : 0.0;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) pred.axes[body_slot(k, 9) + 4 * (3 * i + j)] = b.rotation(i, j);
        pred.origin[body_slot(k, 3) + 4 * i] = b.translation[i];
      }
    }
    const double inertial[10] = {
        b.mass,          b.first_moment.x(), b.first_moment.y(), b.first_moment.z(),
        b.inertia(0, 0), b.inertia(0, 1),    b.inertia(0, 2),    b.inertia(1, 1),
        b.inertia(1, 2), b.inertia(2, 2)};
    for (int i = 0; i < 10; ++i) pred.inertial[body_slot(k, 10) + 4 * i] = inertial[i];
  }
  if (base.offset) out.offset = values.tail<6>();
  pred.four_lanes = detail::cpu_has_avx2();
  out.plan = std::move(plan);
  return out;
}

namespace {

const MotionPredictorPlan& plan_of(const char* function, const MotionPredictor& predictor) {
  return detail::checked_plan(function, predictor.plan, "compile_motion_predictor");
}

// Every workspace array holds a fixed number of components per body lane.
void check_data(const char* function, const MotionPredictorPlan& plan,
                const MotionPredictorData& data) {
  const auto check = [&](const char* name, const std::vector<double>& v, int per_lane) {
    detail::check_size(function, name, static_cast<Eigen::Index>(v.size()),
                       static_cast<Eigen::Index>(per_lane) * plan.lanes,
                       "a workspace made for this predictor's model");
  };
  check("data.sincos", data.sincos, 2);
  check("data.rotation", data.rotation, 9);
  check("data.translation", data.translation, 3);
  check("data.joint_rates", data.joint_rates, 4);
  check("data.motion", data.motion, 9);
  check("data.wrench", data.wrench, 6);
}

}  // namespace

MotionPredictorData::MotionPredictorData(const MotionPredictor& predictor) {
  const MotionPredictorPlan& p = plan_of("MotionPredictorData", predictor);
  sincos.assign(2 * p.lanes, 0.0);
  rotation = p.axes;
  translation = p.origin;
  joint_rates.assign(4 * p.lanes, 0.0);
  motion.assign(9 * p.lanes, 0.0);
  wrench.assign(6 * p.lanes, 0.0);
}

namespace {

using detail::Lanes;
using detail::load;  // of a double or of lanes of bodies
using detail::store;

template <class T>
struct Vec3 {
  T x, y, z;
};
template <class T>
[[gnu::always_inline]] inline Vec3<T> operator+(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.x + b.x, a.y + b.y, a.z + b.z};
}
template <class T>
[[gnu::always_inline]] inline Vec3<T> operator*(const T& s, const Vec3<T>& a) {
  return {s * a.x, s * a.y, s * a.z};
}
template <class T>
[[gnu::always_inline]] inline Vec3<T> cross(const Vec3<T>& a, const Vec3<T>& b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
// Component I of v (const or not).
template <int I, class V>
[[gnu::always_inline]] inline auto& at(V& v) {
  if constexpr (I == 0) return v.x;
  if constexpr (I == 1) return v.y;
  if constexpr (I == 2) return v.z;
}

// Rotations Rot_M(theta) about axis M (cos c, sin s) of the parent's frame:
// Rot_M^T v (into the body) and Rot_M v (out of it); the axis' component stays.
template <int M>
[[gnu::always_inline]] inline Vec3<double> turn_back(double c, double s, Vec3<double> v) {
  constexpr int i = (M + 1) % 3, j = (M + 2) % 3;
  const double vi = at<i>(v), vj = at<j>(v);
  at<i>(v) = c * vi + s * vj;
  at<j>(v) = c * vj - s * vi;
  return v;
}
template <int M>
[[gnu::always_inline]] inline Vec3<double> turn(double c, double s, Vec3<double> v) {
  constexpr int i = (M + 1) % 3, j = (M + 2) % 3;
  const double vi = at<i>(v), vj = at<j>(v);
  at<i>(v) = c * vi - s * vj;
  at<j>(v) = c * vj + s * vi;
  return v;
}
// v + (u x e_M) x_cross + e_M x_axis.
template <int M>
[[gnu::always_inline]] inline Vec3<double> add_axis(Vec3<double> v, const Vec3<double>& u,
                                                    double x_cross, double x_axis) {
  constexpr int i = (M + 1) % 3, j = (M + 2) % 3;  // u x e_M = (u_j, -u_i) at (i, j)
  at<i>(v) += at<j>(u) * x_cross;
  at<j>(v) -= at<i>(u) * x_cross;
  at<M>(v) += x_axis;
  return v;
}

// Components c, c + 1, c + 2 from a body's (or a block's) slot: stride 4.
template <class T>
[[gnu::always_inline]] inline Vec3<T> load3(const double* p, int c) {
  return {load<T>(p + 4 * c), load<T>(p + 4 * c + 4), load<T>(p + 4 * c + 8)};
}
template <class T>
[[gnu::always_inline]] inline void store3(double* p, int c, const Vec3<T>& v) {
  store(p + 4 * c, v.x);
  store(p + 4 * c + 4, v.y);
  store(p + 4 * c + 8, v.z);
}

// B v, or B^T v when Back; B row-major at a body's slot.
template <bool Back = false>
[[gnu::always_inline]] inline Vec3<double> rotate(const double* B, const Vec3<double>& v) {
  const auto b = [&](int i, int j) { return Back ? B[4 * (3 * j + i)] : B[4 * (3 * i + j)]; };
  return {(b(0, 0) * v.x + b(0, 1) * v.y) + b(0, 2) * v.z,
          (b(1, 0) * v.x + b(1, 1) * v.y) + b(1, 2) * v.z,
          (b(2, 0) * v.x + b(2, 1) * v.y) + b(2, 2) * v.z};
}

// q of the joints of V's lanes of bodies, built in registers (a vector
// written lane by lane through memory and read whole stalls the load).
template <class V>
[[gnu::always_inline]] inline V gather(const double* q, const int* joint, Eigen::Index stride) {
  if constexpr (sizeof(V) == 4 * sizeof(double))
    return V{q[joint[0] * stride], q[joint[1] * stride], q[joint[2] * stride],
             q[joint[3] * stride]};
  else
    return V{q[joint[0] * stride], q[joint[1] * stride]};
}

// Joint stage, V's lanes of bodies at a time: theta_k and d_k, their sines
// and cosines, B_k and r_k.
template <class V>
[[gnu::always_inline]] inline void joint_stage(const MotionPredictorPlan& p, MotionPredictorData& d,
                                               const double* q, const double* qd, const double* qdd,
                                               const Eigen::Index* stride) {
  constexpr int W = sizeof(V) / sizeof(double);
  for (int k = 0; k < p.lanes; k += W) {
    const int* joint = p.joint.data() + k;
    const V qk = gather<V>(q, joint, stride[0]), qdk = gather<V>(qd, joint, stride[1]);
    const V qddk = gather<V>(qdd, joint, stride[2]);
    const V revolute = load<V>(p.revolute.data() + k), prismatic = load<V>(p.prismatic.data() + k);
    const V theta = revolute * qk + load<V>(p.angle.data() + k),
            slide = prismatic * qk + load<V>(p.slide.data() + k);
    double* rates = d.joint_rates.data() + body_slot(k, 4);
    store(rates, revolute * qdk);
    store(rates + 4, revolute * qddk);
    store(rates + 8, (prismatic + prismatic) * qdk);
    store(rates + 12, prismatic * qddk);
    V s, c;
    detail::sincos_lanes(theta, s, c);
    store(d.sincos.data() + body_slot(k, 2), s);
    store(d.sincos.data() + body_slot(k, 2) + 4, c);
    const double* A = p.axes.data() + body_slot(k, 9);
    double* B = d.rotation.data() + body_slot(k, 9);
    const double* t0 = p.origin.data() + body_slot(k, 3);
    double* r = d.translation.data() + body_slot(k, 3);
    for (int i = 0; i < 3; ++i)
      store(r + 4 * i, load<V>(t0 + 4 * i) + slide * load<V>(A + 4 * (3 * i + 2)));
    if (!p.general[k / 4]) continue;  // only bodies on the general path use B_k
    for (int i = 0; i < 3; ++i) {
      const V a0 = load<V>(A + 4 * (3 * i)), a1 = load<V>(A + 4 * (3 * i + 1));
      store(B + 4 * (3 * i), a0 * c + a1 * s);
      store(B + 4 * (3 * i + 1), a1 * c - a0 * s);
    }
  }
}

// One body of the forward pass (header) from its parent's w, dw and u (its
// frame), in place. M: the body turns about axis M of its parent's frame;
// kGeneralAxis: by B_k, about its own z axis. j: the joint rates.
template <int M>
[[gnu::always_inline]] inline void forward_step(const double* B, const double* sc, const double* j,
                                                const Vec3<double>& u, Vec3<double>& w,
                                                Vec3<double>& dw, Vec3<double>& a) {
  constexpr int axis = M == kGeneralAxis ? 2 : M;
  const auto back = [&](const Vec3<double>& v) {
    if constexpr (M == kGeneralAxis)
      return rotate<true>(B, v);
    else
      return turn_back<M>(sc[4], sc[0], v);
  };
  const Vec3<double> wr = back(w), dwr = back(dw), ar = back(u);
  w = wr;
  at<axis>(w) += j[0];                       // z qd (revolute)
  dw = add_axis<axis>(dwr, wr, j[0], j[4]);  // z qdd + w' x z qd (revolute)
  a = add_axis<axis>(ar, w, j[8], j[12]);    // z qdd + 2 w x z qd (prismatic)
}

// One body of the backward pass: its share (F, N) in its parent's frame,
// from its own wrench and its carried child's share, in place.
template <int M>
[[gnu::always_inline]] inline void backward_step(const double* B, const double* sc,
                                                 const Vec3<double>& r, const double* own,
                                                 Vec3<double>& F, Vec3<double>& N) {
  const auto out = [&](const Vec3<double>& v) {
    if constexpr (M == kGeneralAxis)
      return rotate(B, v);
    else
      return turn<M>(sc[4], sc[0], v);
  };
  const Vec3<double> bf = out(load3<double>(own, 0) + F);
  const Vec3<double> bn = out(load3<double>(own, 3) + N);
  F = bf;
  N = bn + cross(r, bf);
}

// f(std::integral_constant<int, M>{}) for a body's M (0, 1, 2 or kGeneralAxis):
// the step compiled for each.
template <class F>
[[gnu::always_inline]] inline void on_axis(int axis, F&& f) {
  switch (axis) {
    case 0:
      return f(std::integral_constant<int, 0>{});
    case 1:
      return f(std::integral_constant<int, 1>{});
    case 2:
      return f(std::integral_constant<int, 2>{});
    default:
      return f(std::integral_constant<int, kGeneralAxis>{});
  }
}

// Forward pass, one body after the other (header). Along a serial run the
// parent's motion stays in registers.
[[gnu::always_inline]] inline void forward_stage(const MotionPredictorPlan& p,
                                                 MotionPredictorData& d, const Eigen::Vector3d& g,
                                                 const FrameMotion& sensor) {
  double* motion = d.motion.data();
  Vec3<double> w{sensor.omega.x(), sensor.omega.y(), sensor.omega.z()};
  Vec3<double> dw{sensor.omega_dot.x(), sensor.omega_dot.y(), sensor.omega_dot.z()};
  Vec3<double> a{sensor.accel.x() - g.x(), sensor.accel.y() - g.y(), sensor.accel.z() - g.z()};
  store3(motion, 0, w);
  store3(motion, 3, dw);
  store3(motion, 6, a);
  for (int k = 1; k < p.num_bodies; ++k) {
    const int pa = p.parent[k];
    if (pa != k - 1) {  // a branch: the parent's motion from memory
      const double* m = motion + body_slot(pa, 9);
      w = load3<double>(m, 0), dw = load3<double>(m, 3), a = load3<double>(m, 6);
    }
    const Vec3<double> r = load3<double>(d.translation.data() + body_slot(k, 3), 0);
    const Vec3<double> u = a + (cross(dw, r) + cross(w, cross(w, r)));
    const double* B = d.rotation.data() + body_slot(k, 9);
    const double* sc = d.sincos.data() + body_slot(k, 2);
    const double* j = d.joint_rates.data() + body_slot(k, 4);
    on_axis(p.axis[k], [&](auto m) { forward_step<decltype(m)::value>(B, sc, j, u, w, dw, a); });
    double* m = motion + body_slot(k, 9);
    store3(m, 0, w);
    store3(m, 3, dw);
    store3(m, 6, a);
  }
}

// Body wrenches, V's lanes of bodies at a time (header).
template <class V>
[[gnu::always_inline]] inline void wrench_stage(const MotionPredictorPlan& p,
                                                MotionPredictorData& d) {
  constexpr int W = sizeof(V) / sizeof(double);
  for (int k = 0; k < p.lanes; k += W) {
    const double* in = p.inertial.data() + body_slot(k, 10);
    const V m = load<V>(in);
    const Vec3<V> h = load3<V>(in, 1);
    const V ixx = load<V>(in + 16), ixy = load<V>(in + 20), ixz = load<V>(in + 24);
    const V iyy = load<V>(in + 28), iyz = load<V>(in + 32), izz = load<V>(in + 36);
    const auto I = [&](const Vec3<V>& v) {
      return Vec3<V>{ixx * v.x + ixy * v.y + ixz * v.z, ixy * v.x + iyy * v.y + iyz * v.z,
                     ixz * v.x + iyz * v.y + izz * v.z};
    };
    const double* mo = d.motion.data() + body_slot(k, 9);
    const Vec3<V> w = load3<V>(mo, 0), dw = load3<V>(mo, 3), a = load3<V>(mo, 6);
    const Vec3<V> f = m * a + (cross(dw, h) + cross(w, cross(w, h)));
    const Vec3<V> n = I(dw) + (cross(w, I(w)) + cross(h, a));
    double* out = d.wrench.data() + body_slot(k, 6);
    store3(out, 0, f);
    store3(out, 3, n);
  }
}

// Backward pass: subtree sums into the parents, from the last body to body 1.
// Along a serial run the child's share stays in registers (carry); where a
// branch joins, it is added to the parent's slot.
[[gnu::always_inline]] inline void backward_stage(const MotionPredictorPlan& p,
                                                  MotionPredictorData& d, double* out) {
  double* wrench = d.wrench.data();
  Vec3<double> F{0.0, 0.0, 0.0}, N{0.0, 0.0, 0.0};  // carry: child k + 1's share, body k's frame
  for (int k = p.num_bodies - 1; k >= 1; --k) {
    const double* own = wrench + body_slot(k, 6);
    const double* B = d.rotation.data() + body_slot(k, 9);
    const double* sc = d.sincos.data() + body_slot(k, 2);
    const Vec3<double> r = load3<double>(d.translation.data() + body_slot(k, 3), 0);
    on_axis(p.axis[k], [&](auto m) { backward_step<decltype(m)::value>(B, sc, r, own, F, N); });
    const int pa = p.parent[k];
    if (pa != k - 1) {  // a branch joins its parent
      double* to = wrench + body_slot(pa, 6);
      store3(to, 0, load3<double>(to, 0) + F);
      store3(to, 3, load3<double>(to, 3) + N);
      F = N = {0.0, 0.0, 0.0};
    }
  }
  const Vec3<double> F0 = load3<double>(wrench, 0) + F, N0 = load3<double>(wrench, 3) + N;
  out[0] = -F0.x, out[1] = -F0.y, out[2] = -F0.z;
  out[3] = -N0.x, out[4] = -N0.y, out[5] = -N0.z;
}

template <class V>
[[gnu::always_inline]] inline void run(const MotionPredictorPlan& p, MotionPredictorData& d,
                                       const double* q, const double* qd, const double* qdd,
                                       const Eigen::Index* stride, const Eigen::Vector3d& g,
                                       const FrameMotion& sensor, double* out) {
  joint_stage<V>(p, d, q, qd, qdd, stride);
  forward_stage(p, d, g, sensor);
  wrench_stage<V>(p, d);
  backward_stage(p, d, out);
}

void run_two_lanes(const MotionPredictorPlan& p, MotionPredictorData& d, const double* q,
                   const double* qd, const double* qdd, const Eigen::Index* stride,
                   const Eigen::Vector3d& g, const FrameMotion& sensor, double* out) {
  run<Lanes>(p, d, q, qd, qdd, stride, g, sensor, out);
}

#if MASSID_X86
[[gnu::target("avx2")]] void run_avx2(const MotionPredictorPlan& p, MotionPredictorData& d,
                                      const double* q, const double* qd, const double* qdd,
                                      const Eigen::Index* stride, const Eigen::Vector3d& g,
                                      const FrameMotion& sensor, double* out) {
  run<detail::Lanes4>(p, d, q, qd, qdd, stride, g, sensor, out);
}
#endif

// One function for both forms, so that they give the same bits.
void run_any(const MotionPredictorPlan& p, int num_joints, MotionPredictorData& d, const double* q,
             const double* qd, const double* qdd, const Eigen::Index* stride,
             const Eigen::Vector3d& g, const FrameMotion& sensor, double* out) {
  static const double kNoJoints = 0.0;  // what bodies without a joint read
  static const Eigen::Index kNoStride[3] = {0, 0, 0};
  if (num_joints == 0) q = qd = qdd = &kNoJoints, stride = kNoStride;
#if MASSID_X86
  if (p.four_lanes) return run_avx2(p, d, q, qd, qdd, stride, g, sensor, out);
#endif
  run_two_lanes(p, d, q, qd, qdd, stride, g, sensor, out);
}

// One sample from contiguous q, qd, qdd.
Wrench run_one(const MotionPredictorPlan& p, int num_joints, MotionPredictorData& d,
               const double* q, const double* qd, const double* qdd, const Eigen::Vector3d& g,
               const FrameMotion& sensor) {
  static const Eigen::Index kUnitStride[3] = {1, 1, 1};
  Wrench w;
  run_any(p, num_joints, d, q, qd, qdd, kUnitStride, g, sensor, w.data());
  return w;
}

}  // namespace

Wrench predict_motion(const MotionPredictor& predictor, MotionPredictorData& d, const double* q,
                      const double* qd, const double* qdd, const Eigen::Vector3d& g,
                      const FrameMotion& sensor) {
  const MotionPredictorPlan& p = plan_of("predict_motion", predictor);
  check_data("predict_motion", p, d);
  return run_one(p, predictor.num_joints, d, q, qd, qdd, g, sensor);
}

Wrench predict_motion(const MotionPredictor& predictor, MotionPredictorData& data,
                      const Eigen::Ref<const Eigen::VectorXd>& q,
                      const Eigen::Ref<const Eigen::VectorXd>& qd,
                      const Eigen::Ref<const Eigen::VectorXd>& qdd, const Eigen::Vector3d& g,
                      const FrameMotion& sensor) {
  const MotionPredictorPlan& p = plan_of("predict_motion", predictor);
  check_data("predict_motion", p, data);
  const Eigen::Index n = predictor.num_joints;
  detail::check_size("predict_motion", "q", q.size(), n, "the model's joints");
  detail::check_size("predict_motion", "qd", qd.size(), n, "the model's joints");
  detail::check_size("predict_motion", "qdd", qdd.size(), n, "the model's joints");
  return run_one(p, predictor.num_joints, data, q.data(), qd.data(), qdd.data(), g, sensor);
}

void predict_motion(const MotionPredictor& predictor, MotionPredictorData& d,
                    const Eigen::Ref<const Eigen::MatrixXd>& q,
                    const Eigen::Ref<const Eigen::MatrixXd>& qd,
                    const Eigen::Ref<const Eigen::MatrixXd>& qdd,
                    const Eigen::Ref<const Eigen::MatrixXd>& gravity,
                    Eigen::Ref<Eigen::MatrixXd> wrenches) {
  const MotionPredictorPlan& p = plan_of("predict_motion", predictor);
  check_data("predict_motion", p, d);
  const Eigen::Index n = predictor.num_joints, N = q.rows();
  const char* joints = "the model's joints";
  detail::check_size("predict_motion", "q columns", q.cols(), n, joints);
  detail::check_size("predict_motion", "qd columns", qd.cols(), n, joints);
  detail::check_size("predict_motion", "qdd columns", qdd.cols(), n, joints);
  detail::check_size("predict_motion", "qd rows", qd.rows(), N, "q's rows");
  detail::check_size("predict_motion", "qdd rows", qdd.rows(), N, "q's rows");
  detail::check_size("predict_motion", "gravity columns", gravity.cols(), 3, "gx, gy, gz");
  detail::check_size("predict_motion", "gravity rows", gravity.rows(), N, "q's rows");
  detail::check_size("predict_motion", "wrenches columns", wrenches.cols(), 6, "fx..mz");
  detail::check_size("predict_motion", "wrenches rows", wrenches.rows(), N, "q's rows");
  const FrameMotion rest;
  const Eigen::Index stride[3] = {q.outerStride(), qd.outerStride(), qdd.outerStride()};
  const bool any = n > 0;  // else the data may be null: run_any ignores them
  for (Eigen::Index i = 0; i < N; ++i) {
    const Eigen::Vector3d g = gravity.row(i).transpose();
    double w[6];
    run_any(p, predictor.num_joints, d, any ? q.data() + i : nullptr, any ? qd.data() + i : nullptr,
            any ? qdd.data() + i : nullptr, stride, g, rest, w);
    for (int k = 0; k < 6; ++k) wrenches(i, k) = w[k];
  }
}

Eigen::MatrixXd predict_samples(const MotionPredictor& predictor, MotionPredictorData& data,
                                const Samples& s) {
  const int nj = predictor.num_joints;
  const bool moving = nj > 0 && s.qd.cols() == nj && s.qdd.cols() == nj;
  const Eigen::MatrixXd none = Eigen::MatrixXd::Zero(s.size(), nj);
  const Eigen::MatrixXd& qd = moving ? s.qd : none;
  const Eigen::MatrixXd& qdd = moving ? s.qdd : none;
  Eigen::MatrixXd P(s.size(), 6);
  if (!s.has_sensor_motion()) {
    predict_motion(predictor, data, s.q, qd, qdd, s.gravity, P);
  } else {  // the sensor frame moves: row by row with its motion
    Eigen::VectorXd q(nj), v(nj), a(nj);
    for (int i = 0; i < s.size(); ++i) {
      q = s.q.row(i).transpose();
      v = qd.row(i).transpose();
      a = qdd.row(i).transpose();
      P.row(i) = predict_motion(predictor, data, q.data(), v.data(), a.data(),
                                s.gravity.row(i).transpose(), sensor_motion(s, i))
                     .transpose();
    }
  }
  return P;
}

}  // namespace massid
