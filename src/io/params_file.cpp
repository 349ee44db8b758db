#include "massid/io/params_file.hpp"

#include <fmt/format.h>

#include <Eigen/QR>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>

#include "io/atomic_file.hpp"
#include "io/json_text.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/regressor.hpp"
#include "massid/core/standard_parameters.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {
namespace {

using json = nlohmann::ordered_json;

}  // namespace

ParamsFile read_params(const std::string& path) {
  json j = parse_json(read_file(path, "cannot open params file"), path);
  ParamsFile p;
  p.source = path;
  auto fail = [&](const std::string& what) { throw InputError(fmt::format("{}: {}", path, what)); };
  try {
    if (!j.is_object()) fail("not a massid params file (expected a JSON object)");
    if (j.value("format", "") != kParamsFormat)
      fail(fmt::format("not a massid params file: \"format\" must be \"{}\"", kParamsFormat));
    p.sensor_link = j.at("sensor_link").get<std::string>();
    p.joints = j.at("joints").get<std::vector<std::string>>();
    if (j.contains("held_joints"))
      for (const auto& [name, value] : j["held_joints"].items())
        p.held.emplace_back(name, value.get<double>());
    p.gravity_from = j.value("gravity_from", "columns");
    if (j.contains("samples")) {
      // Any JSON number converts to int, and a double beyond int's range is UB.
      const json& n = j["samples"];
      if (!n.is_number_integer() || n.get<long long>() < 0 ||
          n.get<long long>() > std::numeric_limits<int>::max())
        fail(fmt::format("\"samples\" must be a non-negative integer, not {}", n.dump()));
      p.samples = n.get<int>();
    }
    if (j.contains("model")) {
      const std::string model = j["model"].get<std::string>();
      if (model != "static" && model != "dynamic")
        fail(fmt::format("\"model\" must be \"static\" or \"dynamic\", not \"{}\"", model));
      p.dynamic = model == "dynamic";
    }
    if (p.dynamic && j.contains("motion")) {
      const json& m = j["motion"];
      p.fixed_gravity = m.value("gravity", "varying") == "fixed";
      if (p.fixed_gravity)
        for (int k = 0; k < 3; ++k) p.gravity[k] = m.at("gravity_vector").at(k).get<double>();
      p.sensor_moving = m.value("sensor_moving", false);
    }
    p.total_mass = p.dynamic && !j.contains("total_mass") ? std::numeric_limits<double>::quiet_NaN()
                                                          : j.at("total_mass").get<double>();
    for (const auto& e : j.at("base_parameters")) {
      ParamsFile::Entry entry;
      entry.name = e.at("name").get<std::string>();
      entry.value = e.at("value").get<double>();
      entry.stddev = e.value("std", 0.0);
      entry.unit = e.value("unit", "");
      entry.expression = e.value("expression", "");
      for (const auto& t : e.at("terms"))
        entry.terms.push_back({t.at("link").get<std::string>(), t.at("param").get<std::string>(),
                               t.at("coef").get<double>()});
      p.base_parameters.push_back(entry);
    }
    if (j.contains("sensor_offset")) {
      const auto& o = j["sensor_offset"];
      p.has_offset = true;
      for (int k = 0; k < 3; ++k) {
        p.offset[k] = o.at("force").at(k).get<double>();
        p.offset[3 + k] = o.at("moment").at(k).get<double>();
        if (o.contains("force_std")) p.offset_std[k] = o["force_std"].at(k).get<double>();
        if (o.contains("moment_std")) p.offset_std[3 + k] = o["moment_std"].at(k).get<double>();
      }
    }
    p.condition_number = j.value("condition_number", 0.0);
    if (j.contains("residual_rms")) {  // the tracker's default noise (tracker_noise)
      const json& r = j["residual_rms"];
      for (int k = 0; k < 6; ++k) {
        p.residual_rms[k] = r.at(kWrenchColumns[k]).get<double>();
        if (!(p.residual_rms[k] >= 0.0 && std::isfinite(p.residual_rms[k])))
          fail(fmt::format("\"residual_rms\": \"{}\" is not a finite number >= 0",
                           kWrenchColumns[k]));
      }
    }
    if (j.contains("delay")) {
      p.delay = j["delay"].at("value").get<double>();
      p.delay_std = j["delay"].value("std", 0.0);
      if (!std::isfinite(p.delay)) fail("\"delay\": \"value\" is not finite");
    }
    if (j.contains("physical")) {
      const json& links = j["physical"].at("links");
      if (!links.is_object()) fail("\"physical\": \"links\" must be an object keyed by link name");
      for (const auto& [name, e] : links.items()) {
        ParamsFile::PhysicalEntry entry;
        entry.link = name;
        for (int k = 0; k < 10; ++k) {
          const char* kind = ParameterLayout::kind_name(k);
          if (!e.contains(kind) || !e[kind].is_number())
            fail(fmt::format("\"physical\": link '{}' needs a number \"{}\"", name, kind));
          entry.params[k] = e[kind].get<double>();
          if (!std::isfinite(entry.params[k]))
            fail(fmt::format("\"physical\": link '{}': \"{}\" is not finite", name, kind));
        }
        p.physical.push_back(entry);
      }
    }
  } catch (const json::exception& e) {
    fail(fmt::format("missing or wrong field: {}", e.what()));
  }
  return p;
}

