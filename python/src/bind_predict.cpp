// Params files, the predictor and simulated measurements (massid/io/params_file.hpp,
// predictor.hpp, simulate.hpp).
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/stl.h>

#include <limits>
#include <memory>

#include "bindings.hpp"
#include "convert.hpp"
#include "hints.hpp"
#include "io/atomic_file.hpp"
#include "massid/core/base_regressor.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/motion_predictor.hpp"
#include "massid/core/predictor.hpp"
#include "massid/core/simulate.hpp"
#include "massid/identify/motion_data.hpp"
#include "massid/identify/predict_log.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/live/identified_model.hpp"

namespace massid::python {

namespace {

// The model a params file (or an identification) belongs to: the URDF loaded
// at its sensor link with its held joints, or a Model checked against them.
Model model_for(const py::handle& robot, const std::string& sensor_link,
                const std::vector<std::pair<std::string, double>>& held) {
  if (py::isinstance<Model>(robot)) {
    Model model = robot.cast<Model>();
    if (model.sensor_link() != sensor_link)
      throw InputError(fmt::format(
          "the model's sensor link is '{}', the parameters' '{}': load_model(urdf, sensor='{}')",
          model.sensor_link(), sensor_link, sensor_link));
    return model.held.empty() ? hold_joints(std::move(model), held) : model;
  }
  return model_of(robot, sensor_link, held_dict(held));
}

// massid.Predictor: a thin adapter over the identified model every door
// shares (identified_model.hpp), static or dynamic, with its workspace.
struct PyPredictor {
  IdentifiedModel identified;
  Model model;  // identified.model(), for Python
  bool dynamic = false;
  std::unique_ptr<IdentifiedModelData> data;
  std::optional<Eigen::Vector3d> level_gravity;  // dynamic, identified at one gravity
  std::optional<Wrench> offset;                  // the identified offsets

  explicit PyPredictor(IdentifiedModel m)
      : identified(std::move(m)),
        model(identified.model()),
        dynamic(identified.dynamic()),
        data(std::make_unique<IdentifiedModelData>(identified)),
        level_gravity(identified.fixed_gravity()) {
    if (identified.has_offset()) offset = identified.offset();
  }

  // [N x 6] the mechanism's wrench (weight and motion, no offset) at every
  // sample, as `massid predict` computes it.
  Eigen::MatrixXd predict_samples(const Samples& s) {
    py::gil_scoped_release release;
    return identified.predict_samples(*data, s);
  }

