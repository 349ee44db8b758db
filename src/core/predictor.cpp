#include "massid/core/predictor.hpp"

#include <Eigen/Geometry>
#include <cstring>
#include <memory>
#include <string>

#include "core/argument_checks.hpp"
#include "core/body_tree.hpp"
#include "core/predictor_plan.hpp"
#include "core/sincos.hpp"
#include "core/vector_paths.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/regressor.hpp"

// The four-lane helpers below (x86-64 only) pass 32-byte vectors by value;
// they are always inlined into the AVX2 function, so GCC's note that such a call's ABI depends
// on -mavx concerns no real call.
#pragma GCC diagnostic ignored "-Wpsabi"

namespace massid {

namespace {

using detail::axis_to_z;
using detail::depth_first;
using detail::PredictorPlan;
using detail::PredictorStep;

// A rigid body of the recursion before depth-first numbering.
struct GravityBody : detail::TreeBody {
  double mass = 0.0, subtree_mass = 0.0;                   // m_b, M_b
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();  // h_b
};

}  // namespace

Predictor compile_predictor(const Model& model, const BaseParameters& base,
                            const Eigen::Ref<const Eigen::VectorXd>& values) {
  detail::check_size("compile_predictor", "values", values.size(), base.num_unknowns(),
                     "the base parameters, then the offsets");
  Predictor out;
  out.num_joints = model.num_joints();
  auto plan = std::make_shared<PredictorPlan>();
  PredictorPlan& pred = *plan;
  // Rigid bodies, each turned so that its joint axis is z; in_body[l]: link
  // l's frame in its body's frame (axis-aligned, see header).
  detail::BodyTree<GravityBody> tree = detail::fold_fixed_links<GravityBody>(
      model, [&](GravityBody& b, int l, const Eigen::Isometry3d& to_joint) {
        const Eigen::Matrix3d C = axis_to_z(model.links[l].axis);
        b.rotation = to_joint.linear() * C;
        return Eigen::Matrix3d(C.transpose());
      });
  std::vector<GravityBody>& bodies = tree.bodies;
  const std::vector<int>& body_of = tree.body_of;
  const std::vector<Eigen::Isometry3d>& in_body = tree.in_body;
  if (base.motion())
    throw InputError(
        "the gravity predictor takes static (first-moment) base parameters; a dynamic params "
        "file needs the motion predictor (motion_predictor.hpp)");
  // Base parameter i stands for column base.column[i] of Y' (base_parameters.hpp).
  for (int i = 0; i < base.num_mass(); ++i) {
    const int c = base.column[i];
    const int l = c / kParamsPerLink, k = c % kParamsPerLink;
    const double v = values[i];
    GravityBody& b = bodies[body_of[l]];
    const Eigen::Isometry3d& T = in_body[l];
    if (c == kMass) {
      out.total_mass = v;
    } else if (k == kMass) {
      b.mass += v;  // Y'(m_l) = [0; p_l x g]
      b.first_moment += v * T.translation();
    } else {
      b.first_moment += v * T.linear().col(k - kMx);
    }
  }
  // Subtree masses, children after parents: accumulate backwards.
  for (int b = static_cast<int>(bodies.size()) - 1; b >= 0; --b) {
    bodies[b].subtree_mass += bodies[b].mass;
    if (b > 0) bodies[bodies[b].parent].subtree_mass += bodies[b].subtree_mass;
  }
  // Depth-first numbering, then the steps and the joint stage's lanes,
  // padded to a multiple of four: theta = scale q + offset for a revolute
  // joint (q's mimic map), 0 q + 0 for a prismatic one and past n.
  const std::vector<int> order = depth_first(bodies);
  std::vector<int> number(bodies.size());
  for (std::size_t k = 0; k < order.size(); ++k) number[order[k]] = static_cast<int>(k);
  const std::size_t lanes = (order.size() - 1 + 3) / 4 * 4;
  pred.lane_joint.assign(lanes, 0);
  pred.lane_scale.assign(lanes, 0.0);
  pred.lane_offset.assign(lanes, 0.0);
  for (std::size_t k = 0; k < order.size(); ++k) {
    const GravityBody& b = bodies[order[k]];
    pred.first_moment.push_back(b.first_moment);
    if (k == 0) continue;
    PredictorStep s;
    s.joint = b.joint;
    s.joint_scale = b.joint_scale;
    s.joint_offset = b.joint_offset;
    s.parent = number[b.parent];
    s.carry = s.parent == static_cast<int>(k) - 1;
    s.gathers = s.carry && bodies[b.parent].children.size() > 1;
    const Eigen::Vector3d constant =
        b.subtree_mass * b.translation +
        (s.carry ? bodies[b.parent].first_moment : Eigen::Vector3d::Zero());
    Eigen::Map<Eigen::Vector3d>(s.constant) = constant;
    if (!s.carry) Eigen::Map<Eigen::Vector3d>(s.resume) = bodies[order[k - 1]].first_moment;
    const Eigen::Matrix3d& A = b.rotation;
    for (int j = 0; j < 3; ++j) Eigen::Map<Eigen::Vector3d>(s.axes[j]) = A.col(j);
    s.row2[0] = A(2, 0), s.row2[1] = A(2, 1), s.row2[2] = A(2, 1), s.row2[3] = -A(2, 0);
    s.slide = b.type == JointType::Prismatic ? b.subtree_mass : 0.0;
    pred.steps.push_back(s);
    pred.lane_joint[k - 1] = b.joint;
    if (b.type == JointType::Revolute) {
      pred.lane_scale[k - 1] = b.joint_scale;
      pred.lane_offset[k - 1] = b.joint_offset;
    }
  }
  if (base.offset) out.offset = values.tail<6>();
  pred.four_lanes = detail::cpu_has_avx2();
  pred.num_gathered = 4 * static_cast<int>(pred.first_moment.size());
  out.plan = std::move(plan);
  return out;
}

namespace {

const PredictorPlan& plan_of(const char* function, const Predictor& predictor) {
  return detail::checked_plan(function, predictor.plan, "compile_predictor");
}

// The workspace's sizes follow from the number of bodies alone.
void check_data(const char* function, const PredictorPlan& plan, const PredictorData& data) {
  detail::check_size(function, "data.sin", static_cast<Eigen::Index>(data.sin.size()),
                     static_cast<Eigen::Index>(plan.lane_joint.size()),
                     "the predictor's joint lanes: a workspace made for another model");
  detail::check_size(function, "data.gathered", static_cast<Eigen::Index>(data.gathered.size()),
                     plan.num_gathered, "four per body: a workspace made for another model");
  detail::check_size(function, "data.cos", static_cast<Eigen::Index>(data.cos.size()),
                     static_cast<Eigen::Index>(plan.lane_joint.size()),
                     "the predictor's joint lanes: a workspace made for another model");
}

}  // namespace

PredictorData::PredictorData(const Predictor& predictor) {
  const PredictorPlan& plan = plan_of("PredictorData", predictor);
  sin.assign(plan.lane_joint.size(), 0.0);
  cos.assign(plan.lane_joint.size(), 1.0);
  gathered.assign(plan.num_gathered, 0.0);
}

namespace {

using detail::Lanes;
using detail::load;
using detail::splat;

// Joint stage: theta_k built in registers (no store-to-load round trip), then
// their sines and cosines, V's lanes at a time. Lanes past n compute sin 0.
template <class V>
[[gnu::always_inline]] inline void joint_stage(const PredictorPlan& pred, PredictorData& data,
                                               const double* q, Eigen::Index q_stride) {
  constexpr int kLanes = sizeof(V) / sizeof(double);
  const int lanes = static_cast<int>(data.sin.size());
  const int* joint = pred.lane_joint.data();
  const double* scale = pred.lane_scale.data();
  const double* offset = pred.lane_offset.data();
  for (int i = 0; i < lanes; i += kLanes) {
    V theta, s, c;
    for (int l = 0; l < kLanes; ++l)
      theta[l] = scale[i + l] * q[joint[i + l] * q_stride] + offset[i + l];
    detail::sincos_lanes(theta, s, c);
    std::memcpy(data.sin.data() + i, &s, sizeof s);
    std::memcpy(data.cos.data() + i, &c, sizeof c);
  }
}

// H(q) by the backward recursion of the header, two lanes: rows 0 and 1 of a
// 3-vector share one register, row 2 is a scalar. Both paths run it: S's x and
// y are broadcast in-lane (one cycle), where a four-lane S (x, y, z, 0) needs
// lane-crossing broadcasts on the dependent chain, 10 % slower on the whole
// call (docs/performance.md).
[[gnu::always_inline]] inline Eigen::Vector3d recursion2(const PredictorPlan& pred,
                                                         PredictorData& data, const double* q,
                                                         Eigen::Index q_stride) {
  const int n = static_cast<int>(pred.steps.size());
  const PredictorStep* steps = pred.steps.data();
  const double* sines = data.sin.data();
  const double* cosines = data.cos.data();
  double* gathered = data.gathered.data();
  // S = (xy, z): the partial sum carried along a serial run, from the last body (a leaf).
  const Eigen::Vector3d& last = pred.first_moment.back();
  Lanes xy{last.x(), last.y()};
  double z = last.z();
  for (int k = n; k >= 1; --k) {
    const PredictorStep& s = steps[k - 1];
    const Lanes c = splat<Lanes>(cosines[k - 1]), sn = splat<Lanes>(sines[k - 1]);
    const double d = s.slide * (s.joint_scale * q[s.joint * q_stride] + s.joint_offset);
    // Off the chain: B_k's columns b0, b1 (A_k's z column a2) and p = c_k (+ h_p).
    const Lanes a0 = load<Lanes>(s.axes[0]), a1 = load<Lanes>(s.axes[1]);
    const Lanes a2 = load<Lanes>(s.axes[2]);
    const Lanes b0 = a0 * c + a1 * sn, b1 = a1 * c - a0 * sn;
    const Lanes b_row2 = load<Lanes>(s.row2) * c + load<Lanes>(s.row2 + 2) * sn;
    const double a22 = s.axes[2][2];
    Lanes p01 = load<Lanes>(s.constant) + splat<Lanes>(d) * a2;
    double p2 = s.constant[2] + d * a22;
    double* g = gathered + 4 * s.parent;
    if (s.gathers) {  // p's other children, summed earlier; leave zero for the next call
      p01 += load<Lanes>(g);
      p2 += g[2];
      g[0] = g[1] = g[2] = 0.0;
    }
    // The chain: (B0 x + B1 y) + (B2 z + p), two additions deep.
    const Lanes t01 =
        (b0 * splat<Lanes>(xy[0]) + b1 * splat<Lanes>(xy[1])) + (a2 * splat<Lanes>(z) + p01);
    const Lanes r2 = b_row2 * xy;
    const double t2 = (r2[0] + r2[1]) + (a22 * z + p2);
    if (s.carry) {
      xy = t01, z = t2;
    } else {  // a branch joins its parent: gather, and restart at leaf k - 1
      g[0] += t01[0], g[1] += t01[1], g[2] += t2;
      xy = load<Lanes>(s.resume), z = s.resume[2];
    }
  }
  return {xy[0], xy[1], z};  // body 1's parent is body 0: the last step carries H
}

Eigen::Vector3d first_moment_two_lanes(const PredictorPlan& pred, PredictorData& data,
                                       const double* q, Eigen::Index q_stride) {
  joint_stage<Lanes>(pred, data, q, q_stride);
  return recursion2(pred, data, q, q_stride);
}

#if MASSID_X86
[[gnu::target("avx2")]] Eigen::Vector3d first_moment_avx2(const PredictorPlan& pred,
                                                          PredictorData& data, const double* q,
                                                          Eigen::Index q_stride) {
  joint_stage<detail::Lanes4>(pred, data, q, q_stride);
  return recursion2(pred, data, q, q_stride);
}
#endif

Eigen::Vector3d first_moment(const PredictorPlan& pred, PredictorData& data, const double* q,
                             Eigen::Index q_stride) {
#if MASSID_X86
  if (pred.four_lanes) return first_moment_avx2(pred, data, q, q_stride);
#endif
  return first_moment_two_lanes(pred, data, q, q_stride);
}

}  // namespace

Wrench predict(const Predictor& pred, PredictorData& data,
               const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Vector3d& g) {
  const PredictorPlan& plan = plan_of("predict", pred);
  check_data("predict", plan, data);
  detail::check_size("predict", "q", q.size(), pred.num_joints, "the model's joints");
  const Eigen::Vector3d H = first_moment(plan, data, q.data(), 1);
  Wrench w;
  w.head<3>() = pred.total_mass * g;
  w.tail<3>() = H.cross(g);
  return w;
}

void predict(const Predictor& pred, PredictorData& data, const Eigen::Ref<const Eigen::MatrixXd>& q,
             const Eigen::Ref<const Eigen::MatrixXd>& gravity,
             Eigen::Ref<Eigen::MatrixXd> wrenches) {
  const PredictorPlan& plan = plan_of("predict", pred);
  check_data("predict", plan, data);
  detail::check_size("predict", "q columns", q.cols(), pred.num_joints, "the model's joints");
  detail::check_size("predict", "gravity columns", gravity.cols(), 3, "gx, gy, gz");
  detail::check_size("predict", "gravity rows", gravity.rows(), q.rows(), "q's rows");
  detail::check_size("predict", "wrenches columns", wrenches.cols(), 6, "fx..mz");
  detail::check_size("predict", "wrenches rows", wrenches.rows(), q.rows(), "q's rows");
  for (Eigen::Index i = 0; i < q.rows(); ++i) {
    const Eigen::Vector3d g = gravity.row(i).transpose();
    const Eigen::Vector3d H =
        first_moment(plan, data, q.cols() > 0 ? q.data() + i : nullptr, q.outerStride());
    wrenches.row(i).head<3>() = (pred.total_mass * g).transpose();
    wrenches.row(i).tail<3>() = H.cross(g).transpose();
  }
}

}  // namespace massid
