// Ten standard parameters per link (m, mx, my, mz, ixx .. izz; inertia about
// the link origin, link frame): what they say of one body (mass, centre of
// mass, inertia about it, the pseudo-inertia) and the base parameters they
// give. What reading a params file's "physical" section needs; the fit that
// makes them is physical.hpp's.
#pragma once

#include <Eigen/Core>
#include <string>

#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"

namespace massid {

// One measured link's consistent parameters.
struct PhysicalLink {
  std::string name;
  double mass = 0.0;                                            // kg
  Eigen::Vector3d com = Eigen::Vector3d::Zero();                // centre of mass, link frame, m
  Eigen::Matrix3d inertia_com = Eigen::Matrix3d::Zero();        // about com, link frame, kg m^2
  Eigen::Vector3d principal_moments = Eigen::Vector3d::Zero();  // of inertia_com, ascending
  // Smallest eigenvalue of the pseudo-inertia J (kg m^2) and whether it is
  // non-negative within round-off (-1e-12 tr J): the link is a real body (or
  // no body: all ten parameters zero, a massless frame).
  double min_eigenvalue = 0.0;
  bool consistent = false;
  bool prior_body = false;  // the URDF gave no mass: the prior was the tiny body
  // prior_body and rigidly fixed to a neighbour the data cannot tell it from
  // (ee_link, tool0, a massless root): its fitted body joined the
  // neighbour's, its ten parameters are 0 (consistent: no body) and it stays
  // massless in the identified URDF.
  bool unseen = false;
};

// K pi for ten standard parameters per link (full layout, [10 num_links]):
// the base parameters (num_mass) they give in base's layout (4 or 10 per link).
Eigen::VectorXd base_values_of_standard(const Model& model, const BaseParameters& base,
                                        const Eigen::VectorXd& standard);

// The pseudo-inertia J of one link's ten standard parameters (m, h, I about the origin).
Eigen::Matrix4d pseudo_inertia(const Eigen::Ref<const Eigen::VectorXd>& ten);

// One link's summary fields (mass, com, inertia about the com, principal
// moments, J's smallest eigenvalue) from its ten standard parameters.
PhysicalLink physical_link(const std::string& name, const Eigen::Ref<const Eigen::VectorXd>& ten);

}  // namespace massid
