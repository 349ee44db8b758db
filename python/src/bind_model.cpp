// Model, base parameters and regressors (massid/core/model.hpp, base_parameters.hpp,
// regressor.hpp, base_regressor.hpp).
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>

#include "bindings.hpp"
#include "convert.hpp"
#include "massid/core/base_regressor.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/regressor.hpp"
#include "massid/identify/params_json.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/urdf.hpp"
#include "massid/report/report.hpp"

namespace massid::python {

const char* joint_type_name(JointType t) {
  switch (t) {
    case JointType::Revolute:
      return "revolute";
    case JointType::Prismatic:
      return "prismatic";
    default:
      return "fixed";
  }
}

std::vector<std::string> joint_names(const Model& model) {
  std::vector<std::string> n;
  for (const Joint& j : model.joints) n.push_back(j.name);
  return n;
}

std::vector<std::string> unknown_names(const BaseParameters& base) {
  std::vector<std::string> n;
  for (int k = 0; k < base.num_unknowns(); ++k) n.push_back(base.unknown_name(k));
  return n;
}

NamedParameter named_parameter(const Model& model, const BaseParameter& p) {
  NamedParameter out;
  out.name = p.name;
  out.unit = p.unit;
  out.expression = p.expression;
  for (const Term& t : p.terms)
    out.terms.emplace_back(model.links[t.link].name, standard_parameter_kind(t.param), t.coef);
  out.value = out.std = std::numeric_limits<double>::quiet_NaN();
  return out;
}

namespace {

// [N, 6, cols] from N blocks of 6 x cols.
template <class Fill>
py::array_t<double> stacked(Eigen::Index N, Eigen::Index cols, Fill&& fill) {
  py::array_t<double> out({N, Eigen::Index(6), cols});
  auto r = out.mutable_unchecked<3>();
  Eigen::MatrixXd block(6, cols);
  for (Eigen::Index i = 0; i < N; ++i) {
    fill(i, block);
    for (int k = 0; k < 6; ++k)
      for (Eigen::Index c = 0; c < cols; ++c) r(i, k, c) = block(k, c);
  }
  return out;
}

std::string joint_list(const Model& model) {
  return fmt::format("q (joints {})", fmt::join(joint_names(model), ", "));
}

}  // namespace

MotionArrays motion_arrays(const Model& model, Eigen::Index rows, const py::handle& qd,
                           const py::handle& qdd, const py::handle& sensor_motion) {
  MotionArrays m;
  if (qd.is_none() != qdd.is_none())
    throw InputError("qd and qdd: give both (velocities and accelerations), or neither");
  m.present = !qd.is_none();
  if (!m.present) {
    if (!sensor_motion.is_none()) throw InputError("sensor_motion goes with qd and qdd");
    return m;
  }
  const std::string joints = fmt::format("(joints {})", fmt::join(joint_names(model), ", "));
  m.qd = optional_matrix(qd, rows, model.num_joints(), "qd " + joints);
  m.qdd = optional_matrix(qdd, rows, model.num_joints(), "qdd " + joints);
  m.sensor_motion = optional_matrix(sensor_motion, rows, 9,
                                    "sensor_motion (wx, wy, wz, dwx, dwy, dwz, ax, ay, az)");
  return m;
}

FrameMotion MotionArrays::sensor(Eigen::Index i) const {
  FrameMotion f;
  if (sensor_motion.cols() == 9) {
    f.omega = sensor_motion.block<1, 3>(i, 0).transpose();
    f.omega_dot = sensor_motion.block<1, 3>(i, 3).transpose();
    f.accel = sensor_motion.block<1, 3>(i, 6).transpose();
  }
  return f;
}

std::pair<Eigen::MatrixXd, Eigen::MatrixXd> poses_of(const Model& model, const py::handle& q,
                                                     const py::handle& gravity) {
  Eigen::MatrixXd Q = to_matrix(q, model.num_joints(), joint_list(model));
  Eigen::MatrixXd G = to_matrix(gravity, 3, "gravity (gx, gy, gz)");
  if (Q.rows() != G.rows())
    throw InputError(
        fmt::format("q has {} rows and gravity {}: one of each per sample", Q.rows(), G.rows()));
  return {std::move(Q), std::move(G)};
}

void bind_model(py::module_& m) {
  py::class_<Joint>(m, "Joint", "A movable joint of the measured subtree.")
      .def_readonly("name", &Joint::name)
      .def_property_readonly(
          "type", [](const Joint& j) { return joint_type_name(j.type); },
          "'revolute' (continuous too) or 'prismatic'")
      .def_readonly("continuous", &Joint::continuous)
      .def_readonly("limited", &Joint::limited)
      .def_readonly("lower", &Joint::lower, "lower limit, rad or m")
      .def_readonly("upper", &Joint::upper, "upper limit, rad or m")
      .def_readonly("velocity_limit", &Joint::velocity_limit,
                    "the URDF's <limit velocity>, rad/s or m/s; 0 when not given")
      .def("__repr__", [](const Joint& j) {
        return fmt::format("Joint('{}', {}{})", j.name, joint_type_name(j.type),
                           j.limited ? fmt::format(", [{:.6g}, {:.6g}]", j.lower, j.upper) : "");
      });

  py::class_<Link>(m, "Link", "A measured link (the sensor link and its subtree).")
      .def_readonly("name", &Link::name)
      .def_readonly("parent", &Link::parent, "index in Model.links, -1 for the sensor link")
      .def_readonly("joint", &Link::joint, "joint from the parent ('' for the sensor link)")
      .def_property_readonly("joint_type", [](const Link& l) { return joint_type_name(l.type); })
      .def_readonly("mass", &Link::mass, "nominal mass from the URDF, kg")
      .def_property_readonly(
          "com", [](const Link& l) { return l.com; }, "nominal centre of mass in the link frame, m")
      .def("__repr__", [](const Link& l) { return fmt::format("Link('{}')", l.name); });

  py::class_<Model>(m, "Model",
                    "The measured bodies of a URDF: the sensor link and its subtree. Immutable.")
      .def_readonly("name", &Model::name)
      .def_readonly("source", &Model::source)
      .def_property_readonly("sensor_link", &Model::sensor_link)
      .def_readonly("links", &Model::links)
      .def_readonly("joints", &Model::joints)
      .def_property_readonly("joint_names", &joint_names)
      .def_property_readonly(
          "held", [](const Model& mo) { return held_dict(mo.held); },
          "joints held still: name -> position (rad or m)")
      .def_property_readonly("num_joints", &Model::num_joints)
      .def_property_readonly("num_links", &Model::num_links)
      .def_property_readonly("nominal_total_mass", &Model::nominal_total_mass)
      .def_property_readonly("standard_parameter_names",
                             [](const Model& mo) {
                               std::vector<std::string> n;
                               for (int i = 0; i < num_standard_parameters(mo); ++i)
                                 n.push_back(standard_parameter_name(mo, i));
                               return n;
                             })
      .def(
          "nominal_parameters",
          [](const Model& mo, bool dynamic) {
            return dynamic ? ParameterLayout::full().nominal(mo) : nominal_standard_parameters(mo);
          },
          py::arg("dynamic") = false,
          "[4 L] the URDF's inertials as standard parameters: m, mx, my, mz per link; "
          "dynamic=True: [10 L] m, mx, my, mz, ixx, ixy, ixz, iyy, iyz, izz per link (inertia "
          "about the link origin, link frame)")
      .def(
          "parameter_names",
          [](const Model& mo, bool dynamic) {
            const ParameterLayout layout =
                dynamic ? ParameterLayout::full() : ParameterLayout::first_moments();
            std::vector<std::string> n;
            for (int i = 0; i < layout.size(mo); ++i) n.push_back(layout.name(mo, i));
            return n;
          },
          py::arg("dynamic") = false,
          "Names of the standard parameters, 'm(link)', 'mx(link)', ... ([4 L]; dynamic=True: "
          "[10 L] with 'ixx(link)' ... 'izz(link)')")
      .def("__repr__", [](const Model& mo) {
        return fmt::format("Model('{}', sensor_link='{}', {} links, {} joints)", mo.name,
                           mo.sensor_link(), mo.num_links(), mo.num_joints());
      });

  m.def(
      "load_model",
      [](const py::object& urdf, std::optional<std::string> sensor,
         std::optional<std::map<std::string, double>> fixed) {
        if (!is_path(urdf)) throw InputError("urdf: expected a path");
        return model_of(urdf, sensor, fixed);
      },
      py::arg("urdf"), py::arg("sensor") = py::none(), py::arg("fixed") = py::none(),
      "Loads a URDF. sensor: the sensor link (default: the root link); fixed: joints held "
      "still, name -> position (rad or m).");
  m.def(
      "load_model_string",
      [](const std::string& xml, std::optional<std::string> sensor,
         std::optional<std::map<std::string, double>> fixed) {
        return hold_joints(
            load_urdf_string(xml, sensor.value_or("")),
            fixed ? held_list(*fixed) : std::vector<std::pair<std::string, double>>{});
      },
      py::arg("xml"), py::arg("sensor") = py::none(), py::arg("fixed") = py::none(),
      "load_model for URDF text.");

  py::class_<NamedParameter>(m, "BaseParameter",
                             "A base parameter: a combination of standard parameters that static "
                             "wrenches determine (paper eqs. 27-28).")
      .def_readonly("name", &NamedParameter::name)
      .def_readonly("unit", &NamedParameter::unit)
      .def_readonly("expression", &NamedParameter::expression)
      .def_readonly("terms", &NamedParameter::terms, "(link, 'm'|'mx'|'my'|'mz', coefficient)")
      .def_readonly("value", &NamedParameter::value, "nan when not identified")
      .def_readonly("std", &NamedParameter::std, "standard deviation; nan when not identified")
      .def("__repr__", [](const NamedParameter& p) {
        return std::isnan(p.value)
                   ? fmt::format("BaseParameter({} = {} [{}])", p.name, p.expression, p.unit)
                   : fmt::format("BaseParameter({} = {:.6g} +- {:.2g} {}: {})", p.name, p.value,
                                 p.std, p.unit, p.expression);
      });

  py::class_<PyBase>(m, "BaseParameters", "The base parameters of a model (and the offsets).")
      .def_property_readonly("params",
                             [](const PyBase& b) {
                               std::vector<NamedParameter> out;
                               for (const auto& p : b.base.params)
                                 out.push_back(named_parameter(b.model, p));
                               return out;
                             })
      .def_property_readonly("names",
                             [](const PyBase& b) {
                               std::vector<std::string> n;
                               for (const auto& p : b.base.params) n.push_back(p.name);
                               return n;
                             })
      .def_property_readonly("unknown_names", [](const PyBase& b) { return unknown_names(b.base); })
      .def_property_readonly("offset", [](const PyBase& b) { return b.base.offset; })
      .def_property_readonly("num_unknowns", [](const PyBase& b) { return b.base.num_unknowns(); })
      .def_property_readonly(
          "dynamic", [](const PyBase& b) { return b.base.motion(); },
          "ten standard parameters per link (motion) rather than four (rest)")
      .def_property_readonly(
          "gravity",
          [](const PyBase& b) -> py::object {
            if (!b.base.motion()) return py::none();
            return py::str(b.base.fixed_gravity ? "level" : "varying");
          },
          "dynamic: 'level' (the same gravity in every sample) or 'varying'; None at rest")
      .def_property_readonly(
          "moving_sensor", [](const PyBase& b) { return b.base.sensor_moving; },
          "dynamic: the sensor frame itself moves")
      .def_property_readonly(
          "total_mass_identifiable", [](const PyBase& b) { return b.base.total_mass >= 0; },
          "False when the total mass joins offset fz (dynamic, level, offsets)")
      .def_property_readonly(
          "standard_parameter_names",
          [](const PyBase& b) {
            std::vector<std::string> n;
            for (int i = 0; i < b.base.layout.size(b.model); ++i)
              n.push_back(b.base.layout.name(b.model, i));
            return n;
          },
          "names of K's columns: 'm(link)', 'mx(link)', ... (and 'ixx(link)' ... dynamic)")
      .def_property_readonly(
          "K", [](const PyBase& b) { return b.base.K; },
          "[num_mass x 4 L] (dynamic: [num_mass x 10 L]): base values = K @ standard parameters")
      .def(
          "report", [](const PyBase& b) { return model_report(b.model, b.base); },
          "The text massid model prints.")
      .def(
          "to_json", [](const PyBase& b) { return params_json(b.model, b.base, nullptr); },
          "The JSON massid model --json prints (a params file without values).")
      .def("__repr__", [](const PyBase& b) {
        return fmt::format("BaseParameters('{}'{}, {} base parameters{})", b.model.name,
                           b.base.motion() ? ", dynamic" : "", b.base.num_mass(),
                           b.base.offset ? " + 6 offsets" : "");
      });

  m.def(
      "base_parameters",
      [](const py::object& robot, bool offset, bool dynamic,
         std::optional<std::string> gravity_model, bool moving_sensor,
         std::optional<std::vector<double>> root_gravity, std::optional<std::string> gravity) {
        if (gravity) {  // the old spelling of gravity_model
          py::module_::import("warnings")
              .attr("warn")("gravity='level'|'varying' is deprecated: use gravity_model=",
                            py::module_::import("builtins").attr("DeprecationWarning"), 2);
          if (!gravity_model) gravity_model = gravity;
        }
        const std::string model_of_gravity = gravity_model.value_or("varying");
        const Model model = model_of(robot, std::nullopt, std::nullopt);
        BaseParameterOptions o;
        o.offset = offset;
        if (model_of_gravity != "level" && model_of_gravity != "varying")
          throw InputError(
              fmt::format("gravity_model: '{}' is not 'level' or 'varying'", model_of_gravity));
        if (dynamic) {
          o.layout = ParameterLayout::full();
          o.fixed_gravity = model_of_gravity == "level";
          o.sensor_moving = moving_sensor;
          // The root frame's gravity as the sensor frame sees it.
          if (o.fixed_gravity)
            o.sensor_gravity = fixed_sensor_gravity(model, root_gravity_of(root_gravity));
        } else if (model_of_gravity != "varying" || moving_sensor || root_gravity) {
          throw InputError("gravity_model, moving_sensor and root_gravity go with dynamic=True");
        }
        py::gil_scoped_release release;
        return PyBase{model, find_base_parameters(model, o)};
      },
      py::arg("model"), py::arg("offset") = false, py::kw_only(), py::arg("dynamic") = false,
      py::arg("gravity_model") = py::none(), py::arg("moving_sensor") = false,
      py::arg("root_gravity") = py::none(), py::arg("gravity") = py::none(),
      "The base parameters of the model (a Model or a URDF path; massid model [--dynamic]); "
      "offset=True adds the six sensor offsets as unknowns. dynamic=True: in motion, ten "
      "parameters per link; gravity_model='level' (the same gravity, root_gravity in the root "
      "frame, in every sample: some constants join the offsets) or 'varying' (a tilting "
      "platform; the default); moving_sensor: the sensor frame itself moves. gravity= is the "
      "deprecated spelling of gravity_model=.");

  m.def(
      "standard_regressor",
      [](const Model& model, const py::object& q, const py::object& gravity, const py::object& qd,
         const py::object& qdd, const py::object& sensor_motion) {
        const auto [Q, G] = poses_of(model, q, gravity);
        const MotionArrays mo = motion_arrays(model, Q.rows(), qd, qdd, sensor_motion);
        KinematicsData kin(model);
        if (!mo.present)
          return stacked(Q.rows(), num_standard_parameters(model),
                         [&](Eigen::Index i, Eigen::MatrixXd& Y) {
                           forward_kinematics(model, kin, Q.row(i).transpose());
                           standard_regressor(model, kin, G.row(i).transpose(), Y);
                         });
        return stacked(
            Q.rows(), ParameterLayout::full().size(model), [&](Eigen::Index i, Eigen::MatrixXd& Y) {
              forward_kinematics(model, kin, Q.row(i).transpose(), mo.qd.row(i).transpose(),
                                 mo.qdd.row(i).transpose(), G.row(i).transpose(), mo.sensor(i));
              motion_regressor(model, kin, Y);
            });
      },
      py::arg("model"), py::arg("q"), py::arg("gravity"), py::kw_only(), py::arg("qd") = py::none(),
      py::arg("qdd") = py::none(), py::arg("sensor_motion") = py::none(),
      "[N, 6, 4 L] Y(q, g) with wrench = Y @ standard parameters (paper eqs. 15, 25, 29).\n"
      "q: [N, num_joints] rad or m; gravity: [N, 3] m/s^2 in the sensor frame.\n"
      "With qd and qdd ([N, num_joints]; sensor_motion [N, 9] optional): in motion, [N, 6, 10 L] "
      "over m, mx, my, mz, ixx ... izz per link (Model.nominal_parameters(dynamic=True)).");

  m.def(
      "regressor",
      [](const Model& model, const py::object& q, const py::object& gravity, bool offset,
         const py::object& qd, const py::object& qdd, const py::object& sensor_motion,
         const py::object& base_arg) {
        const auto [Q, G] = poses_of(model, q, gravity);
        const MotionArrays mo = motion_arrays(model, Q.rows(), qd, qdd, sensor_motion);
        BaseParameters base;
        if (!base_arg.is_none()) {
          const PyBase& b = base_arg.cast<const PyBase&>();
          if (b.model.name != model.name || b.model.sensor_link() != model.sensor_link() ||
              b.model.num_joints() != model.num_joints())
            throw InputError("base: the base parameters of another model");
          if (offset && !b.base.offset)
            throw InputError("offset=True with base=: use base_parameters(..., offset=True)");
          base = b.base;
        } else {
          BaseParameterOptions o;
          o.offset = offset;
          if (mo.present) {
            o.layout = ParameterLayout::full();
            o.sensor_moving = mo.sensor_motion.cols() > 0;
          }
          base = find_base_parameters(model, o);
        }
        if (base.motion() && !mo.present)
          throw InputError("dynamic base parameters: the regressor needs qd and qdd");
        if (!base.motion() && mo.present)
          throw InputError(
              "qd and qdd go with dynamic base parameters (base_parameters(..., "
              "dynamic=True))");
        RegressorData data(model, base);
        return stacked(Q.rows(), base.num_unknowns(), [&](Eigen::Index i, Eigen::MatrixXd& Y) {
          if (mo.present)
            base_regressor(model, base, data, Q.row(i).transpose(), mo.qd.row(i).transpose(),
                           mo.qdd.row(i).transpose(), G.row(i).transpose(), mo.sensor(i));
          else
            base_regressor(model, base, data, Q.row(i).transpose(), G.row(i).transpose());
          Y = data.base;
        });
      },
      py::arg("model"), py::arg("q"), py::arg("gravity"), py::arg("offset") = false, py::kw_only(),
      py::arg("qd") = py::none(), py::arg("qdd") = py::none(),
      py::arg("sensor_motion") = py::none(), py::arg("base") = py::none(),
      "[N, 6, num_unknowns] Y_b(q, g) with wrench = Y_b @ [base values, offsets] (eq. 29), in "
      "the order of base_parameters(model, offset).unknown_names.\n"
      "With qd and qdd: in motion, over the dynamic base parameters (base: a BaseParameters "
      "from base_parameters(..., dynamic=True); default: gravity varying, the sensor moving "
      "when sensor_motion is given).");
}

}  // namespace massid::python
