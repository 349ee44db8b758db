// Private: the cross-product matrix, skew(v) w = v x w.
#pragma once

#include <Eigen/Core>

namespace massid::detail {

inline Eigen::Matrix3d skew(const Eigen::Vector3d& v) {
  Eigen::Matrix3d S;
  S << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return S;
}

}  // namespace massid::detail
