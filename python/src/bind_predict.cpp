// Params files, the predictor and simulated measurements (massid/params_file.hpp,
// predictor.hpp, simulate.hpp).
#include <fmt/format.h>
#include <pybind11/stl.h>

#include "bindings.hpp"
#include "convert.hpp"
#include "massid/atomic_file.hpp"
#include "massid/errors.hpp"
#include "massid/params_file.hpp"
#include "massid/predictor.hpp"
#include "massid/simulate.hpp"

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

struct PyPredictor {
  Model model;
  Predictor predictor;
  PredictorData data;

  PyPredictor(Model m, Predictor p)
      : model(std::move(m)), predictor(std::move(p)), data(predictor) {}

  py::object operator()(const py::object& q, const py::object& gravity) {
    const auto [Q, G] = poses_of(model, q, gravity);
    Eigen::MatrixXd W(Q.rows(), 6);
    predict(predictor, data, Q, G, W);
    const py::object ndim = py::module_::import("numpy").attr("ndim");
    const bool single = ndim(q).cast<int>() == 1 && ndim(gravity).cast<int>() == 1;
    return single ? py::cast(Eigen::VectorXd(W.row(0).transpose())) : py::cast(std::move(W));
  }
};

std::unique_ptr<PyPredictor> make_predictor(const py::object& robot, const py::object& params) {
  if (py::isinstance<Identification>(params)) {
    const auto& id = params.cast<const Identification&>();
    if (!robot.is_none()) {
      const Model check = model_for(robot, id.model.sensor_link(), id.model.held);
      if (check.name != id.model.name)
        throw InputError(
            fmt::format("robot '{}' is not the identified robot '{}'", check.name, id.model.name));
    }
    return std::make_unique<PyPredictor>(id.model,
                                         compile_predictor(id.model, id.base, id.summary.value));
  }
  const ParamsFile file = py::isinstance<ParamsFile>(params) ? params.cast<ParamsFile>()
                          : is_path(params)                  ? read_params(path_of(params))
                                                             : throw InputError(
                                                                   "params: expected a params file path, "
                                                                                    "massid.Params or massid.Identification");
  Model model = model_for(robot, file.sensor_link, file.held);
  Predictor predictor = compile_predictor(model, file);
  return std::make_unique<PyPredictor>(std::move(model), std::move(predictor));
}

std::optional<Wrench> optional_wrench(bool present, const Wrench& w) {
  return present ? std::optional<Wrench>(w) : std::nullopt;
}

}  // namespace

void bind_predict(py::module_& m) {
  py::class_<ParamsFile>(m, "Params", "A params file ('massid-params-1') read back.")
      .def_readonly("source", &ParamsFile::source)
      .def_readonly("sensor_link", &ParamsFile::sensor_link)
      .def_readonly("joints", &ParamsFile::joints)
      .def_property_readonly("held", [](const ParamsFile& p) { return held_dict(p.held); })
      .def_readonly("gravity_from", &ParamsFile::gravity_from)
      .def_readonly("samples", &ParamsFile::samples)
      .def_readonly("total_mass", &ParamsFile::total_mass)
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
      .def_property_readonly("residual_rms", [](const ParamsFile& p) { return p.residual_rms; })
      .def("__repr__", [](const ParamsFile& p) {
        return fmt::format("Params('{}', total_mass={:.6g}, {} base parameters)", p.source,
                           p.total_mass, p.base_parameters.size());
      });

  m.def(
      "load_params", [](const py::object& path) { return read_params(path_of(path)); },
      py::arg("path"),
      "Reads a params file written by identify (massid.InputError names file:line:column).");

  py::class_<PyPredictor>(m, "Predictor",
                          "The gravity wrench predictor compiled from identified parameters: "
                          "w = Y_b(q, g) pi_b (paper eq. 29), about 50 ns per pose.")
      .def(py::init(&make_predictor), py::arg("robot"), py::arg("params"),
           "robot: URDF path or Model (None with an Identification); params: a params file "
           "path, massid.Params or massid.Identification.")
      .def_readonly("model", &PyPredictor::model)
      .def_property_readonly("joint_names",
                             [](const PyPredictor& p) { return joint_names(p.model); })
      .def("predict", &PyPredictor::operator(), py::arg("q"), py::arg("gravity"),
           "[N, 6] wrenches for q [N, num_joints] (rad or m) and gravity [N, 3] (m/s^2, sensor "
           "frame); [6] for single vectors.")
      .def("__call__", &PyPredictor::operator(), py::arg("q"), py::arg("gravity"));

  m.def(
      "predict",
      [](const py::object& robot, const py::object& params, const py::object& data) {
        auto p = make_predictor(robot, params);
        const Samples s = samples_of(p->model, data, WrenchColumns::Optional);
        Eigen::MatrixXd W(s.size(), 6);
        predict(p->predictor, p->data, s.q, s.gravity, W);
        return W;
      },
      py::arg("robot"), py::arg("params"), py::arg("data"),
      "[N, 6] predicted gravity wrench at every row of data: a CSV path or columns by name "
      "(joints or JOINT_deg, and gx, gy, gz or a measured force, as massid predict).");

  m.def(
      "simulate",
      [](const py::object& robot, const py::object& plan, double noise_force, double noise_moment,
         std::optional<std::vector<double>> offset, std::uint64_t seed, int repeat) {
        const Model model = model_of(robot, std::nullopt, std::nullopt);
        py::dict in;
        Samples s;
        if (py::isinstance<Plan>(plan)) {
          const auto& p = plan.cast<const Plan&>();
          in = plan_columns(p);
          s = samples_of(model, in, WrenchColumns::Optional);
        } else {
          in = is_path(plan) ? csv_columns(read_csv(path_of(plan))) : py::dict(plan);
          s = samples_of(model, in, WrenchColumns::Optional);
        }
        if (s.gravity_from_force) throw InputError(s.source + ": simulate needs gx,gy,gz columns");
        SimulateOptions o;
        if (!(noise_force >= 0) || !(noise_moment >= 0))
          throw InputError("noise_force and noise_moment must be >= 0");
        if (repeat < 1) throw InputError("repeat must be >= 1");
        o.noise_force = noise_force;
        o.noise_moment = noise_moment;
        if (offset) {
          if (offset->size() != 6) throw InputError("offset: six numbers fx, fy, fz, mx, my, mz");
          o.offset = Eigen::Map<const Wrench>(offset->data());
        }
        o.seed = seed;
        o.repeat = repeat;
        const Eigen::MatrixXd W = simulate_wrenches(model, s, o);
        py::dict out;
        const py::module_ np = py::module_::import("numpy");
        for (const auto& [k, v] : in)
          out[k] = np.attr("repeat")(np.attr("asarray")(v, "float64"), repeat);
        for (int k = 0; k < 6; ++k) out[py::str(kWrenchColumns[k])] = Eigen::VectorXd(W.col(k));
        return out;
      },
      py::arg("robot"), py::arg("plan"), py::kw_only(), py::arg("noise_force") = 0.0,
      py::arg("noise_moment") = 0.0, py::arg("offset") = py::none(), py::arg("seed") = 1,
      py::arg("repeat") = 1,
      "The plan's columns (each repeated `repeat` times) with the wrenches fx ... mz that the "
      "URDF's inertials would produce, plus Gaussian noise (N, N m) and a constant offset: a "
      "data set for identify.");

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
