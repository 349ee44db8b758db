#include "massid/predictor.hpp"

#include <Eigen/Geometry>

#include "massid/regressor.hpp"
#include "sincos.hpp"

namespace massid {

namespace {

// A rotation C with C e_z = axis (unit): the joint frame turned so that its
// axis is z.
Eigen::Matrix3d axis_to_z(const Eigen::Vector3d& axis) {
  return Eigen::Quaterniond::FromTwoVectors(Eigen::Vector3d::UnitZ(), axis.normalized())
      .toRotationMatrix();
}

}  // namespace

Predictor compile_predictor(const Model& model, const BaseParameters& base,
                            const Eigen::Ref<const Eigen::VectorXd>& values) {
  Predictor pred;
  pred.num_joints = model.num_joints();
  // Rigid bodies: a link joined by a fixed joint belongs to its parent's body.
  // in_body[l]: link l's frame in its body's frame (axis-aligned, see header).
  std::vector<int> body_of(model.num_links());
  std::vector<Eigen::Isometry3d> in_body(model.num_links());
  const auto add_body = [&pred](int parent, int joint, JointType type, const Eigen::Matrix3d& A,
                                const Eigen::Vector3d& t) {
    pred.parent.push_back(parent);
    pred.joint.push_back(joint);
    pred.revolute.push_back(type == JointType::Revolute ? 1.0 : 0.0);
    pred.prismatic.push_back(type == JointType::Prismatic ? 1.0 : 0.0);
    pred.rotation.push_back(A);
    pred.translation.push_back(t);
    pred.subtree_mass.push_back(0.0);
    pred.first_moment.push_back(Eigen::Vector3d::Zero());
  };
  for (int l = 0; l < model.num_links(); ++l) {
    const Link& link = model.links[l];
    if (l == 0) {
      body_of[l] = 0;
      in_body[l].setIdentity();
      add_body(-1, 0, JointType::Fixed, Eigen::Matrix3d::Identity(), Eigen::Vector3d::Zero());
      continue;
    }
    const Eigen::Isometry3d to_joint = in_body[link.parent] * link.origin;
    if (link.type == JointType::Fixed) {
      body_of[l] = body_of[link.parent];
      in_body[l] = to_joint;
      continue;
    }
    const Eigen::Matrix3d C = axis_to_z(link.axis);
    body_of[l] = pred.num_bodies();
    add_body(body_of[link.parent], link.joint_index, link.type, to_joint.linear() * C,
             to_joint.translation());
    in_body[l].setIdentity();
    in_body[l].linear() = C.transpose();  // link frame in the axis-aligned body frame
  }
  // Base parameter i stands for column base.column[i] of Y' (base_parameters.hpp).
  std::vector<double> mass(pred.parent.size(), 0.0);
  for (int i = 0; i < base.num_mass(); ++i) {
    const int c = base.column[i];
    const int l = c / kParamsPerLink, k = c % kParamsPerLink;
    const double v = values[i];
    const int b = body_of[l];
    const Eigen::Isometry3d& T = in_body[l];
    if (c == kMass) {
      pred.total_mass = v;
    } else if (k == kMass) {
      mass[b] += v;  // Y'(m_l) = [0; p_l x g]
      pred.first_moment[b] += v * T.translation();
    } else {
      pred.first_moment[b] += v * T.linear().col(k - kMx);
    }
  }
  // Subtree masses, children after parents: accumulate backwards.
  for (int b = pred.num_bodies() - 1; b >= 0; --b) {
    pred.subtree_mass[b] += mass[b];
    if (b > 0) pred.subtree_mass[pred.parent[b]] += pred.subtree_mass[b];
  }
  if (base.offset) pred.offset = values.tail<6>();
  return pred;
}

namespace {
// Movable bodies, rounded up to even for the two-lane sincos.
std::size_t lanes_for(const Predictor& p) { return (p.parent.size() - 1 + 1) / 2 * 2; }
}  // namespace

PredictorData::PredictorData(const Predictor& predictor)
    : theta(lanes_for(predictor), 0.0),
      sin(lanes_for(predictor), 0.0),
      cos(lanes_for(predictor), 1.0),
      subtree(predictor.parent.size(), Eigen::Vector3d::Zero()) {}

namespace {

// H(q) by the backward recursion of the header.
Eigen::Vector3d first_moment(const Predictor& pred, PredictorData& data, const double* q,
                             Eigen::Index q_stride) {
  const int nb = pred.num_bodies();
  for (int b = 1; b < nb; ++b) data.theta[b - 1] = pred.revolute[b] * q[pred.joint[b] * q_stride];
  detail::sincos_many(data.theta.data(), data.sin.data(), data.cos.data(),
                      static_cast<int>(data.theta.size()));
  for (int b = 0; b < nb; ++b) data.subtree[b] = pred.first_moment[b];
  for (int b = nb - 1; b > 0; --b) {
    const Eigen::Vector3d& S = data.subtree[b];
    const double c = data.cos[b - 1], s = data.sin[b - 1], m = pred.subtree_mass[b];
    const Eigen::Vector3d v(c * S.x() - s * S.y(), s * S.x() + c * S.y(),
                            S.z() + m * pred.prismatic[b] * q[pred.joint[b] * q_stride]);
    data.subtree[pred.parent[b]] += m * pred.translation[b] + pred.rotation[b] * v;
  }
  return data.subtree[0];
}

}  // namespace

Wrench predict(const Predictor& pred, PredictorData& data,
               const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Vector3d& g) {
  const Eigen::Vector3d H = first_moment(pred, data, q.data(), 1);
  Wrench w;
  w.head<3>() = pred.total_mass * g + pred.offset.head<3>();
  w.tail<3>() = H.cross(g) + pred.offset.tail<3>();
  return w;
}

void predict(const Predictor& pred, PredictorData& data, const Eigen::Ref<const Eigen::MatrixXd>& q,
             const Eigen::Ref<const Eigen::MatrixXd>& gravity,
             Eigen::Ref<Eigen::MatrixXd> wrenches) {
  for (Eigen::Index i = 0; i < q.rows(); ++i) {
    const Eigen::Vector3d g = gravity.row(i).transpose();
    const Eigen::Vector3d H = first_moment(pred, data, q.data() + i, q.outerStride());
    wrenches.row(i).head<3>() = (pred.total_mass * g + pred.offset.head<3>()).transpose();
    wrenches.row(i).tail<3>() = (H.cross(g) + pred.offset.tail<3>()).transpose();
  }
}

}  // namespace massid
