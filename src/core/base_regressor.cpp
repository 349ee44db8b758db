#include "massid/core/base_regressor.hpp"

#include "core/argument_checks.hpp"
#include "massid/core/regressor.hpp"

namespace massid {
namespace {

// Y_b from the standard regressor in data.standard.
void reduce(const BaseParameters& base, RegressorData& data) {
  const int P = base.layout.per_link();
  for (int i = 0; i < base.num_mass(); ++i) {
    const int c = base.column[i];
    data.base.col(i) = data.standard.col(c);
    // Y'(m_l) = Y(m_l) - Y(m_sensor) for links other than the sensor (c != 0).
    if (c % P == kMass && c != kMass) data.base.col(i) -= data.standard.col(kMass);
  }
  if (base.offset) data.base.rightCols<6>().setIdentity();
}

}  // namespace

RegressorData::RegressorData(const Model& model, const BaseParameters& base)
    : kinematics(model), standard(6, base.layout.size(model)), base(6, base.num_unknowns()) {}

void base_regressor(const Model& model, const BaseParameters& base, RegressorData& data,
                    const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Vector3d& g) {
  detail::check_size("base_regressor", "q", q.size(), model.num_joints(), "the model's joints");
  if (base.motion()) {
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(q.size());
    base_regressor(model, base, data, q, zero, zero, g, FrameMotion{});
    return;
  }
  forward_kinematics(model, data.kinematics, q);
  standard_regressor(model, data.kinematics, g, data.standard);
  reduce(base, data);
}

void base_regressor(const Model& model, const BaseParameters& base, RegressorData& data,
                    const Eigen::Ref<const Eigen::VectorXd>& q,
                    const Eigen::Ref<const Eigen::VectorXd>& qd,
                    const Eigen::Ref<const Eigen::VectorXd>& qdd, const Eigen::Vector3d& g,
                    const FrameMotion& sensor) {
  const int n = model.num_joints();
  detail::check_size("base_regressor", "q", q.size(), n, "the model's joints");
  detail::check_size("base_regressor", "qd", qd.size(), n, "the model's joints");
  detail::check_size("base_regressor", "qdd", qdd.size(), n, "the model's joints");
  forward_kinematics(model, data.kinematics, q, qd, qdd, g, sensor);
  motion_regressor(model, data.kinematics, data.standard);
  reduce(base, data);
}

FrameMotion sensor_motion(const Samples& s, int i) {
  if (!s.has_sensor_motion()) return {};
  const auto m = s.sensor_motion.row(i);
  return {m.segment<3>(0).transpose(), m.segment<3>(3).transpose(), m.segment<3>(6).transpose()};
}

void base_regressor(const Model& model, const BaseParameters& base, RegressorData& data,
                    const Samples& s, int i) {
  detail::check_index("base_regressor", "sample", i, s.size());
  const Eigen::Vector3d g = s.gravity.row(i).transpose();
  if (!base.motion()) {
    base_regressor(model, base, data, s.q.row(i).transpose(), g);
    return;
  }
  const Eigen::Index nj = s.q.cols();
  const Eigen::VectorXd zero = Eigen::VectorXd::Zero(nj);
  const bool moving = nj > 0 && s.qd.cols() == nj && s.qdd.cols() == nj;
  base_regressor(model, base, data, s.q.row(i).transpose(),
                 moving ? Eigen::VectorXd(s.qd.row(i).transpose()) : zero,
                 moving ? Eigen::VectorXd(s.qdd.row(i).transpose()) : zero, g, sensor_motion(s, i));
}

}  // namespace massid