Eigen::VectorXd values_in_basis(const ParamsFile& params, const Model& model,
                                const BaseParameters& base) {
  const ParameterLayout& layout = base.layout;
  const int n = layout.size(model);
  const int nf = static_cast<int>(params.base_parameters.size());
  Eigen::MatrixXd Kf = Eigen::MatrixXd::Zero(nf, n);
  Eigen::VectorXd vf(nf);
  for (int i = 0; i < nf; ++i) {
    const auto& e = params.base_parameters[i];
    vf[i] = e.value;
    for (const auto& t : e.terms) {
      const int l = model.find_link(t.link);
      if (l < 0)
        throw InputError(
            fmt::format("{}: base parameter '{}' refers to link '{}', which is not "
                        "a measured link of {} below '{}'",
                        params.source, e.name, t.link, model.source, model.sensor_link()));
      const int k = ParameterLayout::kind_from_name(t.param);
      if (k < 0 || k >= layout.per_link())
        throw InputError(fmt::format(
            "{}: base parameter '{}': unknown parameter '{}' ({})", params.source, e.name, t.param,
            layout.inertia() ? "m, mx, my, mz, ixx, ixy, ixz, iyy, iyz, izz" : "m, mx, my, mz"));
      Kf(i, layout.index(l, k)) += t.coef;
    }
  }
  // The file's own basis (a file of this model, written by params_json: its
  // terms are K's rows to the bit): its values as they are, so that a params
  // file predicts the same bits as the identification it was written from.
  Eigen::VectorXd v(base.num_unknowns());
  if (base.offset) v.tail(6) = params.offset;
  if (Kf.rows() == base.K.rows() && Kf.cols() == base.K.cols() && Kf == base.K) {
    v.head(base.num_mass()) = vf;
    return v;
  }
  // A file without base parameters (a hand-edited or truncated file) spans
  // nothing: named, before a factorisation of an empty matrix.
  if (Kf.rows() == 0)
    throw InputError(fmt::format(
        "{}: has no base parameters (\"base_parameters\" is empty), and {} with sensor link '{}' "
        "has {}: identify again, or check that the file is whole",
        params.source, model.source, model.sensor_link(), base.num_mass()));
  // Another basis of the same space: K = A Kf: solve A^T from Kf^T A^T = K^T,
  // then check the fit.
  const Eigen::MatrixXd At = Kf.transpose().colPivHouseholderQr().solve(base.K.transpose());
  const double misfit = (Kf.transpose() * At - base.K.transpose()).norm();
  if (!(misfit <= 1e-6 * std::max(1.0, base.K.norm())))
    throw InputError(fmt::format(
        "{}: its base parameters do not span those of {} with sensor link '{}' (identified for "
        "another robot, sensor link or URDF version?)",
        params.source, model.source, model.sensor_link()));
  v.head(base.num_mass()) = At.transpose() * vf;
  return v;
}

Eigen::VectorXd physical_values_in_basis(const ParamsFile& params, const Model& model,
                                         const BaseParameters& base) {
  if (params.physical.empty())
    throw InputError(
        fmt::format(
            "{}: has no \"physical\" section: identify with physically consistent parameters to "
            "predict from them",
            params.source),
        {{Hint::Setting::Physical, "on"}});
  Eigen::VectorXd pi =
      Eigen::VectorXd::Constant(10 * model.num_links(), std::numeric_limits<double>::quiet_NaN());
  for (const ParamsFile::PhysicalEntry& e : params.physical) {
    const int l = model.find_link(e.link);
    if (l < 0)
      throw InputError(fmt::format(
          "{}: \"physical\" names link '{}', which is not a measured link of {} below '{}'",
          params.source, e.link, model.source, model.sensor_link()));
    pi.segment<10>(10 * l) = e.params;
  }
  for (int l = 0; l < model.num_links(); ++l)
    if (std::isnan(pi[10 * l]))
      throw InputError(fmt::format("{}: \"physical\" has no parameters for link '{}'",
                                   params.source, model.links[l].name));
  Eigen::VectorXd v(base.num_unknowns());
  v.head(base.num_mass()) = base_values_of_standard(model, base, pi);
  if (base.offset) v.tail(6) = params.offset;
  return v;
}

BaseParameterOptions base_parameter_options(const ParamsFile& params) {
  BaseParameterOptions options;
  options.offset = params.has_offset;
  if (params.dynamic) {
    options.layout = ParameterLayout::full();
    options.fixed_gravity = params.fixed_gravity;
    options.sensor_gravity = params.gravity;
    options.sensor_moving = params.sensor_moving;
  }
  return options;
}

}  // namespace massid
