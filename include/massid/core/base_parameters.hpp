// Base parameters: the linear combinations of standard parameters that static
// base wrenches determine (paper eqs. 27-28, found numerically for any tree).
//
// Coordinates. The regressor is first rewritten in coordinates pi' where the
// sensor link's mass is replaced by the total mass M_t = sum_l m_l:
//   Y'(M_t)  = Y(m_sensor) = [g; 0]
//   Y'(m_l)  = Y(m_l) - Y(m_sensor) = [0; p_l x g]      (l != sensor)
//   Y'(h_l)  = Y(h_l)
// so the total mass is always a base parameter of its own (paper eq. 37).
//
// Selection. The columns of Y', stacked over random joint positions and
// gravity directions, are visited in a fixed order of preference: M_t, then
// the first moments mx, my, mz of each link from the sensor outwards
// (depth-first), then the other links' masses. A column becomes a base
// parameter when, normalised to unit length, its distance from the span of the
// columns already kept exceeds `rank_tolerance` (Gram-Schmidt, i.e. QR with
// this column order). Every other column is a combination of the kept ones,
// Y'_D = Y'_B beta, and the base parameters are pi_b = pi'_B + beta pi'_D.
// Preferring proximal first moments yields the paper's eq. 28 for the PUMA.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <string>
#include <vector>

#include "massid/core/model.hpp"
#include "massid/core/parameters.hpp"

namespace massid {

struct Term {
  int link = 0;   // index in Model::links
  int param = 0;  // ParamKind: 0 m, 1 mx, 2 my, 3 mz, 4 ixx ... 9 izz
  double coef = 0.0;
};

struct BaseParameter {
  std::string name;         // "p1", ..., "M" for the total mass
  std::string expression;   // "mx(link2) + 0.198 m(link3)"
  std::string unit;         // "kg", "kg m" or "kg m^2"
  std::vector<Term> terms;  // base value = sum coef * standard parameter
};

// What the data can show: the parameter layout and the excitation that the
// random configurations of the reduction imitate.
//   Rest (first-moment layout): random q and gravity directions, as above.
//   Motion (full layout): random q, qd, qdd; gravity in random directions, or
//   fixed (`sensor_gravity`, in the sensor frame: a level platform, whose data
//   cannot tell some constants from the offsets; from a root-frame vector:
//   fixed_sensor_gravity, kinematics.hpp); the sensor frame at rest unless
//   `sensor_moving`.
// In motion the preference order is M_t, each link's first moments and
// inertia (from the sensor outwards), then the other masses; with offsets and a fixed
// gravity, columns in the span of the offsets are not identifiable and join
// them (M_t then too: total_mass is -1).
struct BaseParameterOptions {
  ParameterLayout layout = ParameterLayout::first_moments();
  bool sensor_moving = false;  // motion: the sensor frame moves (platform, upstream joints)
  bool fixed_gravity = false;  // motion: gravity is `sensor_gravity` in every sample
  Eigen::Vector3d sensor_gravity{0.0, 0.0, -9.80665};  // the sensor frame, m/s^2
  bool offset = false;                                 // six sensor offsets join the unknowns
  double rank_tolerance = 1e-8;                        // on unit-norm columns, see above
  int samples = 0;                // random configurations; 0: max(40, 2 * standard)
  std::uint64_t seed = 20260101;  // fixed: the basis is a property of the model
};

struct BaseParameters {
  std::vector<BaseParameter> params;  // mass base parameters, named p1.. (distal first), then M
  Eigen::MatrixXd K;                  // [num_mass x num_standard] pi_b = K pi
  std::vector<int> column;            // [num_mass] column of Y' each one stands for
  ParameterLayout layout = ParameterLayout::first_moments();  // standard parameters (K's columns)
  bool sensor_moving = false;  // the reduction's assumptions (BaseParameterOptions)
  bool fixed_gravity = false;
  Eigen::Vector3d sensor_gravity = Eigen::Vector3d::Zero();  // the sensor frame
  int total_mass = 0;   // index of M in params; -1 when not identifiable
  bool offset = false;  // unknowns = params, then fx fy fz mx my mz offsets
  double rank_tolerance = 0.0;

  int num_mass() const { return static_cast<int>(params.size()); }
  bool motion() const { return layout.inertia(); }
  int num_unknowns() const { return num_mass() + (offset ? 6 : 0); }
  // Name of unknown i: a base parameter name or "offset_fx" ... "offset_mz".
  std::string unknown_name(int i) const;
  // True for unknowns whose regressor has moment rows (all but M, force offsets).
  bool is_moment_unknown(int i) const;
};

BaseParameters find_base_parameters(const Model& model, const BaseParameterOptions& options = {});

// Readable form of sum coef * standard parameter, round-off cleaned. One
// parameter summed over every link of a model of more than
// kAllLinksShortened links (a hand's total mass) reads
// "m(all N links below SENSOR, itself included)".
inline constexpr int kAllLinksShortened = 10;
std::string format_expression(const Model& model, const std::vector<Term>& terms);

}  // namespace massid
