// The standard parameters of the measured links: one layout for rest and motion.
//
//   first moments (static):  4 per link   m, mx, my, mz
//   full (motion):          10 per link   m, mx, my, mz, ixx, ixy, ixz, iyy, iyz, izz
//
// (mx, my, mz) = m c is the first moment, c the centre of mass in the link
// frame; the inertia (ixx ... izz) is about the LINK-FRAME ORIGIN, in the link
// frame, so that the wrench is linear in the parameters:
//   I_O = I_C + m (|c|^2 1 - c c^T)          (parallel axes; URDF gives I_C)
// Parameters are stored link-major: index = per_link * link + kind.
#pragma once

#include <Eigen/Core>
#include <string>

#include "massid/core/model.hpp"

namespace massid {

// The kind of a standard parameter (its position within a link's block).
enum ParamKind : int {
  kMass = 0,
  kMx = 1,
  kMy = 2,
  kMz = 3,
  kIxx = 4,
  kIxy = 5,
  kIxz = 6,
  kIyy = 7,
  kIyz = 8,
  kIzz = 9
};

class ParameterLayout {
 public:
  static ParameterLayout first_moments() { return ParameterLayout(4); }
  static ParameterLayout full() { return ParameterLayout(10); }
  // 4 or 10; anything else: the first-moment layout.
  static ParameterLayout of_size(int per_link) { return ParameterLayout(per_link == 10 ? 10 : 4); }

  int per_link() const { return per_link_; }
  bool inertia() const { return per_link_ == 10; }  // the full (motion) layout
  int size(const Model& model) const { return per_link_ * model.num_links(); }
  int index(int link, int kind) const { return per_link_ * link + kind; }
  int link_of(int index) const { return index / per_link_; }
  int kind_of(int index) const { return index % per_link_; }

  // "m", "mx", ..., "izz"; -1 for an unknown name.
  static const char* kind_name(int kind);
  static int kind_from_name(const std::string& name);
  static const char* kind_unit(int kind);  // "kg", "kg m", "kg m^2"
  // "mx(link2)"
  std::string name(const Model& model, int index) const;
  // The URDF's inertials in this layout (links without <inertial>: 0).
  Eigen::VectorXd nominal(const Model& model) const;

  bool operator==(const ParameterLayout& o) const { return per_link_ == o.per_link_; }

 private:
  explicit ParameterLayout(int per_link) : per_link_(per_link) {}
  int per_link_;
};

// Inertia about the link origin from the inertia about the centre of mass.
Eigen::Matrix3d inertia_about_origin(double mass, const Eigen::Vector3d& com,
                                     const Eigen::Matrix3d& inertia_com);

}  // namespace massid