  py::object operator()(const py::object& q, const py::object& gravity, const py::object& qd,
                        const py::object& qdd, const py::object& sensor_motion_arg,
                        const py::object& t, std::optional<double> cutoff) {
    const py::object ndim = py::module_::import("numpy").attr("ndim");
    if (!dynamic) {
      if (!qd.is_none() || !qdd.is_none() || !sensor_motion_arg.is_none() || !t.is_none() || cutoff)
        throw InputError(
            "static (first-moment) parameters predict the gravity wrench from q and gravity "
            "alone: qd, qdd, sensor_motion, t and cutoff go with dynamic parameters");
      if (gravity.is_none()) throw InputError("gravity (gx, gy, gz) is needed");
      const auto [Q, G] = poses_of(model, q, gravity);
      Samples s;
      s.q = Q;
      s.gravity = G;
      const Eigen::MatrixXd W = predict_samples(s);
      const bool single = ndim(q).cast<int>() == 1 && ndim(gravity).cast<int>() == 1;
      return single ? py::cast(Eigen::VectorXd(W.row(0).transpose())) : py::cast(std::move(W));
    }
    // Dynamic.
    Samples s;
    s.source = "q";
    s.q = to_matrix(q, model.num_joints(),
                    fmt::format("q (joints {})", fmt::join(joint_names(model), ", ")));
    const Eigen::Index N = s.q.rows();
    if (gravity.is_none()) {
      if (!level_gravity)
        throw InputError(
            "gravity (gx, gy, gz) is needed: the parameters were identified with varying "
            "gravity");
      s.gravity = level_gravity->transpose().replicate(N, 1);
    } else {
      s.gravity = to_matrix(gravity, 3, "gravity (gx, gy, gz)");
      if (s.gravity.rows() != N)
        throw InputError(fmt::format("q has {} rows and gravity {}: one of each per sample", N,
                                     s.gravity.rows()));
    }
    const bool single =
        ndim(q).cast<int>() == 1 && (gravity.is_none() || ndim(gravity).cast<int>() == 1);
    if (!qd.is_none() || !qdd.is_none()) {
      if (!t.is_none() || cutoff)
        throw InputError("t and cutoff go with positions alone (qd and qdd derived from them)");
      const MotionArrays mo = motion_arrays(model, N, qd, qdd, sensor_motion_arg);
      s.qd = mo.qd;
      s.qdd = mo.qdd;
      s.sensor_motion = mo.sensor_motion;
      Eigen::MatrixXd W = predict_samples(s);
      return single ? py::cast(Eigen::VectorXd(W.row(0).transpose())) : py::cast(std::move(W));
    }
    if (t.is_none())
      throw InputError(
          "dynamic parameters predict the wrench in motion: give qd and qdd (joint velocities "
          "and accelerations), or t to derive them from q (zero-phase low-pass, as massid "
          "predict)");
    s.time = to_vector(t, "t");
    if (s.time.size() != N)
      throw InputError(
          fmt::format("q has {} rows and t {}: one of each per sample", N, s.time.size()));
    if (!sensor_motion_arg.is_none())
      s.sensor_motion = optional_matrix(sensor_motion_arg, N, 9,
                                        "sensor_motion (wx, wy, wz, dwx, dwy, dwz, ax, ay, az)");
    s.line.resize(N);
    for (Eigen::Index i = 0; i < N; ++i) s.line[i] = static_cast<int>(i);
    s.qd.resize(N, 0);
    s.qdd.resize(N, 0);
    MotionDataOptions o = motion_data_options(cutoff, std::nullopt);
    o.filter.decimation = 1;
    const Samples kept = prepare_motion_samples(model, std::move(s), o);
    return py::cast(spread_rows(predict_samples(kept), kept.line, N, nullptr));
  }

