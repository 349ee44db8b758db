#include <cmath>
#include <limits>

#include "massid/core/kinematics.hpp"
#include "massid/identify/estimation.hpp"

namespace massid {

Eigen::VectorXd parameter_scales(const Model& model, const BaseParameters& base,
                                 const IdentifySummary* summary) {
  double mass = model.nominal_total_mass();
  if (summary && base.total_mass >= 0 && summary->value[base.total_mass] > 0)
    mass = summary->value[base.total_mass];
  const double length = reach(model);
  Eigen::VectorXd out(base.num_mass());
  for (int i = 0; i < base.num_mass(); ++i) {
    const std::string& unit = base.params[i].unit;
    const int power = unit == "kg" ? 0 : unit == "kg m" ? 1 : 2;
    out[i] = mass > 0 && length > 0 ? mass * std::pow(length, power)
                                    : std::numeric_limits<double>::quiet_NaN();
  }
  return out;
}

}  // namespace massid
