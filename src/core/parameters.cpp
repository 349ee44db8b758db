#include "massid/core/parameters.hpp"

#include <fmt/format.h>

namespace massid {
namespace {
const char* const kKinds[] = {"m", "mx", "my", "mz", "ixx", "ixy", "ixz", "iyy", "iyz", "izz"};
}

const char* ParameterLayout::kind_name(int kind) { return kKinds[kind]; }

int ParameterLayout::kind_from_name(const std::string& name) {
  for (int k = 0; k < 10; ++k)
    if (name == kKinds[k]) return k;
  return -1;
}

const char* ParameterLayout::kind_unit(int kind) {
  return kind == kMass ? "kg" : kind <= kMz ? "kg m" : "kg m^2";
}

std::string ParameterLayout::name(const Model& model, int index) const {
  return fmt::format("{}({})", kind_name(kind_of(index)), model.links[link_of(index)].name);
}

Eigen::Matrix3d inertia_about_origin(double mass, const Eigen::Vector3d& com,
                                     const Eigen::Matrix3d& inertia_com) {
  return inertia_com +
         mass * (com.squaredNorm() * Eigen::Matrix3d::Identity() - com * com.transpose());
}

Eigen::VectorXd ParameterLayout::nominal(const Model& model) const {
  Eigen::VectorXd pi = Eigen::VectorXd::Zero(size(model));
  for (int l = 0; l < model.num_links(); ++l) {
    const Link& link = model.links[l];
    pi[index(l, kMass)] = link.mass;
    pi.segment<3>(index(l, kMx)) = link.mass * link.com;
    if (inertia()) {
      const Eigen::Matrix3d I = inertia_about_origin(link.mass, link.com, link.inertia);
      // ixx, ixy, ixz, iyy, iyz, izz: the upper triangle, row by row.
      for (int r = 0, k = kIxx; r < 3; ++r)
        for (int c = r; c < 3; ++c) pi[index(l, k++)] = I(r, c);
    }
  }
  return pi;
}

}  // namespace massid
