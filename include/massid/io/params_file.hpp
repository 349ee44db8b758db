// The parameters file (JSON, "massid-params-1"): identified base parameters
// with their terms, standard deviations, covariance and fit statistics.
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"
#include "massid/core/predictor.hpp"

namespace massid {

// The "format" of every params file.
inline constexpr const char* kParamsFormat = "massid-params-1";

struct ParamsFile {
  struct NamedTerm {
    std::string link, param;
    double coef = 0.0;
  };
  struct Entry {
    std::string name, unit, expression;
    double value = 0.0, stddev = 0.0;
    std::vector<NamedTerm> terms;
  };
  std::string source;  // path, for messages
  std::string sensor_link;
  std::vector<std::string> joints;
  std::vector<std::pair<std::string, double>> held;  // joints held still (hold_joints)
  std::string gravity_from;                          // "columns", "force" or "upstream joints"
  // "model": "dynamic" (ten parameters per link, identified in motion) with
  // the assumptions of its base-parameter reduction; absent or "static": the
  // first-moment model.
  bool dynamic = false;
  bool fixed_gravity = false;  // every sample had this gravity (sensor frame)
  Eigen::Vector3d gravity = Eigen::Vector3d::Zero();
  bool sensor_moving = false;
  int samples = 0;
  double total_mass = 0.0;  // NaN when not identifiable (dynamic, level, with offsets)
  std::vector<Entry> base_parameters;
  bool has_offset = false;
  Wrench offset = Wrench::Zero(), offset_std = Wrench::Zero();
  double condition_number = 0.0;
  // "delay" (identify --dynamic --delay): the wrench's lag behind the joint
  // stream, s (positive: the wrench arrives late); 0 without.
  double delay = 0.0, delay_std = 0.0;
  Wrench residual_rms = Wrench::Zero();
  // "physical" (identify --physical): the ten standard parameters of every
  // measured link (m, mx, my, mz, ixx .. izz; inertia about the link origin),
  // in the file's order. Empty when the file has no such section.
  struct PhysicalEntry {
    std::string link;
    Eigen::Matrix<double, 10, 1> params = Eigen::Matrix<double, 10, 1>::Zero();
  };
  std::vector<PhysicalEntry> physical;
};

// Reads and checks a params file; InputError names file:line:column.
ParamsFile read_params(const std::string& path);

// The base-parameter reduction a params file was identified with (its layout,
// offsets and, in motion, gravity and sensor assumptions).
BaseParameterOptions base_parameter_options(const ParamsFile& params);

// The file's values expressed in `base` (num_unknowns, offsets last). The
// file's terms may use another basis of the same space; InputError when the
// file's parameters do not match the model (another robot or sensor link).
Eigen::VectorXd values_in_basis(const ParamsFile& params, const Model& model,
                                const BaseParameters& base);

// The file's physical parameters as values in `base` (K pi_phys, then the
// file's offsets): what `predict --physical` predicts from. InputError when
// the file has no "physical" section or it does not name every measured link
// of `model` (or names another).
Eigen::VectorXd physical_values_in_basis(const ParamsFile& params, const Model& model,
                                         const BaseParameters& base);

}  // namespace massid
