// Identification (massid/identify/estimation.hpp, identify_file.hpp, setup_checks.hpp,
// params_file.hpp, report.hpp): massid.identify and its result.
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <algorithm>
#include <climits>
#include <limits>

#include "bindings.hpp"
#include "convert.hpp"
#include "hints.hpp"
#include "identify/identify_file.hpp"
#include "io/atomic_file.hpp"
#include "massid/core/errors.hpp"
#include "massid/identify/delay.hpp"
#include "massid/identify/identify_request.hpp"
#include "massid/identify/params_json.hpp"
#include "massid/identify/physical.hpp"
#include "massid/identify/setup_checks.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/report/report.hpp"

namespace massid::python {

namespace {

// The set-up checks (setup_checks.hpp): errors raise InputError with every
// error on its own line; warnings are returned, with their hints.
std::vector<Warning> run_checks(const Model& model, const py::handle& data, const Samples* samples,
                                const std::vector<std::string>& header, bool motion,
                                const SampleOptions& read = {}) {
  SetupCheckOptions o;
  o.read = read;              // the root gravity (a file read here)
  o.constant_joints = false;  // left to the identifiability diagnosis (exit 3), as the CLI
  o.motion = motion;          // the force is not the weight alone
  const std::vector<SetupFinding> findings =
      samples ? check_setup(model, *samples, header, o) : check_setup_file(model, path_of(data), o);
  std::vector<std::string> errors;
  std::vector<Warning> warnings;
  for (const SetupFinding& f : findings)
    if (f.severity == SetupFinding::Severity::Error)
      errors.push_back(with_hints(f.message, f.hints));
    else
      warnings.push_back({f.message, f.hints});
  if (!errors.empty()) throw InputError(fmt::format("{}", fmt::join(errors, "\n")));
  return warnings;
}

Identification run_identify(const py::object& robot, const py::object& data, bool offset,
                            std::optional<std::string> sensor,
                            std::optional<std::map<std::string, double>> fixed, bool robust,
                            std::optional<std::string> drift, std::optional<double> sigma_force,
                            std::optional<double> sigma_moment, bool checks, bool dynamic,
                            std::optional<double> cutoff,
                            std::optional<std::vector<double>> root_gravity,
                            std::optional<std::vector<double>> level_gravity,
                            std::optional<std::string> rest, const py::object& delay, bool physical,
                            std::optional<std::map<std::string, std::string>> columns) {
  // The keywords as a request (identify_request.hpp), checked by its rules.
  IdentifyRequest request;
  request.offset = offset;
  request.dynamic = dynamic;
  request.checks = checks;
  request.robust = robust;
  request.physical = physical;
  request.drift = drift.value_or("");
  request.rest = rest.value_or("");
  if (!delay.is_none())
    request.delay = py::isinstance<py::str>(delay) ? delay.cast<std::string>()
                                                   : fmt::format("{}", delay.cast<double>());
  request.cutoff = cutoff;
  request.sigma_force = sigma_force;
  request.sigma_moment = sigma_moment;
  if (root_gravity) request.root_gravity = root_gravity_of(root_gravity);
  request.level_gravity = level_gravity_of(level_gravity);
  request.columns = column_names_of(columns);
  request.validate(spelling());
  // A URDF path or a Model, the joints below the sensor that the data lack held (with a note).
  std::optional<Warning> held;
  Model model = is_path(data)
                    ? hold_unlogged_file_joints(model_of(robot, sensor, fixed), path_of(data),
                                                request.sample_options(), &held)
                    : hold_unlogged_joints(model_of(robot, sensor, fixed), columns_of(data).names,
                                           "data", request.sample_options(), &held);
  if (held) warn_note(with_hints(held->message, held->hints));
  std::vector<Warning> notes;
  Identification out;
  if (is_path(data)) {
    // As massid identify [--dynamic]: streamed where it can be.
    const std::string path = path_of(data);
    warn_note(file_column_note(model, path, request.sample_options()));
    if (checks) notes = run_checks(model, data, nullptr, {}, dynamic, request.sample_options());
    py::gil_scoped_release release;
    out = identify(std::move(model), request, IdentifySource::file(path));
  } else {
    // Columns in memory: the same steps on the samples.
    std::vector<std::string> header;
    Samples raw =
        samples_of(model, data, WrenchColumns::Required, &header, request.sample_options());
    warn_note(
        column_note(model, header, "data", WrenchColumns::Required, request.sample_options()));
    if (checks)
      notes = run_checks(model, data, &raw, column_roles(model, header, request.sample_options()),
                         dynamic);
    py::gil_scoped_release release;
    out = identify(std::move(model), request, IdentifySource::data(std::move(raw)));
  }
  out.warnings.insert(out.warnings.begin(), notes.begin(), notes.end());
  const py::object warn = py::module_::import("warnings").attr("warn");
  const py::object category = py::module_::import("massid").attr("MassidWarning");
  for (const Warning& w : out.warnings) warn(with_hints(w.message, w.hints), category, 3);
  return out;
}

double nan_or(bool present, double v) {
  return present ? v : std::numeric_limits<double>::quiet_NaN();
}

// A motion part of the samples (None at rest or when absent).
std::optional<Eigen::MatrixXd> optional_matrix_of(const Eigen::MatrixXd& m, bool motion) {
  return motion && m.cols() > 0 ? std::optional<Eigen::MatrixXd>(m) : std::nullopt;
}

std::optional<Eigen::VectorXd> optional_vector(bool present, const Eigen::VectorXd& v) {
  return present ? std::optional<Eigen::VectorXd>(v) : std::nullopt;
}

}  // namespace

void bind_identify(py::module_& m) {
  py::class_<PhysicalLink>(
      m, "PhysicalLink",
      "One link's physically consistent parameters (massid/identify/physical.hpp).")
      .def_readonly("name", &PhysicalLink::name)
      .def_readonly("mass", &PhysicalLink::mass, "kg")
      .def_readonly("com", &PhysicalLink::com, "[3] centre of mass, link frame, m")
      .def_readonly("inertia_com", &PhysicalLink::inertia_com,
                    "[3, 3] rotational inertia about the centre of mass, link frame, kg m^2")
      .def_readonly("principal_moments", &PhysicalLink::principal_moments,
                    "[3] principal moments about the centre of mass, ascending")
      .def_readonly("min_eigenvalue", &PhysicalLink::min_eigenvalue,
                    "smallest eigenvalue of the pseudo-inertia J, kg m^2")
      .def_readonly("consistent", &PhysicalLink::consistent, "m > 0 and J >= 0 (round-off)")
      .def_readonly("prior_body", &PhysicalLink::prior_body,
                    "the URDF gave no mass: the prior was a tiny body")
      .def("__repr__", [](const PhysicalLink& l) {
        return fmt::format("PhysicalLink('{}', mass={:.6g}, consistent={})", l.name, l.mass,
                           l.consistent ? "True" : "False");
      });
  py::class_<PhysicalSummary>(m, "PhysicalSummary",
                              "Physically consistent standard parameters fitted to identified "
                              "base parameters (massid/identify/physical.hpp).")
      .def_readonly("standard", &PhysicalSummary::standard,
                    "[10 num_links] m, mx, my, mz, ixx .. izz per link (inertia about the link "
                    "origin)")
      .def_readonly("links", &PhysicalSummary::links)
      .def_readonly("mismatch", &PhysicalSummary::mismatch,
                    "[num base parameters] (K pi_phys - identified) / std")
      .def_readonly("worst", &PhysicalSummary::worst, "index of the worst mismatch (-1: none)")
      .def_readonly("worst_mismatch", &PhysicalSummary::worst_mismatch)
      .def_readonly("static_layout", &PhysicalSummary::static_layout)
      .def_readonly("cost", &PhysicalSummary::cost)
      .def_readonly("iterations", &PhysicalSummary::iterations)
      .def_readonly("solve_seconds", &PhysicalSummary::solve_seconds)
      .def_readonly("converged", &PhysicalSummary::converged)
      .def_property_readonly("consistent", &PhysicalSummary::consistent)
      .def("__repr__", [](const PhysicalSummary& p) {
        return fmt::format("PhysicalSummary({} links, consistent={}, worst mismatch {:.3g} std)",
                           p.links.size(), p.consistent() ? "True" : "False", p.worst_mismatch);
      });
  py::class_<Outlier>(m, "Outlier", "A sample whose residual is implausible for the fitted noise.")
      .def_readonly("sample", &Outlier::sample, "row in the data")
      .def_readonly("line", &Outlier::line, "file line (row index for columns given as arrays)")
      .def_readonly("score", &Outlier::score,
                    "standardised residual norm d, chi with 6 degrees of freedom")
      .def("__repr__", [](const Outlier& o) {
        return fmt::format("Outlier(sample={}, line={}, score={:.3g})", o.sample, o.line, o.score);
      });

  using I = Identification;
  const auto sum = [](const I& i) -> const IdentifySummary& { return i.summary; };
  py::class_<I>(m, "Identification",
                "Identified base parameters (paper eqs. 32-36) with the samples they came from. "
                "Attributes mirror the params file.")
      .def_readonly("model", &I::model)
      .def_property_readonly("source", [](const I& i) { return i.samples.source; })
      .def_property_readonly(
          "total_mass",
          [sum](const I& i) {
            return nan_or(i.base.total_mass >= 0, sum(i).value[std::max(i.base.total_mass, 0)]);
          },
          "kg; nan when not identifiable (dynamic, constant gravity, offsets)")
      .def_property_readonly("total_mass_std",
                             [sum](const I& i) {
                               return nan_or(i.base.total_mass >= 0,
                                             sum(i).stddev[std::max(i.base.total_mass, 0)]);
                             })
      .def_property_readonly(
          "dynamic", [](const I& i) { return i.base.motion(); },
          "identified in motion (ten parameters per link; dynamic=True)")
      .def_property_readonly("base_parameters",
                             [sum](const I& i) {
                               std::vector<NamedParameter> out;
                               for (int k = 0; k < i.base.num_mass(); ++k) {
                                 NamedParameter p = named_parameter(i.model, i.base.params[k]);
                                 p.value = sum(i).value[k];
                                 p.std = sum(i).stddev[k];
                                 out.push_back(std::move(p));
                               }
                               return out;
                             })
      .def_property_readonly("unknown_names", [](const I& i) { return unknown_names(i.base); })
      .def_property_readonly(
          "values", [sum](const I& i) { return sum(i).value; },
          "[p] base parameters, then the offsets")
      .def_property_readonly("std", [sum](const I& i) { return sum(i).stddev; })
      .def_property_readonly("covariance", [sum](const I& i) { return sum(i).covariance; })
      .def_property_readonly("correlation",
                             [sum](const I& i) {
                               const Eigen::MatrixXd& C = sum(i).covariance;
                               const Eigen::VectorXd d = C.diagonal().cwiseSqrt();
                               Eigen::MatrixXd R = C.array() / (d * d.transpose()).array();
                               return R;
                             })
      .def_property_readonly("offset",
                             [sum](const I& i) {
                               return optional_vector(i.base.offset,
                                                      sum(i).value.tail(i.base.offset ? 6 : 0));
                             })
      .def_property_readonly("offset_std",
                             [sum](const I& i) {
                               return optional_vector(i.base.offset,
                                                      sum(i).stddev.tail(i.base.offset ? 6 : 0));
                             })
      .def_property_readonly("condition_number",
                             [sum](const I& i) { return sum(i).condition_number; })
      .def_property_readonly("chi2_per_dof", [sum](const I& i) { return sum(i).chi2_per_dof; })
      .def_property_readonly("sigma", [sum](const I& i) { return sum(i).sigma; })
      .def_property_readonly("sigma_estimated",
                             [sum](const I& i) { return sum(i).sigma_estimated; })
      .def_property_readonly("samples", [sum](const I& i) { return sum(i).samples; })
      .def_property_readonly("residual_rms", [sum](const I& i) { return sum(i).residual_rms; })
      .def_property_readonly("residual_max", [sum](const I& i) { return sum(i).residual_max; })
      .def_property_readonly("q", [](const I& i) { return i.samples.q; })
      .def_property_readonly(
          "qd", [](const I& i) { return optional_matrix_of(i.samples.qd, i.base.motion()); },
          "[N, num_joints] joint velocities (dynamic; derived when the log had none), else None")
      .def_property_readonly(
          "qdd", [](const I& i) { return optional_matrix_of(i.samples.qdd, i.base.motion()); },
          "[N, num_joints] joint accelerations (dynamic), else None")
      .def_property_readonly(
          "sensor_motion",
          [](const I& i) { return optional_matrix_of(i.samples.sensor_motion, i.base.motion()); },
          "[N, 9] wx wy wz, dwx dwy dwz, ax ay az of the sensor frame (dynamic, when the data "
          "have it), else None")
      .def_property_readonly(
          "filter",
          [](const I& i) -> py::object {
            if (!i.motion.derived) return py::none();
            py::dict d;
            d["cutoff"] = i.motion.kernels.cutoff;
            d["rate"] = 1.0 / i.motion.kernels.dt;
            d["half_width"] = i.motion.kernels.half_width;
            d["decimation"] = i.motion.decimation;
            d["rows"] = i.motion.rows;
            return d;
          },
          "dynamic, derivatives derived from t and the positions: the zero-phase low-pass "
          "(cutoff Hz, rate Hz, half_width samples dropped at each end, decimation, rows of the "
          "data); None otherwise")
      .def_property_readonly("gravity", [](const I& i) { return i.samples.gravity; })
      .def_property_readonly("wrench", [](const I& i) { return i.samples.wrench; })
      .def_property_readonly("fitted", [](const I& i) { return i.fitted; })
      .def_property_readonly(
          "residuals", [](const I& i) { return Eigen::MatrixXd(i.samples.wrench - i.fitted); })
      .def_property_readonly("lines",
                             [](const I& i) {
                               py::array_t<long> a(static_cast<py::ssize_t>(i.samples.line.size()));
                               std::copy(i.samples.line.begin(), i.samples.line.end(),
                                         a.mutable_data());
                               return a;
                             })
      .def_property_readonly(
          "time",
          [](const I& i) { return optional_vector(i.samples.time.size() > 0, i.samples.time); })
      .def_property_readonly("gravity_from_force",
                             [sum](const I& i) { return sum(i).gravity_from_force; })
      .def_property_readonly("outliers", [sum](const I& i) { return sum(i).outliers; })
      .def_property_readonly("outlier_threshold",
                             [sum](const I& i) { return sum(i).outlier_threshold; })
      .def_property_readonly("robust", [sum](const I& i) { return sum(i).robust; })
      .def_property_readonly(
          "used",
          [sum](const I& i) {
            py::array_t<bool> a(i.samples.size());
            bool* p = a.mutable_data();
            std::fill(p, p + i.samples.size(), true);
            if (sum(i).robust)
              for (const Outlier& o : sum(i).outliers) p[o.sample] = false;
            return a;
          },
          "[N] False for the samples that robust=True rejected")
      .def_property_readonly(
          "delay",
          [sum](const I& i) -> py::object {
            const DelayEstimate& d = sum(i).delay;
            if (!d.applied) return py::none();
            py::dict out;
            out["value"] = d.value;
            out["std"] = d.std;
            out["estimated"] = d.estimated;
            py::list scan;
            for (const auto& point : d.scan) scan.append(py::make_tuple(point[0], point[1]));
            out["scan"] = scan;
            return out;
          },
          "dynamic with delay: the wrench's lag applied (value and std in s, estimated, the scan "
          "of (delay, chi^2)); None when none was")
      .def_property_readonly(
          "rest_windows",
          [sum](const I& i) -> py::object {
            const RestWindows& w = sum(i).rest;
            if (!w.continuous) return py::none();
            py::list windows;
            for (const RestWindow& r : w.windows) windows.append(py::make_tuple(r.first, r.last));
            py::dict d;
            d["windows"] = windows;
            d["samples"] = w.samples;
            d["rows"] = w.rows;
            d["moving"] = w.moving;
            d["criterion"] = w.criterion;
            d["trimmed"] = w.trimmed;
            d["longest_settling"] = w.longest_settling;
            return d;
          },
          "a continuous static log: its rest windows as (first, last) rows of the log, samples, "
          "rows, moving rows and what moved, rows trimmed where the wrench had not settled and the "
          "longest such cut at a window's start (s); None when every row is a sample")
      .def_property_readonly(
          "quasi_static",
          [sum](const I& i) -> py::object {
            const RestWindows& w = sum(i).rest;
            if (!w.quasi_static) return py::none();
            py::dict d;
            d["rows"] = w.rows;
            d["windowed_samples"] = w.windowed_samples;
            d["max_speed"] = w.max_speed;
            d["inertial_force"] = w.inertial_force;
            d["inertial_moment"] = w.inertial_moment;
            d["noise_force"] = w.noise_force;
            d["noise_moment"] = w.noise_moment;
            return d;
          },
          "a continuous static log too slow for its motion to show: every row was a sample, "
          "with the numbers that justify it (the joints' largest speed, the largest inertial "
          "force and moment from the URDF's inertials, the force and moment noise, the rows the "
          "rest windows would have kept); None otherwise")
      .def_property_readonly("drift",
                             [sum](const I& i) -> py::object {
                               switch (sum(i).drift) {
                                 case Drift::Linear:
                                   return py::str("linear");
                                 case Drift::PerBlock:
                                   return py::str("per-block");
                                 default:
                                   return py::none();
                               }
                             })
      .def_property_readonly("drift_names", [sum](const I& i) { return sum(i).drift_names; })
      .def_property_readonly("drift_values", [sum](const I& i) { return sum(i).drift_value; })
      .def_property_readonly("drift_std", [sum](const I& i) { return sum(i).drift_stddev; })
      .def_readonly("physical", &I::physical,
                    "physical=True: the physically consistent parameters (PhysicalSummary), "
                    "else None")
      .def_property_readonly(
          "warnings",
          [](const I& i) {
            std::vector<std::string> out;
            for (const Warning& w : i.warnings) out.push_back(with_hints(w.message, w.hints));
            return out;
          },
          "The fit's warnings (MassidWarning), one line each, the hints as keywords.")
      .def(
          "report",
          [sum](const I& i) { return identify_report(i.model, i.base, sum(i), i.samples.source); },
          "The text report that massid identify prints.")
      .def(
          "to_json",
          [sum](const I& i) {
            return params_json(i.model, i.base, &sum(i), i.physical ? &*i.physical : nullptr);
          },
          "The params file's text ('massid-params-1').")
      .def(
          "save",
          [sum](const I& i, const py::object& path) {
            write_file_atomically(path_of(path), params_json(i.model, i.base, &sum(i),
                                                             i.physical ? &*i.physical : nullptr));
          },
          py::arg("path"), "Writes the params file (atomically: never half-written).")
      .def(
          "predictor",
          [](const py::object& self) {
            return py::module_::import("massid").attr("Predictor")(py::none(), self);
          },
          "A Predictor of these parameters.")
      .def("__repr__", [sum](const I& i) {
        const std::string mass =
            i.base.total_mass >= 0
                ? fmt::format("total_mass={:.6g} +- {:.2g} kg", sum(i).value[i.base.total_mass],
                              sum(i).stddev[i.base.total_mass])
                : std::string("total_mass not identifiable");
        return fmt::format("Identification('{}'{}, {}, {} samples, condition number {:.4g})",
                           i.model.name, i.base.motion() ? ", dynamic" : "", mass, sum(i).samples,
                           sum(i).condition_number);
      });

  m.def(
      "load_identification",
      [](const py::object& path) {
        const std::string p = path_of(path);
        py::gil_scoped_release release;
        return read_identification(p);
      },
      py::arg("path"),
      R"(An identification from the record `massid identify --report` hands to the report
(massid/identify/identification.hpp): the fit the command printed, with its samples, without
fitting again. Loads the URDF named in it. Raises InputError for a file that is not such
a record or whose URDF no longer gives the same base parameters.)");
  m.def("identify", &run_identify, py::arg("robot"), py::arg("data"), py::kw_only(),
        py::arg("offset") = false, py::arg("sensor") = py::none(), py::arg("fixed") = py::none(),
        py::arg("robust") = false, py::arg("drift") = py::none(),
        py::arg("sigma_force") = py::none(), py::arg("sigma_moment") = py::none(),
        py::arg("checks") = true, py::arg("dynamic") = false, py::arg("cutoff") = py::none(),
        py::arg("root_gravity") = py::none(), py::arg("level_gravity") = py::none(),
        py::arg("rest") = py::none(), py::arg("delay") = py::none(), py::arg("physical") = false,
        py::arg("columns") = py::none(),
        R"(Identifies the base parameters from measured wrenches (massid identify [--dynamic]).

robot: URDF path or Model. data: a CSV path (streamed, as the CLI) or columns by name
(joints or JOINT_deg, gx, gy, gz, fx ... mz, optional t and block). offset: estimate the six
sensor offsets; sensor: sensor link; fixed: joints held still, name -> position;
robust: reject samples with implausible residuals; drift: 'linear' (column t) or
'per-block' (column block); sigma_force / sigma_moment: noise (default: from residuals);
checks: the set-up checks (sign, frame, units, gravity, columns). rest: a static log
with t recorded while the robot moved from pose to pose: 'auto' (None: the default) uses
only its rest windows (.rest_windows says which), 'off' every row. delay (dynamic): the lag of the wrench
behind the joint stream, s (positive when the wrench arrives late), or 'auto' to estimate it
within +-20 ms (.delay says what was applied). physical: also fit ten physically consistent
standard parameters per link that reproduce the base parameters, the URDF's inertials where the
data cannot see (.physical, a PhysicalSummary; saved under "physical"). root_gravity: gravity
in the URDF root frame, for a sensor below movable joints whose columns the data have (they
then give gravity in the sensor frame when there are no gx,gy,gz), at rest and in motion.
level_gravity: gravity in the sensor frame with the platform level, which the data's
tilt_x_deg, tilt_y_deg turn when they have no gx,gy,gz (default: root_gravity through the
fixed joints above the sensor link; an error when the data's gravity comes from elsewhere).
dynamic: identification in motion, ten parameters per link (inertia about the link origin):
the data add JOINT_vel and JOINT_acc, or t to derive them from the positions by a zero-phase
low-pass (cutoff Hz; default min(10, rate/20)); optionally wx..wz, dwx..dwz, ax..az (sensor
motion) and the joints above the sensor link (with their _vel, _acc). columns: columns of
other names read as roles, {ROLE: NAME} (e.g. {'mx': 'tx', 'my': 'ty', 'mz': 'tz'}); the
recorders' common spellings of the wrench (Fx, tx, torque_x, field.wrench.force.x,
/ft_sensor/wrench/force/x, ...) are recognised without it, with a MassidWarning naming them.
Raises InputError (bad input, failed check) or IdentifiabilityError; warnings are issued
as MassidWarning and kept in .warnings.)");
}

}  // namespace massid::python
