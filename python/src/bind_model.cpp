// Model, base parameters and regressors (massid/model.hpp, base_parameters.hpp,
// regressor.hpp, base_regressor.hpp).
#include <fmt/format.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>

#include "bindings.hpp"
#include "convert.hpp"
#include "massid/base_regressor.hpp"
#include "massid/errors.hpp"
#include "massid/regressor.hpp"

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
          "nominal_parameters", [](const Model& mo) { return nominal_standard_parameters(mo); },
          "[4 L] the URDF's inertials as standard parameters: m, mx, my, mz per link")
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

  struct PyBase {
    Model model;
    BaseParameters base;
  };
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
          "K", [](const PyBase& b) { return b.base.K; },
          "[num_mass x 4 L]: base values = K @ standard parameters");

  m.def(
      "base_parameters",
      [](const Model& model, bool offset) {
        BaseParameterOptions o;
        o.offset = offset;
        return PyBase{model, find_base_parameters(model, o)};
      },
      py::arg("model"), py::arg("offset") = false,
      "The base parameters of the model; offset=True adds the six sensor offsets as unknowns.");

  m.def(
      "standard_regressor",
      [](const Model& model, const py::object& q, const py::object& gravity) {
        const auto [Q, G] = poses_of(model, q, gravity);
        KinematicsData kin(model);
        return stacked(Q.rows(), num_standard_parameters(model),
                       [&](Eigen::Index i, Eigen::MatrixXd& Y) {
                         forward_kinematics(model, kin, Q.row(i).transpose());
                         standard_regressor(model, kin, G.row(i).transpose(), Y);
                       });
      },
      py::arg("model"), py::arg("q"), py::arg("gravity"),
      "[N, 6, 4 L] Y(q, g) with wrench = Y @ standard parameters (paper eqs. 15, 25, 29).\n"
      "q: [N, num_joints] rad or m; gravity: [N, 3] m/s^2 in the sensor frame.");

  m.def(
      "regressor",
      [](const Model& model, const py::object& q, const py::object& gravity, bool offset) {
        const auto [Q, G] = poses_of(model, q, gravity);
        BaseParameterOptions o;
        o.offset = offset;
        const BaseParameters base = find_base_parameters(model, o);
        RegressorData data(model, base);
        return stacked(Q.rows(), base.num_unknowns(), [&](Eigen::Index i, Eigen::MatrixXd& Y) {
          base_regressor(model, base, data, Q.row(i).transpose(), G.row(i).transpose());
          Y = data.base;
        });
      },
      py::arg("model"), py::arg("q"), py::arg("gravity"), py::arg("offset") = false,
      "[N, 6, num_unknowns] Y_b(q, g) with wrench = Y_b @ [base values, offsets] (eq. 29), in "
      "the order of base_parameters(model, offset).unknown_names.");
}

}  // namespace massid::python
