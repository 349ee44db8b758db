// The parts of the massid._massid module, one file each (module.cpp puts them
// together), and the Python-side value types they share.
#pragma once

#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "massid/base_parameters.hpp"
#include "massid/design.hpp"
#include "massid/estimation.hpp"
#include "massid/model.hpp"
#include "massid/samples.hpp"

namespace massid::python {

namespace py = pybind11;

// A base parameter as Python sees it (massid.BaseParameter): its terms by link
// name, and the identified value and std (nan when there are none).
struct NamedParameter {
  std::string name, unit, expression;
  std::vector<std::tuple<std::string, std::string, double>> terms;  // (link, kind, coef)
  double value = 0.0, std = 0.0;
};
NamedParameter named_parameter(const Model& model, const BaseParameter& p);
const char* joint_type_name(JointType t);
std::vector<std::string> joint_names(const Model& model);
std::vector<std::string> unknown_names(const BaseParameters& base);  // params, then offsets

// massid.Identification: a fit with the samples it was made from.
struct Identification {
  Model model;
  BaseParameters base;
  IdentifySummary summary;
  Samples samples;
  Eigen::MatrixXd fitted;             // [N x 6] fitted_wrenches
  std::vector<std::string> warnings;  // one line each, without "massid: warning: "
};

// massid.Plan: a designed experiment.
struct Plan {
  Model model;
  BaseParameters base;
  DesignSummary summary;
  DesignOptions options;
};
// The plan CSV's columns (write_plan's): joints (held ones too), gx, gy, gz,
// tilt_x_deg, tilt_y_deg.
py::dict plan_columns(const Plan& plan);

// q [N x num_joints] and gravity [N x 3] of the same N from array-likes.
std::pair<Eigen::MatrixXd, Eigen::MatrixXd> poses_of(const Model& model, const py::handle& q,
                                                     const py::handle& gravity);

void bind_model(py::module_& m);     // Model, load_model, base_parameters, regressors
void bind_predict(py::module_& m);   // Params, load_params, Predictor, predict, simulate
void bind_identify(py::module_& m);  // Identification, identify
void bind_design(py::module_& m);    // Plan, design

}  // namespace massid::python
