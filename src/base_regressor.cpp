#include "massid/base_regressor.hpp"

#include "massid/regressor.hpp"

namespace massid {

RegressorData::RegressorData(const Model& model, const BaseParameters& base)
    : kinematics(model),
      standard(6, num_standard_parameters(model)),
      base(6, base.num_unknowns()) {}

void base_regressor(const Model& model, const BaseParameters& base, RegressorData& data,
                    const Eigen::Ref<const Eigen::VectorXd>& q, const Eigen::Vector3d& g) {
  forward_kinematics(model, data.kinematics, q);
  standard_regressor(model, data.kinematics, g, data.standard);
  for (int i = 0; i < base.num_mass(); ++i) {
    const int c = base.column[i];
    data.base.col(i) = data.standard.col(c);
    // Y'(m_l) = Y(m_l) - Y(m_sensor) for links other than the sensor (c != 0).
    if (c % kParamsPerLink == kMass && c != kMass) data.base.col(i) -= data.standard.col(kMass);
  }
  if (base.offset) data.base.rightCols<6>().setIdentity();
}

}  // namespace massid
