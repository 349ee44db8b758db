#include "massid/params_file.hpp"

#include <fmt/format.h>

#include <Eigen/QR>
#include <cmath>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <sstream>

#include "json_text.hpp"
#include "massid/errors.hpp"
#include "massid/regressor.hpp"
#include "massid/report.hpp"

namespace massid {
namespace {

using json = nlohmann::ordered_json;
constexpr const char* kFormat = "massid-params-1";

json terms_json(const Model& model, const std::vector<Term>& terms) {
  json out = json::array();
  for (const Term& t : terms)
    out.push_back({{"link", model.links[t.link].name},
                   {"param", standard_parameter_kind(t.param)},
                   {"coef", t.coef}});
  return out;
}

json wrench_part(const Eigen::VectorXd& v, int start) {
  return json::array({v[start], v[start + 1], v[start + 2]});
}

// The "physical" section: the ten parameters of every link under "links",
// then what the fit says about them.
json physical_json(const Model& model, const BaseParameters& base, const PhysicalSummary& p) {
  json links = json::object();
  for (int l = 0; l < model.num_links(); ++l) {
    json e = json::object();
    for (int k = 0; k < 10; ++k) e[ParameterLayout::kind_name(k)] = p.standard[10 * l + k];
    links[model.links[l].name] = e;
  }
  json out;
  out["links"] = links;
  out["inertia_about"] = "link origin";
  out["inertia_from"] = p.static_layout ? "urdf (about the centre of mass)" : "data and urdf";
  out["consistent"] = p.consistent();
  json prior = json::array();
  for (const PhysicalLink& l : p.links)
    if (l.prior_body) prior.push_back(l.name);
  out["tiny_prior_bodies"] = prior;
  json mismatch = json::object();
  for (int i = 0; i < base.num_mass(); ++i) mismatch[base.params[i].name] = p.mismatch[i];
  out["mismatch_std"] = mismatch;
  if (p.worst >= 0)
    out["worst_mismatch"] = {{"name", base.params[p.worst].name}, {"std", p.worst_mismatch}};
  // No solve time: the file is the same for the same data (CLI and Python alike).
  out["solver"] = {{"cost", p.cost}, {"iterations", p.iterations}, {"converged", p.converged}};
  return out;
}

}  // namespace

std::string params_json(const Model& model, const BaseParameters& base, const IdentifySummary* s,
                        const PhysicalSummary* physical) {
  json j;
  j["format"] = kFormat;
  j["sensor_link"] = model.sensor_link();
  json joints = json::array();
  for (const Joint& jt : model.joints) joints.push_back(jt.name);
  j["joints"] = joints;
  if (!model.held.empty()) {
    json held = json::object();
    for (const auto& [name, value] : model.held) held[name] = value;
    j["held_joints"] = held;
  }
  if (s) {
    j["gravity_from"] = s->gravity_from_force      ? "force"
                        : s->gravity_from_upstream ? "upstream joints"
                                                   : "columns";
    j["samples"] = s->samples;
    if (s->delay.applied) j["delay"] = {{"value", s->delay.value}, {"std", s->delay.std}};
    if (s->rest.continuous)
      j["rest_windows"] = {{"windows", s->rest.windows.size()},
                           {"samples", s->rest.samples},
                           {"rows", s->rest.rows},
                           {"moving", s->rest.moving},
                           {"criterion", s->rest.criterion}};
    if (base.total_mass >= 0) j["total_mass"] = s->value[base.total_mass];
  }
  if (base.motion()) {
    j["model"] = "dynamic";
    json motion;
    motion["gravity"] = base.fixed_gravity ? "fixed" : "varying";
    if (base.fixed_gravity)
      motion["gravity_vector"] =
          json::array({base.sensor_gravity[0], base.sensor_gravity[1], base.sensor_gravity[2]});
    motion["sensor_moving"] = base.sensor_moving;
    j["motion"] = motion;
  }
  json list = json::array();
  const Eigen::VectorXd scale = parameter_scales(model, base, s);
  for (int i = 0; i < base.num_mass(); ++i) {
    const BaseParameter& p = base.params[i];
    json e;
    e["name"] = p.name;
    if (s) {
      e["value"] = s->value[i];
      e["std"] = s->stddev[i];
    }
    if (std::isfinite(scale[i])) e["scale"] = scale[i];  // report.hpp: what the std is judged by
    e["unit"] = p.unit;
    e["expression"] = p.expression;
    e["terms"] = terms_json(model, p.terms);
    list.push_back(e);
  }
  j["base_parameters"] = list;
  if (base.offset) {
    if (s) {
      const Eigen::VectorXd v = s->value.tail(6), d = s->stddev.tail(6);
      j["sensor_offset"] = {{"force", wrench_part(v, 0)},
                            {"moment", wrench_part(v, 3)},
                            {"force_std", wrench_part(d, 0)},
                            {"moment_std", wrench_part(d, 3)}};
    } else {
      j["sensor_offset"] = {{"force", "estimated"}, {"moment", "estimated"}};
    }
  }
  if (s) {
    j["condition_number"] = s->condition_number;
    json rms;
    for (int k = 0; k < 6; ++k) rms[kWrenchColumns[k]] = s->residual_rms[k];
    j["residual_rms"] = rms;
    json rmax, sigma;
    for (int k = 0; k < 6; ++k) {
      rmax[kWrenchColumns[k]] = s->residual_max[k];
      sigma[kWrenchColumns[k]] = s->sigma[k];
    }
    j["residual_max"] = rmax;
    j["noise_sigma"] = sigma;
    j["noise_sigma_from"] = s->sigma_estimated ? "residuals" : "user";
    j["chi2_per_dof"] = s->chi2_per_dof;
    // Outlier test: rejected samples (robust) or suspect ones, by file line.
    json lines = json::array();
    for (const Outlier& o : s->outliers) lines.push_back(o.line);
    // A streamed fit tested the largest residual of each axis (threshold in
    // sigmas of that axis) instead of each sample's d.
    j["outliers"] = {{"method", s->robust            ? "rejected"
                                : s->per_sample_test ? "reported"
                                                     : "largest residual"},
                     {"threshold", s->per_sample_test ? s->outlier_threshold
                                                      : largest_residual_bound(s->samples)},
                     {"count", s->outliers.size()},
                     {"fraction", s->samples ? double(s->outliers.size()) / s->samples : 0.0},
                     {"lines", lines}};
    if (s->drift != Drift::None) {
      json terms = json::array();
      for (Eigen::Index i = 0; i < s->drift_value.size(); ++i)
        terms.push_back({{"name", s->drift_names[i]},
                         {"value", s->drift_value[i]},
                         {"std", s->drift_stddev[i]}});
      j["drift"] = {{"model", s->drift == Drift::Linear ? "linear" : "per-block"},
                    {"offsets_at", s->drift == Drift::Linear ? "end of the log" : "last block"},
                    {"terms", terms}};
    }
    json names = json::array();
    for (int i = 0; i < base.num_unknowns(); ++i) names.push_back(base.unknown_name(i));
    json cov = json::array();
    for (int r = 0; r < s->covariance.rows(); ++r) {
      json row = json::array();
      for (int c = 0; c < s->covariance.cols(); ++c) row.push_back(s->covariance(r, c));
      cov.push_back(row);
    }
    j["covariance"] = {{"unknowns", names}, {"matrix", cov}};
  }
  if (physical) j["physical"] = physical_json(model, base, *physical);
  return j.dump(2) + "\n";
}

ParamsFile read_params(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open params file", path));
  std::ostringstream buf;
  buf << in.rdbuf();
  const std::string text = buf.str();
  json j = parse_json(text, path);
  ParamsFile p;
  p.source = path;
  auto fail = [&](const std::string& what) { throw InputError(fmt::format("{}: {}", path, what)); };
  try {
    if (!j.is_object()) fail("not a massid params file (expected a JSON object)");
    if (j.value("format", "") != kFormat)
      fail(fmt::format("not a massid params file: \"format\" must be \"{}\"", kFormat));
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
  // K = A Kf: solve A^T from Kf^T A^T = K^T, then check the fit.
  const Eigen::MatrixXd At = Kf.transpose().colPivHouseholderQr().solve(base.K.transpose());
  const double misfit = (Kf.transpose() * At - base.K.transpose()).norm();
  if (!(misfit <= 1e-6 * std::max(1.0, base.K.norm())))
    throw InputError(fmt::format(
        "{}: its base parameters do not span those of {} with sensor link '{}' (identified for "
        "another robot, sensor link or URDF version?)",
        params.source, model.source, model.sensor_link()));
  Eigen::VectorXd v(base.num_unknowns());
  v.head(base.num_mass()) = At.transpose() * vf;
  if (base.offset) v.tail(6) = params.offset;
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

Predictor compile_predictor(const Model& model, const ParamsFile& params) {
  const BaseParameters base = find_base_parameters(model, base_parameter_options(params));
  return compile_predictor(model, base, values_in_basis(params, model, base));
}

}  // namespace massid
