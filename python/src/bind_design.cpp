// Experiment design (massid/design/design.hpp): massid.design and its Plan.
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <numbers>

#include "bindings.hpp"
#include "convert.hpp"
#include "hints.hpp"
#include "massid/core/errors.hpp"
#include "massid/report/report.hpp"

namespace massid::python {

namespace {

constexpr double kDeg = std::numbers::pi / 180.0;

Plan run_design(const py::object& robot, int poses, std::optional<std::string> sensor,
                std::optional<std::map<std::string, double>> fixed, bool offset,
                std::optional<double> tilt_max_deg, int tilt_groups,
                std::optional<std::vector<std::pair<double, double>>> tilts_deg,
                std::optional<std::map<std::string, std::pair<double, double>>> limits,
                std::optional<double> min_height, const std::string& criterion, double noise_force,
                double noise_moment, std::vector<double> level_gravity, std::uint64_t seed,
                int candidates, std::optional<int> level_poses) {
  Plan out;
  out.model = model_of(robot, sensor, fixed);
  BaseParameterOptions bopts;
  bopts.offset = offset;
  out.base = find_base_parameters(out.model, bopts);
  DesignOptions& o = out.options;
  if (poses < 1) throw InputError("poses must be >= 1");
  o.poses = poses;
  if (tilt_max_deg && tilts_deg) throw InputError("give tilt_max_deg or tilts_deg, not both");
  if (tilt_max_deg) {
    if (!(*tilt_max_deg >= 0 && *tilt_max_deg < 90))
      throw InputError(fmt::format("tilt_max_deg: {} is not in [0, 90)", *tilt_max_deg));
    o.tilt_max = *tilt_max_deg * kDeg;
    if (tilt_groups < 0) throw InputError("tilt_groups must be >= 0");
    o.tilt_groups = tilt_groups;
  }
  if (tilts_deg)
    for (const auto& [x, y] : *tilts_deg) o.tilts.push_back({x * kDeg, y * kDeg});
  if (limits) o.limits = *limits;
  o.min_height = min_height;
  if (level_poses) {
    if (*level_poses < 0) throw InputError("level_poses must be >= 0");
    o.level_poses = *level_poses;
  }
  if (criterion == "cond")
    o.criterion = Criterion::Cond;
  else if (criterion == "d-opt")
    o.criterion = Criterion::DOpt;
  else
    throw InputError(fmt::format("criterion: '{}' is not 'cond' or 'd-opt'", criterion));
  if (!(noise_force > 0) || !(noise_moment > 0))
    throw InputError("noise_force and noise_moment must be > 0");
  o.noise_force = noise_force;
  o.noise_moment = noise_moment;
  if (level_gravity.size() != 3) throw InputError("level_gravity: three numbers gx, gy, gz");
  o.level_gravity = Eigen::Map<const Eigen::Vector3d>(level_gravity.data());
  o.seed = seed;
  o.candidates = candidates;
  // A sensor below movable joints: the arm held still with level_gravity in
  // the sensor frame, as before (the arm's poses: the CLI's design, not yet
  // this door's plan columns).
  o.move_arm = false;
  py::gil_scoped_release release;
  out.summary = design(out.model, out.base, o);
  return out;
}

}  // namespace

py::dict plan_columns(const Plan& p) {
  const auto& plan = p.summary.plan;
  const Eigen::Index N = static_cast<Eigen::Index>(plan.size());
  py::dict out;
  const auto add = [&](const std::string& name, auto&& value_of) {
    py::array_t<double> a(N);
    double* d = a.mutable_data();
    for (Eigen::Index i = 0; i < N; ++i) d[i] = value_of(plan[i]);
    out[py::str(name)] = a;
  };
  for (int j = 0; j < p.model.num_joints(); ++j)
    add(p.model.joints[j].name, [j](const PlanPose& pose) { return pose.q[j]; });
  for (const auto& [name, value] : p.model.held)
    add(name, [v = value](const PlanPose&) { return v; });
  for (int k = 0; k < 3; ++k)
    add(std::string("g") + "xyz"[k], [k](const PlanPose& pose) { return pose.gravity[k]; });
  add("tilt_x_deg", [](const PlanPose& pose) { return pose.tilt.x / kDeg; });
  add("tilt_y_deg", [](const PlanPose& pose) { return pose.tilt.y / kDeg; });
  return out;
}

void bind_design(py::module_& m) {
  py::class_<Plan>(m, "Plan", "A designed experiment: poses in the order to run them.")
      .def_property_readonly("joint_names", [](const Plan& p) { return joint_names(p.model); })
      .def_property_readonly("q",
                             [](const Plan& p) {
                               Eigen::MatrixXd Q(p.summary.plan.size(), p.model.num_joints());
                               for (size_t i = 0; i < p.summary.plan.size(); ++i)
                                 Q.row(i) = p.summary.plan[i].q.transpose();
                               return Q;
                             })
      .def_property_readonly("gravity",
                             [](const Plan& p) {
                               Eigen::MatrixXd G(p.summary.plan.size(), 3);
                               for (size_t i = 0; i < p.summary.plan.size(); ++i)
                                 G.row(i) = p.summary.plan[i].gravity.transpose();
                               return G;
                             })
      .def_property_readonly("tilt_deg",
                             [](const Plan& p) {
                               Eigen::MatrixXd T(p.summary.plan.size(), 2);
                               for (size_t i = 0; i < p.summary.plan.size(); ++i)
                                 T.row(i) << p.summary.plan[i].tilt.x / kDeg,
                                     p.summary.plan[i].tilt.y / kDeg;
                               return T;
                             })
      .def_property_readonly("condition_number",
                             [](const Plan& p) { return p.summary.condition_number; })
      .def_property_readonly("log_det", [](const Plan& p) { return p.summary.log_det; })
      .def_property_readonly("identifiable", [](const Plan& p) { return p.summary.identifiable; })
      .def_property_readonly("identifiability_message",
                             [](const Plan& p) { return p.summary.identifiability_message; })
      .def_property_readonly("unknown_names", [](const Plan& p) { return unknown_names(p.base); })
      .def_property_readonly("predicted_std", [](const Plan& p) { return p.summary.predicted_std; })
      .def_property_readonly("expected_error",
                             [](const Plan& p) { return p.summary.expected_error; })
      .def_property_readonly("tilt_changes", [](const Plan& p) { return p.summary.tilt_changes; })
      .def_property_readonly("joint_travel", [](const Plan& p) { return p.summary.joint_travel; })
      .def_property_readonly("seconds", [](const Plan& p) { return p.summary.seconds; })
      .def("columns", &plan_columns,
           "The plan CSV's columns: joints (held ones too), gx, gy, gz, tilt_x_deg, tilt_y_deg.")
      .def(
          "save",
          [](const Plan& p, const py::object& path) {
            write_plan(path_of(path), p.model, p.summary.plan);
          },
          py::arg("path"), "Writes the plan CSV (as massid design -o).")
      .def(
          "report",
          [](const Plan& p) {
            return design_report(p.model, p.base, p.summary, p.options, "", spell);
          },
          "The text report that massid design prints.")
      .def("__len__", [](const Plan& p) { return p.summary.plan.size(); })
      .def("__repr__", [](const Plan& p) {
        return fmt::format("Plan({} poses, condition number {:.4g})", p.summary.plan.size(),
                           p.summary.condition_number);
      });

  m.def("design", &run_design, py::arg("robot"), py::arg("poses") = 30, py::kw_only(),
        py::arg("sensor") = py::none(), py::arg("fixed") = py::none(), py::arg("offset") = false,
        py::arg("tilt_max_deg") = py::none(), py::arg("tilt_groups") = 4,
        py::arg("tilts_deg") = py::none(), py::arg("limits") = py::none(),
        py::arg("min_height") = kDefaultMinHeight, py::arg("criterion") = "cond",
        py::arg("noise_force") = 0.05, py::arg("noise_moment") = 0.005,
        py::arg("level_gravity") = std::vector<double>{0.0, 0.0, -kStandardGravity},
        py::arg("seed") = 1, py::arg("candidates") = 0, py::arg("level_poses") = py::none(),
        R"(Chooses static poses that determine the base parameters well (massid design).

tilt_max_deg: any platform tilt up to this angle (with tilt_groups shared tilts, 0: one
per pose); tilts_deg: or only these (x, y) tilts; neither: level only. limits: joint ->
(lo, hi) narrowed range; min_height: every moving link origin, centre of mass and primitive collision shape at least
this far above the platform plane, m (default 0.05; None: no constraint); with tilts, a quarter
of the poses are kept level (level_poses: how many; 0: the optimiser chooses every tilt); criterion:
'cond' (paper eq. 36) or 'd-opt'; noise_*: per-axis noise for the predicted std.)");
}

}  // namespace massid::python
