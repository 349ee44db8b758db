// Motion: the options of identification in motion, and exciting trajectories
// (massid/identify/motion_data.hpp, excitation.hpp): massid.fourier_trajectory.
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <cmath>

#include "bindings.hpp"
#include "convert.hpp"
#include "massid/core/errors.hpp"
#include "massid/design/excitation.hpp"
#include "massid/io/read_samples.hpp"

namespace massid::python {

MotionDataOptions motion_data_options(std::optional<double> cutoff,
                                      const std::optional<std::vector<double>>& root_gravity,
                                      const std::optional<std::vector<double>>& level_gravity) {
  MotionDataOptions o;
  if (cutoff) {
    if (!(*cutoff > 0 && std::isfinite(*cutoff)))
      throw InputError(fmt::format("cutoff: {} is not a positive number (Hz)", *cutoff));
    o.filter.cutoff = *cutoff;
  }
  o.samples.root_gravity = root_gravity_of(root_gravity);
  o.samples.level_gravity = level_gravity_of(level_gravity);
  return o;
}

namespace {

// The columns write_trajectory writes: t, joints, JOINT_vel, JOINT_acc, gx, gy, gz.
py::dict trajectory_columns(const Model& model, const Samples& s) {
  py::dict out;
  out["t"] = Eigen::VectorXd(s.time);
  for (int j = 0; j < model.num_joints(); ++j)
    out[py::str(model.joints[j].name)] = Eigen::VectorXd(s.q.col(j));
  for (int j = 0; j < model.num_joints(); ++j)
    out[py::str(model.joints[j].name + "_vel")] = Eigen::VectorXd(s.qd.col(j));
  for (int j = 0; j < model.num_joints(); ++j)
    out[py::str(model.joints[j].name + "_acc")] = Eigen::VectorXd(s.qdd.col(j));
  for (int k = 0; k < 3; ++k)
    out[py::str(std::string("g") + "xyz"[k])] = Eigen::VectorXd(s.gravity.col(k));
  return out;
}

py::dict fourier_trajectory(const py::object& robot, int harmonics, double period, double duration,
                            double rate, std::uint64_t seed, std::optional<std::string> sensor,
                            std::optional<std::map<std::string, double>> fixed,
                            std::vector<double> gravity, const py::object& velocity_limit,
                            double acceleration_limit, double position_margin) {
  Model model = model_of(robot, sensor, fixed);
  if (harmonics < 1 || harmonics > 50) throw InputError("harmonics must be in [1, 50]");
  for (auto [v, name] : {std::pair{period, "period"},
                         {duration, "duration"},
                         {rate, "rate"},
                         {acceleration_limit, "acceleration_limit"}})
    if (!(v > 0 && std::isfinite(v)))
      throw InputError(fmt::format("{}: {} is not a positive number", name, v));
  if (!(position_margin >= 0 && position_margin < 0.5))
    throw InputError(fmt::format("position_margin: {} is not in [0, 0.5)", position_margin));
  if (!(duration * rate < 1e8)) throw InputError("duration * rate: more than 1e8 samples");
  if (gravity.size() != 3) throw InputError("gravity: three numbers gx, gy, gz");
  ExcitationLimits limits;
  limits.acceleration = acceleration_limit;
  limits.position_margin = position_margin;
  // velocity_limit: one number for every joint, or joint -> rad/s (m/s); the
  // others keep the URDF's (else 1).
  if (!velocity_limit.is_none()) {
    std::map<std::string, double> per_joint;
    if (py::isinstance<py::float_>(velocity_limit) || py::isinstance<py::int_>(velocity_limit)) {
      for (const Joint& j : model.joints) per_joint[j.name] = velocity_limit.cast<double>();
    } else {
      per_joint = velocity_limit.cast<std::map<std::string, double>>();
    }
    for (const auto& [name, v] : per_joint) {
      const int j = model.find_joint(name);
      if (j < 0) throw InputError(fmt::format("velocity_limit: no movable joint '{}'", name));
      if (!(v > 0 && std::isfinite(v)))
        throw InputError(fmt::format("velocity_limit {}: {} is not a positive number", name, v));
      model.joints[j].velocity_limit = v;
    }
  }
  Samples s;
  {
    py::gil_scoped_release release;
    const FourierTrajectory tr = random_fourier_trajectory(model, harmonics, period, seed, limits);
    s = sample_trajectory(tr, duration, rate, Eigen::Map<const Eigen::Vector3d>(gravity.data()));
  }
  return trajectory_columns(model, s);
}

// massid.prepare_motion: the samples identify/predict make of a motion log.
py::dict prepare_motion(const py::object& robot, const py::object& data,
                        std::optional<double> cutoff, std::optional<int> decimation,
                        std::optional<std::vector<double>> root_gravity,
                        std::optional<std::vector<double>> level_gravity,
                        std::optional<std::string> sensor,
                        std::optional<std::map<std::string, double>> fixed,
                        std::optional<std::map<std::string, std::string>> columns) {
  const Model model = model_of(robot, sensor, fixed);
  MotionDataOptions o = motion_data_options(cutoff, root_gravity, level_gravity);
  o.samples.columns = column_names_of(columns);
  if (decimation) {
    if (*decimation < 1) throw InputError(fmt::format("decimation: {} is not >= 1", *decimation));
    o.filter.decimation = *decimation;
  }
  CsvTable table;
  Samples raw = samples_of(model, data, WrenchColumns::Optional, nullptr, o.samples, &table);
  const bool from_file = is_path(data);
  Samples s;
  {
    py::gil_scoped_release release;
    s = prepare_motion_samples(model, std::move(raw), o);
  }
  py::dict out;
  const Eigen::Index N = s.size();
  // The data row of each sample (lines are file lines for a CSV, rows for columns).
  py::array_t<long> row(N);
  {
    long* r = row.mutable_data();
    Eigen::Index k = 0;
    for (Eigen::Index i = 0; i < N; ++i) {
      if (from_file) {
        while (k < static_cast<Eigen::Index>(table.line.size()) && table.line[k] != s.line[i]) ++k;
        r[i] = static_cast<long>(k);
      } else {
        r[i] = s.line[i];
      }
    }
  }
  if (s.time.size() == N) out["t"] = Eigen::VectorXd(s.time);
  const auto put = [&](const std::vector<Joint>& joints, const Eigen::MatrixXd& m,
                       const char* suffix) {
    if (m.cols() != static_cast<Eigen::Index>(joints.size())) return;
    for (size_t j = 0; j < joints.size(); ++j)
      out[py::str(joints[j].name + suffix)] = Eigen::VectorXd(m.col(static_cast<Eigen::Index>(j)));
  };
  put(model.joints, s.q, "");
  put(model.joints, s.qd, "_vel");
  put(model.joints, s.qdd, "_acc");
  put(model.upstream_joints, s.q_upstream, "");
  put(model.upstream_joints, s.qd_upstream, "_vel");
  put(model.upstream_joints, s.qdd_upstream, "_acc");
  for (int k = 0; k < 3; ++k)
    out[py::str(std::string("g") + "xyz"[k])] = Eigen::VectorXd(s.gravity.col(k));
  if (s.has_sensor_motion()) {
    const char* names[9] = {"wx", "wy", "wz", "dwx", "dwy", "dwz", "ax", "ay", "az"};
    for (int k = 0; k < 9; ++k) out[py::str(names[k])] = Eigen::VectorXd(s.sensor_motion.col(k));
  }
  if (s.has_wrench())
    for (int k = 0; k < 6; ++k) out[py::str(kWrenchColumns[k])] = Eigen::VectorXd(s.wrench.col(k));
  if (!s.block.empty()) {
    Eigen::VectorXd b(N);
    for (Eigen::Index i = 0; i < N; ++i) b[i] = s.block[i];
    out["block"] = b;
  }
  out["row"] = row;
  return out;
}

}  // namespace

void bind_motion(py::module_& m) {
  m.def("prepare_motion", &prepare_motion, py::arg("robot"), py::arg("data"), py::kw_only(),
        py::arg("cutoff") = py::none(), py::arg("decimation") = py::none(),
        py::arg("root_gravity") = py::none(), py::arg("level_gravity") = py::none(),
        py::arg("sensor") = py::none(), py::arg("fixed") = py::none(),
        py::arg("columns") = py::none(),
        R"(The samples that identify(..., dynamic=True) and predict make of a motion log, as
columns: t, joints, JOINT_vel, JOINT_acc (given, or derived from t and the positions by the
zero-phase low-pass: cutoff Hz, default min(10, rate/20); the positions, gravity, sensor
motion and wrench smoothed alike, the rows at each end of each block dropped, every
decimation-th filtered row kept: default floor(rate / (2 cutoff)) as identify, 1 as
predict), gx, gy, gz (from the upstream joints and root_gravity when the data have them, or
from tilt_x_deg, tilt_y_deg turning level_gravity: default root_gravity through the fixed joints
above the sensor link),
wx..az when the sensor moves, fx..mz when measured, block, and row: the data row (from 0)
of each sample.)");
  m.def("fourier_trajectory", &fourier_trajectory, py::arg("robot"), py::arg("harmonics") = 5,
        py::arg("period") = 10.0, py::arg("duration") = 30.0, py::arg("rate") = 1000.0,
        py::arg("seed") = 1, py::kw_only(), py::arg("sensor") = py::none(),
        py::arg("fixed") = py::none(),
        py::arg("gravity") = std::vector<double>{0.0, 0.0, -kStandardGravity},
        py::arg("velocity_limit") = py::none(), py::arg("acceleration_limit") = 4.0,
        py::arg("position_margin") = 0.1,
        R"(An exciting trajectory for identification in motion: a random finite Fourier series
per joint (harmonics of 1/period Hz, Gaussian coefficients falling as 1/k, seed), at rest
at t = 0 and every period, scaled into the joint limits (position_margin of the range kept
free at each end), the velocity limits (velocity_limit: one number or joint -> rad/s, else
the URDF's, else 1) and acceleration_limit (rad/s^2 or m/s^2). Sampled at rate Hz over
[0, duration]: the columns t, joints, JOINT_vel, JOINT_acc, gx, gy, gz (gravity: sensor
frame, the same in every row), a trajectory for simulate(..., dynamic=True).)");
}

}  // namespace massid::python