  // [rows x 6]: row r of W at the data row of line[r] (table: file lines of
  // the rows; null: the lines are row indices), NaN elsewhere.
  static Eigen::MatrixXd spread_rows(const Eigen::MatrixXd& W, const std::vector<int>& line,
                                     Eigen::Index rows, const std::vector<int>* table_lines) {
    Eigen::MatrixXd out =
        Eigen::MatrixXd::Constant(rows, 6, std::numeric_limits<double>::quiet_NaN());
    Eigen::Index r = 0;
    for (size_t k = 0; k < line.size(); ++k) {
      if (table_lines) {
        while (r < rows && (*table_lines)[r] != line[k]) ++r;
      } else {
        r = line[k];
      }
      if (r < rows) out.row(r) = W.row(static_cast<Eigen::Index>(k));
    }
    return out;
  }
};

std::unique_ptr<PyPredictor> make_predictor(const py::object& robot, const py::object& params,
                                            bool physical = false) {
  IdentifiedModelOptions options;
  options.physical = physical;
  if (py::isinstance<Identification>(params)) {
    const auto& id = params.cast<const Identification&>();
    if (!robot.is_none()) {
      const Model check = model_for(robot, id.model.sensor_link(), id.model.held);
      if (check.name != id.model.name)
        throw InputError(
            fmt::format("robot '{}' is not the identified robot '{}'", check.name, id.model.name));
    }
    if (physical && !id.physical)
      throw InputError("physical=True needs an identification made with physical=True");
    return std::make_unique<PyPredictor>(IdentifiedModel::from_identification(id, options));
  }
  const ParamsFile file = py::isinstance<ParamsFile>(params) ? params.cast<ParamsFile>()
                          : is_path(params)                  ? read_params(path_of(params))
                                                             : throw InputError(
                                                                   "params: expected a params file path, "
                                                                                    "massid.Params or massid.Identification");
  return std::make_unique<PyPredictor>(
      IdentifiedModel::from_params(model_for(robot, file.sensor_link, file.held), file, options));
}

// A data argument as a table: a CSV path read as the CLI reads it, or
// columns by name (each cell written as format_number writes it, which reads
// back to the same double; the "lines" are the row indices).
CsvTable table_of(const py::handle& data) {
  if (is_path(data)) return read_csv(path_of(data));
  const Columns c = columns_of(data);
  CsvTable t;
  t.source = "data";
  t.header = c.names;
  const Eigen::Index rows = c.values.empty() ? 0 : c.values.front().size();
  for (size_t k = 0; k < c.values.size(); ++k)
    if (c.values[k].size() != rows)
      throw InputError(fmt::format("data: column '{}' has {} rows, column '{}' has {}",
                                   c.names.front(), rows, c.names[k], c.values[k].size()));
  t.rows.assign(static_cast<size_t>(rows), std::vector<std::string>(c.names.size()));
  for (Eigen::Index r = 0; r < rows; ++r) {
    for (size_t k = 0; k < c.values.size(); ++k)
      t.rows[static_cast<size_t>(r)][k] = format_number(c.values[k][r]);
    t.line.push_back(static_cast<int>(r));
    t.column_offset.emplace_back(c.names.size(), 1);
  }
  return t;
}

// massid predict's pipeline (predict_log.hpp) on a data argument's table
// (table_of), its warnings raised as MassidWarning.
LogPrediction predict_log_of(const IdentifiedModel& identified, CsvTable table,
                             const std::string& source, std::optional<double> cutoff,
                             std::optional<std::vector<double>> root_gravity,
                             std::optional<std::vector<double>> level_gravity, bool checks,
                             const ColumnNames& columns) {
  if (!identified.dynamic() && cutoff) throw InputError("cutoff goes with dynamic parameters");
  PredictLogOptions o;
  o.motion = motion_data_options(cutoff, root_gravity, level_gravity);
  o.motion.samples.columns = columns;
  o.checks = checks;
  LogPrediction out;
  {
    py::gil_scoped_release release;
    out = predict_log(identified, std::move(table), source, o);
  }
  const py::object warn = py::module_::import("warnings").attr("warn");
  const py::object category = py::module_::import("massid").attr("MassidWarning");
  warn_note(out.column_note);
  for (const Warning& w : out.setup.warnings()) warn(with_hints(w.message, w.hints), category, 3);
  return out;
}

LogPrediction predict_log_of(const IdentifiedModel& identified, const py::object& data,
                             std::optional<double> cutoff,
                             std::optional<std::vector<double>> root_gravity,
                             std::optional<std::vector<double>> level_gravity, bool checks,
                             const ColumnNames& columns) {
  return predict_log_of(identified, table_of(data), is_path(data) ? path_of(data) : "data", cutoff,
                        std::move(root_gravity), std::move(level_gravity), checks, columns);
}

// [N x 6] or [6] as numpy gives them, as a matrix of six columns.
Eigen::MatrixXd wrenches_of(const py::object& w, const char* what) { return to_matrix(w, 6, what); }

std::optional<Wrench> optional_wrench(bool present, const Wrench& w) {
  return present ? std::optional<Wrench>(w) : std::nullopt;
}

}  // namespace

IdentifiedModel identified_of(const py::object& robot, const py::object& params) {
  if (py::isinstance<PyPredictor>(robot)) {
    if (!params.is_none())
      throw InputError("params goes with a URDF or Model, not with a massid.Predictor");
    const auto& p = robot.cast<const PyPredictor&>();
    return p.identified;
  }
  if (params.is_none())
    throw InputError(
        "params is needed: a params file path, massid.Params or "
        "massid.Identification (or give a massid.Predictor alone)");
  const std::unique_ptr<PyPredictor> p = make_predictor(robot, params);
  return p->identified;
}

void bind_predict(py::module_& m) {
  py::class_<ParamsFile>(m, "Params", "A params file ('massid-params-1') read back.")
      .def_readonly("source", &ParamsFile::source)
      .def_readonly("sensor_link", &ParamsFile::sensor_link)
      .def_readonly("joints", &ParamsFile::joints)
      .def_property_readonly("held", [](const ParamsFile& p) { return held_dict(p.held); })
      .def_readonly("gravity_from", &ParamsFile::gravity_from)
      .def_readonly("samples", &ParamsFile::samples)
      .def_readonly("total_mass", &ParamsFile::total_mass,
                    "kg; nan when not identifiable (dynamic, level, offsets)")
      .def_readonly("dynamic", &ParamsFile::dynamic,
                    "identified in motion ('model': 'dynamic'): ten parameters per link")
      .def_property_readonly(
          "gravity",
          [](const ParamsFile& p) -> py::object {
            if (!p.dynamic) return py::none();
            return py::str(p.fixed_gravity ? "level" : "varying");
          },
          "dynamic: 'level' (one gravity in every sample) or 'varying'; None at rest")
      .def_property_readonly(
          "gravity_vector",
          [](const ParamsFile& p) -> std::optional<Eigen::Vector3d> {
            if (p.dynamic && p.fixed_gravity) return p.gravity;
            return std::nullopt;
          },
          "dynamic, level: the gravity of every sample (sensor frame), else None")
      .def_readonly("moving_sensor", &ParamsFile::sensor_moving, "dynamic: the sensor frame moved")
      .def_property_readonly("base_parameters",
                             [](const ParamsFile& p) {
                               std::vector<NamedParameter> out;
                               for (const auto& e : p.base_parameters) {
                                 NamedParameter n;
                                 n.name = e.name;
                                 n.unit = e.unit;
                                 n.expression = e.expression;
                                 for (const auto& t : e.terms)
                                   n.terms.emplace_back(t.link, t.param, t.coef);
                                 n.value = e.value;
                                 n.std = e.stddev;
                                 out.push_back(std::move(n));
                               }
                               return out;
                             })
      .def_property_readonly(
          "offset", [](const ParamsFile& p) { return optional_wrench(p.has_offset, p.offset); })
      .def_property_readonly(
          "offset_std",
          [](const ParamsFile& p) { return optional_wrench(p.has_offset, p.offset_std); })
      .def_readonly("condition_number", &ParamsFile::condition_number)
      .def_property_readonly(
          "delay",
          [](const ParamsFile& p) -> py::object {
            if (p.delay == 0.0) return py::none();
            return py::float_(p.delay);
          },
          "the wrench's clock delay, s (identify delay=...), None without")
      .def_property_readonly(
          "physical",
          [](const ParamsFile& p) -> py::object {
            if (p.physical.empty()) return py::none();
            py::dict out;
            for (const auto& e : p.physical) {
              py::dict link;
              for (int k = 0; k < 10; ++k) link[ParameterLayout::kind_name(k)] = e.params[k];
              out[py::str(e.link)] = link;
            }
            return out;
          },
          "the \"physical\" section's links: name -> {m, mx, ..., izz}; None without")
      .def_property_readonly("residual_rms", [](const ParamsFile& p) { return p.residual_rms; })
      .def("__repr__", [](const ParamsFile& p) {
        return fmt::format("Params('{}'{}, total_mass={:.6g}, {} base parameters)", p.source,
                           p.dynamic ? ", dynamic" : "", p.total_mass, p.base_parameters.size());
      });

  m.def(
      "load_params", [](const py::object& path) { return read_params(path_of(path)); },
      py::arg("path"),
      "Reads a params file written by identify (massid.InputError names file:line:column).");

  py::class_<LogPrediction>(
      m, "LogPrediction",
      "A log predicted as massid predict predicts it (predict_log): the samples kept, the "
      "mechanism's wrench, the compensated wrench, the set-up checks' warnings and the "
      "contact notes.")
      .def_readonly("source", &LogPrediction::source)
      .def_property_readonly(
          "lines", [](const LogPrediction& p) { return p.samples.line; },
          "[N] the file line of each predicted row (row index for columns by name); dynamic "
          "without JOINT_vel/_acc: the rows the filter keeps")
      .def_property_readonly(
          "predicted", [](const LogPrediction& p) { return p.predicted; },
          "[N, 6] the mechanism's wrench, without the offset (massid predict's fx_pred..mz_pred)")
      .def_property_readonly(
          "compensated",
          [](const LogPrediction& p) -> std::optional<Eigen::MatrixXd> {
            if (!p.has_wrench()) return std::nullopt;
            return p.compensated;
          },
          "[N, 6] measured - predicted - offset (fx_comp..mz_comp); None without fx..mz")
      .def_property_readonly(
          "warnings",
          [](const LogPrediction& p) {
            std::vector<std::string> out;
            for (const Warning& w : p.setup.warnings())
              out.push_back(with_hints(w.message, w.hints));
            return out;
          },
          "the set-up checks' warnings (also raised as MassidWarning)")
      .def_readonly("notes", &LogPrediction::notes,
                    "one note per contact episode, the text of massid predict's "
                    "'massid: note:' lines")
      .def_property_readonly(
          "contact",
          [](const LogPrediction& p) {
            py::list out;
            for (const ContactEpisode& e : p.contact) {
              py::dict d;
              d["first_line"] = e.first_line;
              d["last_line"] = e.last_line;
              d["rows"] = e.last - e.first + 1;
              d["score"] = e.score;
              d["threshold"] = e.threshold;
              d["force"] = e.force;
              d["moment"] = e.moment;
              out.append(d);
            }
            return out;
          },
          "the contact episodes: first_line, last_line, rows, score, threshold, force (N), "
          "moment (N m)")
      .def_property_readonly(
          "cutoff",
          [](const LogPrediction& p) -> std::optional<double> {
            if (!p.motion.derived) return std::nullopt;
            return p.motion.kernels.cutoff;
          },
          "dynamic, derived from t: the low-pass cut-off, Hz; else None")
      .def("__repr__", [](const LogPrediction& p) {
        return fmt::format("LogPrediction('{}', {} rows, {} contact episode(s))", p.source,
                           p.samples.size(), p.contact.size());
      });

  const char* predict_doc =
      "[N, 6] wrenches for q [N, num_joints] (rad or m) and gravity [N, 3] (m/s^2, sensor "
      "frame); [6] for single vectors.\n"
      "Never the identified sensor offset (as massid predict's fx_pred..mz_pred): "
      "compensate(measured, predicted) subtracts it.\n"
      "Dynamic parameters: the full wrench (weight and motion) from q, qd and qdd [N, num_joints] "
      "(and sensor_motion [N, 9]: wx wy wz, "
      "dwx dwy dwz, ax ay az); gravity may be omitted for parameters identified at one "
      "gravity. Or from q and t [N] alone: qd and qdd derived by the zero-phase low-pass of "
      "massid predict (cutoff Hz; q and gravity smoothed alike), NaN in the rows at each end "
      "that the filter drops.";
  py::class_<PyPredictor>(m, "Predictor",
                          "The wrench predictor compiled from identified parameters: static, "
                          "the gravity wrench w = Y_b(q, g) pi_b (paper eq. 29), about 50 ns per "
                          "pose; dynamic, the full wrench in motion by Newton-Euler over the "
                          "identified bodies.")
      .def(py::init(&make_predictor), py::arg("robot"), py::arg("params"), py::kw_only(),
           py::arg("physical") = false,
           "robot: URDF path or Model (None with an Identification); params: a params file "
           "path, massid.Params or massid.Identification; physical: predict from its physical "
           "parameters (identify physical=True) instead of its base parameters.")
      .def_readonly("model", &PyPredictor::model)
      .def_readonly("dynamic", &PyPredictor::dynamic, "dynamic parameters (predicts in motion)")
      .def_readonly("offset", &PyPredictor::offset,
                    "[6] the identified sensor offsets (None without): never in the predictions; "
                    "compensate() and sensor_reading() apply them")
      .def_property_readonly("has_offset",
                             [](const PyPredictor& p) { return p.identified.has_offset(); })
      .def_property_readonly(
          "delay", [](const PyPredictor& p) { return p.identified.delay(); },
          "the wrench's clock delay, s (0 without): predict_log applies it from t; predict() "
          "takes the joint state it is given (pass that of t - delay)")
      .def(
          "compensate",
          [](const PyPredictor& p, const py::object& measured, const py::object& predicted) {
            const py::object ndim = py::module_::import("numpy").attr("ndim");
            const Eigen::MatrixXd C =
                p.identified.compensate_rows(wrenches_of(measured, "measured (fx..mz)"),
                                             wrenches_of(predicted, "predicted (fx..mz)"));
            if (C.rows() == 1 && ndim(measured).cast<int>() == 1)
              return py::cast(Eigen::VectorXd(C.row(0).transpose()));
            return py::cast(C);
          },
          py::arg("measured"), py::arg("predicted"),
          "The compensated wrench: (measured - predicted) - offset, [N, 6] or [6], as massid "
          "predict's fx_comp..mz_comp and massid compensate (predicted: this predictor's "
          "output)")
      .def(
          "sensor_reading",
          [](const PyPredictor& p, const py::object& predicted) {
            const py::object ndim = py::module_::import("numpy").attr("ndim");
            const Eigen::MatrixXd R =
                p.identified.sensor_reading_rows(wrenches_of(predicted, "predicted (fx..mz)"));
            if (R.rows() == 1 && ndim(predicted).cast<int>() == 1)
              return py::cast(Eigen::VectorXd(R.row(0).transpose()));
            return py::cast(R);
          },
          py::arg("predicted"), "What the sensor reads: predicted + offset, [N, 6] or [6]")
      .def_property_readonly("joint_names",
                             [](const PyPredictor& p) { return joint_names(p.model); })
      .def("predict", &PyPredictor::operator(), py::arg("q"), py::arg("gravity") = py::none(),
           py::arg("qd") = py::none(), py::arg("qdd") = py::none(), py::kw_only(),
           py::arg("sensor_motion") = py::none(), py::arg("t") = py::none(),
           py::arg("cutoff") = py::none(), predict_doc)
      .def(
          "predict_log",
          [](const PyPredictor& p, const py::object& data, std::optional<double> cutoff,
             std::optional<std::vector<double>> root_gravity,
             std::optional<std::vector<double>> level_gravity, bool checks,
             std::optional<std::map<std::string, std::string>> columns) {
            return predict_log_of(p.identified, data, cutoff, std::move(root_gravity),
                                  std::move(level_gravity), checks, column_names_of(columns));
          },
          py::arg("data"), py::kw_only(), py::arg("cutoff") = py::none(),
          py::arg("root_gravity") = py::none(), py::arg("level_gravity") = py::none(),
          py::arg("checks") = true, py::arg("columns") = py::none(),
          "massid predict on a log (a CSV path, or columns by name): the set-up checks (InputError "
          "with the CLI's message when they refuse; warnings as MassidWarning), the motion "
          "filter of a dynamic model's log without JOINT_vel/_acc, the predicted and "
          "compensated wrench and the contact notes, as a LogPrediction.")
      .def("__call__", &PyPredictor::operator(), py::arg("q"), py::arg("gravity") = py::none(),
           py::arg("qd") = py::none(), py::arg("qdd") = py::none(), py::kw_only(),
           py::arg("sensor_motion") = py::none(), py::arg("t") = py::none(),
           py::arg("cutoff") = py::none())
      .def("__repr__", [](const PyPredictor& p) {
        return fmt::format("Predictor('{}'{}, sensor_link='{}')", p.model.name,
                           p.dynamic ? ", dynamic" : "", p.model.sensor_link());
      });

  m.def(
      "load_predictor",
      [](const py::object& robot, const py::object& params, bool physical) {
        return make_predictor(robot, params, physical);
      },
      py::arg("robot"), py::arg("params"), py::kw_only(), py::arg("physical") = false,
      "massid.Predictor(robot, params, physical=physical): the identified model of a params "
      "file (static or dynamic) or an Identification, as every door loads it.");

  m.def(
      "predict",
      [](const py::object& robot, const py::object& params, const py::object& data,
         std::optional<double> cutoff, std::optional<std::vector<double>> root_gravity,
         std::optional<std::vector<double>> level_gravity, bool physical,
         std::optional<std::map<std::string, std::string>> columns) {
        // massid predict's pipeline without its set-up checks (predict_log.hpp),
        // its notes of the clock delay applied raised as MassidWarning, and its
        // rows spread back over the data's: rows the filter drops are NaN.
        const auto p = make_predictor(robot, params, physical);
        CsvTable table = table_of(data);
        const std::vector<int> lines = table.line;
        const LogPrediction out = predict_log_of(
            p->identified, std::move(table), is_path(data) ? path_of(data) : "data", cutoff,
            std::move(root_gravity), std::move(level_gravity), false, column_names_of(columns));
        const size_t delay_notes = out.notes.size() - out.contact.size();
        for (size_t k = 0; k < delay_notes; ++k) warn_note(out.notes[k]);
        return PyPredictor::spread_rows(out.predicted, out.samples.line,
                                        static_cast<Eigen::Index>(lines.size()), &lines);
      },
      py::arg("robot"), py::arg("params"), py::arg("data"), py::kw_only(),
      py::arg("cutoff") = py::none(), py::arg("root_gravity") = py::none(),
      py::arg("level_gravity") = py::none(), py::arg("physical") = false,
      py::arg("columns") = py::none(),
      "[N, 6] the mechanism's predicted wrench at every row of data, WITHOUT the identified "
      "sensor offsets (massid predict's fx_pred..mz_pred; a Predictor's call and "
      "Predictor.offset give the offsets): data is a CSV path or columns by name "
      "(joints or JOINT_deg, and gx, gy, gz or a measured force, as massid predict).\n"
      "Dynamic parameters: the full wrench in motion from JOINT_vel and "
      "JOINT_acc, or derived from t and the positions by the zero-phase low-pass of massid "
      "predict (cutoff Hz): the rows the filter drops at each end (of each block) are NaN. "
      "root_gravity: gravity in the URDF root frame (sensor below movable joints). "
      "level_gravity: gravity in the sensor frame with the platform level, which tilt_x_deg, "
      "tilt_y_deg turn in data without gx, gy, gz (default: root_gravity through the fixed "
      "joints above the sensor link). "
      "columns: columns of other names read as roles, {ROLE: NAME} (as massid predict "
      "--columns). physical: from the params' physical parameters (identify physical=True), K "
      "pi_phys "
      "into the same predictor.");

  m.def(
      "column_roles",
      [](const py::object& robot, const std::vector<std::string>& names,
         std::optional<std::map<std::string, std::string>> columns) {
        const Model model = model_of(robot, std::nullopt, std::nullopt);
        SampleOptions o;
        o.columns = column_names_of(columns);
        return column_roles(model, names, o);
      },
      py::arg("robot"), py::arg("names"), py::kw_only(), py::arg("columns") = py::none(),
      "The role each of a header's columns is read as (its name, unless columns= {ROLE: NAME} "
      "or a recorder's spelling of the wrench binds it otherwise; '' for a column a binding "
      "displaced or a group ignored): the one binding of the readers, for code that looks "
      "columns up by role.");

  m.def(
      "predict_log",
      [](const py::object& robot, const py::object& params, const py::object& data,
         std::optional<double> cutoff, std::optional<std::vector<double>> root_gravity,
         std::optional<std::vector<double>> level_gravity, bool physical, bool checks,
         std::optional<std::map<std::string, std::string>> columns) {
        const auto p = make_predictor(robot, params, physical);
        return predict_log_of(p->identified, data, cutoff, std::move(root_gravity),
                              std::move(level_gravity), checks, column_names_of(columns));
      },
      py::arg("robot"), py::arg("params"), py::arg("data"), py::kw_only(),
      py::arg("cutoff") = py::none(), py::arg("root_gravity") = py::none(),
      py::arg("level_gravity") = py::none(), py::arg("physical") = false, py::arg("checks") = true,
      py::arg("columns") = py::none(),
      "Predictor(robot, params, physical=physical).predict_log(data, ...): massid predict's "
      "pipeline on a log, its set-up checks and contact notes included (a LogPrediction).");

  m.def(
      "simulate",
      [](const py::object& robot, const py::object& plan, double noise_force, double noise_moment,
         std::optional<std::vector<double>> sensor_offset, std::uint64_t seed, int repeat,
         bool dynamic, std::optional<std::vector<double>> root_gravity,
         std::optional<std::vector<double>> level_gravity,
         std::optional<std::vector<double>> offset,
         std::optional<std::map<std::string, std::string>> columns) {
        if (offset) {  // the old spelling of sensor_offset
          if (sensor_offset)
            throw InputError("offset= is the old spelling of sensor_offset=: give one");
          py::module_::import("warnings")
              .attr("warn")("offset= with six numbers is deprecated: use sensor_offset=",
                            py::module_::import("builtins").attr("DeprecationWarning"), 2);
          sensor_offset = std::move(offset);
        }
        const Model model = model_of(robot, std::nullopt, std::nullopt);
        SampleOptions sopts;
        sopts.root_gravity = root_gravity_of(root_gravity);
        sopts.level_gravity = level_gravity_of(level_gravity);
        sopts.columns = column_names_of(columns);
        sopts.sensor_motion = dynamic;
        py::dict in;
        Samples s;
        if (py::isinstance<Plan>(plan)) {
          const auto& p = plan.cast<const Plan&>();
          in = plan_columns(p);
          s = samples_of(model, in, WrenchColumns::Optional, nullptr, sopts);
        } else {
          in = is_path(plan) ? csv_columns(read_csv(path_of(plan))) : py::dict(plan);
          s = samples_of(model, in, WrenchColumns::Optional, nullptr, sopts);
          if (is_path(plan)) s.source = path_of(plan);
        }
        if (s.gravity_from_force) throw InputError(s.source + ": simulate needs gx,gy,gz columns");
        if (dynamic) {  // as massid simulate --dynamic
          if (model.num_joints() > 0 && s.qd.cols() != model.num_joints())
            throw InputError(
                fmt::format("{}: simulate with dynamic=True needs the trajectory's velocities and "
                            "accelerations: columns JOINT_vel and JOINT_acc for every joint "
                            "(fourier_trajectory makes them)",
                            s.source));
          if (s.q_upstream.cols() > 0 && s.qd_upstream.cols() == 0 && !s.has_sensor_motion())
            throw InputError(fmt::format(
                "{}: simulate with dynamic=True needs the upstream joints' _vel and _acc columns",
                s.source));
        }
        SimulateOptions o;
        if (!(noise_force >= 0) || !(noise_moment >= 0))
          throw InputError("noise_force and noise_moment must be >= 0");
        if (repeat < 1) throw InputError("repeat must be >= 1");
        o.noise_force = noise_force;
        o.noise_moment = noise_moment;
        if (sensor_offset) {
          if (sensor_offset->size() != 6)
            throw InputError("sensor_offset: six numbers fx, fy, fz, mx, my, mz");
          o.offset = Eigen::Map<const Wrench>(sensor_offset->data());
        }
        o.seed = seed;
        o.repeat = repeat;
        o.dynamic = dynamic;
        Eigen::MatrixXd W;
        {
          py::gil_scoped_release release;
          W = simulate_wrenches(model, s, o);
        }
        py::dict out;
        const py::module_ np = py::module_::import("numpy");
        for (const auto& [k, v] : in)
          out[k] = np.attr("repeat")(np.attr("asarray")(v, "float64"), repeat);
        for (int k = 0; k < 6; ++k) out[py::str(kWrenchColumns[k])] = Eigen::VectorXd(W.col(k));
        return out;
      },
      py::arg("robot"), py::arg("plan"), py::kw_only(), py::arg("noise_force") = 0.0,
      py::arg("noise_moment") = 0.0, py::arg("sensor_offset") = py::none(), py::arg("seed") = 1,
      py::arg("repeat") = 1, py::arg("dynamic") = false, py::arg("root_gravity") = py::none(),
      py::arg("level_gravity") = py::none(), py::arg("offset") = py::none(),
      py::arg("columns") = py::none(),
      "The plan's columns (each repeated `repeat` times) with the wrenches fx ... mz that the "
      "URDF's inertials would produce, plus Gaussian noise (N, N m) and a constant offset: a "
      "data set for identify.\n"
      "dynamic=True: the wrench in motion (weight and inertial forces, ten parameters per "
      "link) along a trajectory with JOINT_vel and JOINT_acc columns (fourier_trajectory), "
      "and the sensor's motion wx..az when given (massid simulate --dynamic). root_gravity: "
      "gravity in the URDF root frame for a sensor below movable joints. level_gravity: "
      "gravity in the sensor frame with the platform level, which a plan's tilt_x_deg, "
      "tilt_y_deg turn (default: root_gravity through the fixed joints above the sensor link).");

  // For massid.report: the CLI's atomic write (InputError naming the path).
  m.def(
      "_write_file_atomically",
      [](const py::object& path, const std::string& text) {
        write_file_atomically(path_of(path), text);
      },
      py::arg("path"), py::arg("text"),
      "Writes text to a temporary file beside path and renames it over path.");

  m.def(
      "read_csv", [](const py::object& path) { return csv_columns(read_csv(path_of(path))); },
      py::arg("path"),
      "A CSV's columns as float64 arrays by name (the CLI's reader: InputError names "
      "file:line:column).");
}

}  // namespace massid::python
