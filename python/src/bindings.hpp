// The parts of the massid._massid module, one file each (module.cpp puts them
// together), and the Python-side value types they share.
#pragma once

#include <pybind11/pybind11.h>

#include <Eigen/Core>
#include <optional>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/design/design.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/identify/identification.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/live/identified_model.hpp"

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

// massid.BaseParameters: a model's base parameters (static or dynamic).
struct PyBase {
  Model model;
  BaseParameters base;
};

// The motion options of the cutoff, root_gravity and level_gravity arguments
// (cutoff: Hz, > 0).
MotionDataOptions motion_data_options(std::optional<double> cutoff,
                                      const std::optional<std::vector<double>>& root_gravity,
                                      const std::optional<std::vector<double>>& level_gravity = {});

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

// qd, qdd [N x num_joints] and sensor_motion [N x 9] (0 x 0 when None) of a
// regressor or predictor call; present: qd and qdd were given.
struct MotionArrays {
  bool present = false;
  Eigen::MatrixXd qd, qdd, sensor_motion;
  FrameMotion sensor(Eigen::Index i) const;  // at rest without sensor_motion
};
MotionArrays motion_arrays(const Model& model, Eigen::Index rows, const py::handle& qd,
                           const py::handle& qdd, const py::handle& sensor_motion);

// The identified model of a massid.Predictor, or of Predictor's (robot,
// params) arguments (its residual_rms: the tracker's default noise).
IdentifiedModel identified_of(const py::object& robot, const py::object& params);

void bind_model(py::module_& m);     // Model, load_model, base_parameters, regressors
void bind_motion(py::module_& m);    // fourier_trajectory
void bind_predict(py::module_& m);   // Params, load_params, Predictor, predict, simulate
void bind_identify(py::module_& m);  // Identification, identify
void bind_design(py::module_& m);    // Plan, design
void bind_track(py::module_& m);     // Tracker, TrackerEstimate

}  // namespace massid::python
