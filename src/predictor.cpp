#include "massid/predictor.hpp"

#include <Eigen/Geometry>

#include "massid/regressor.hpp"

namespace massid {

Predictor compile_predictor(const Model& model, const BaseParameters& base,
                            const Eigen::Ref<const Eigen::VectorXd>& values) {
  Predictor pred;
  pred.num_joints = model.num_joints();
  // Rigid bodies: a link joined by a fixed joint belongs to its parent's body.
  std::vector<int> body_of(model.num_links());
  std::vector<Eigen::Isometry3d> in_body(model.num_links());  // link frame in its body frame
  for (int l = 0; l < model.num_links(); ++l) {
    const Link& link = model.links[l];
    if (l == 0) {
      body_of[l] = 0;
      in_body[l].setIdentity();
      pred.bodies.emplace_back();
      continue;
    }
    const Eigen::Isometry3d to_joint = in_body[link.parent] * link.origin;
    if (link.type == JointType::Fixed) {
      body_of[l] = body_of[link.parent];
      in_body[l] = to_joint;
      continue;
    }
    Predictor::Body b;
    b.parent = body_of[link.parent];
    b.rotation = to_joint.linear();
    b.translation = to_joint.translation();
    b.axis = link.axis;
    b.type = link.type;
    b.joint = link.joint_index;
    body_of[l] = static_cast<int>(pred.bodies.size());
    in_body[l].setIdentity();
    pred.bodies.push_back(b);
  }
  // Base parameter i stands for column base.column[i] of Y' (base_parameters.hpp).
  for (int i = 0; i < base.num_mass(); ++i) {
    const int c = base.column[i];
    const int l = c / kParamsPerLink, k = c % kParamsPerLink;
    const double v = values[i];
    Predictor::Body& b = pred.bodies[body_of[l]];
    const Eigen::Isometry3d& T = in_body[l];
    if (c == kMass) {
      pred.total_mass = v;
    } else if (k == kMass) {
      b.mass += v;  // Y'(m_l) = [0; p_l x g]
      b.first_moment += v * T.translation();
    } else {
      b.first_moment += v * T.linear().col(k - kMx);
    }
  }
  if (base.offset) pred.offset = values.tail<6>();
  return pred;
}

PredictorData::PredictorData(const Predictor& predictor)
    : rotation(predictor.bodies.size(), Eigen::Matrix3d::Identity()),
      position(predictor.bodies.size(), Eigen::Vector3d::Zero()) {}

Wrench predict(const Predictor& pred, PredictorData& data,
               const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Vector3d& g) {
  Eigen::Vector3d H = pred.bodies[0].first_moment;
  const int nb = static_cast<int>(pred.bodies.size());
  for (int b = 1; b < nb; ++b) {
    const Predictor::Body& body = pred.bodies[b];
    const Eigen::Matrix3d& Rp = data.rotation[body.parent];
    Eigen::Matrix3d R = Rp * body.rotation;
    Eigen::Vector3d p = data.position[body.parent] + Rp * body.translation;
    if (body.type == JointType::Revolute)
      R = R * Eigen::AngleAxisd(q[body.joint], body.axis).toRotationMatrix();
    else
      p += (q[body.joint] * R) * body.axis;
    data.rotation[b] = R;
    data.position[b] = p;
    H += body.mass * p + R * body.first_moment;
  }
  Wrench w;
  w.head<3>() = pred.total_mass * g;
  w.tail<3>() = H.cross(g);
  return w + pred.offset;
}

}  // namespace massid
