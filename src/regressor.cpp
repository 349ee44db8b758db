#include "massid/regressor.hpp"

#include <fmt/format.h>

namespace massid {

const char* standard_parameter_kind(int param) {
  static const char* const kinds[] = {"m", "mx", "my", "mz"};
  return kinds[param];
}

std::string standard_parameter_name(const Model& model, int index) {
  return fmt::format("{}({})", standard_parameter_kind(index % kParamsPerLink),
                     model.links[index / kParamsPerLink].name);
}

Eigen::VectorXd nominal_standard_parameters(const Model& model) {
  Eigen::VectorXd pi = Eigen::VectorXd::Zero(num_standard_parameters(model));
  for (int l = 0; l < model.num_links(); ++l) {
    pi[kParamsPerLink * l + kMass] = model.links[l].mass;
    pi.segment<3>(kParamsPerLink * l + kMx) = model.links[l].mass * model.links[l].com;
  }
  return pi;
}

void standard_regressor(const Model& model, const KinematicsData& data, const Eigen::Vector3d& g,
                        Eigen::Ref<Eigen::MatrixXd> Y) {
  Y.setZero();
  for (int l = 0; l < model.num_links(); ++l) {
    const int c = kParamsPerLink * l;
    // mass column: force g, moment p_l x g
    Y.block<3, 1>(0, c + kMass) = g;
    Y.block<3, 1>(3, c + kMass) = data.position[l].cross(g);
    // first-moment columns: moment (R_l e_k) x g
    for (int k = 0; k < 3; ++k) Y.block<3, 1>(3, c + kMx + k) = data.rotation[l].col(k).cross(g);
  }
}

}  // namespace massid
