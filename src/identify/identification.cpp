#include "massid/identify/identification.hpp"

#include <fmt/format.h>

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <utility>

#include "identify/identify_file.hpp"
#include "io/atomic_file.hpp"
#include "massid/core/errors.hpp"
#include "massid/identify/delay.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"
#include "massid/io/urdf.hpp"
#include "massid/live/identified_model.hpp"

namespace massid {

std::vector<Warning> identification_notes(const IdentifySummary& summary,
                                          const std::string& source) {
  std::vector<Warning> out;
  if (summary.gravity_from_force)
    out.push_back({fmt::format("{} has no gx,gy,gz columns: gravity is taken along the measured "
                               "force (paper eq. 37), |g| = {} m/s^2",
                               source, kStandardGravity),
                   {}});
  for (Warning& w : identify_warnings(summary, source)) out.push_back(std::move(w));
  return out;
}

// ---------------------------------------------------------------------------
// The record file

namespace {

using record_json = nlohmann::json;
constexpr const char* kRecordFormat = "massid-identification-1";
static_assert(std::endian::native == std::endian::little, "records store little-endian doubles");

// A matrix as {rows, cols, data: the column-major doubles' bytes}.
record_json matrix(const Eigen::MatrixXd& m) {
  std::vector<std::uint8_t> bytes(static_cast<std::size_t>(m.size()) * sizeof(double));
  if (!bytes.empty()) std::memcpy(bytes.data(), m.data(), bytes.size());
  return {{"rows", m.rows()}, {"cols", m.cols()}, {"data", record_json::binary(std::move(bytes))}};
}

Eigen::MatrixXd matrix_of(const record_json& j) {
  const Eigen::Index rows = j.at("rows").get<Eigen::Index>(),
                     cols = j.at("cols").get<Eigen::Index>();
  const auto& bytes = j.at("data").get_binary();
  if (rows < 0 || cols < 0 ||
      bytes.size() != static_cast<std::size_t>(rows * cols) * sizeof(double))
    throw std::runtime_error("a matrix's size does not match its data");
  Eigen::MatrixXd m(rows, cols);
  if (!bytes.empty()) std::memcpy(m.data(), bytes.data(), bytes.size());
  return m;
}

// A fixed-size vector (6 or 3): the stored one must have that size.
template <int R>
Eigen::Matrix<double, R, 1> vector_of(const record_json& j) {
  const Eigen::MatrixXd m = matrix_of(j);
  if (m.rows() != R || m.cols() != 1) throw std::runtime_error("a vector has the wrong size");
  return m;
}

record_json rest_json(const RestWindows& w) {
  record_json windows = record_json::array();
  for (const RestWindow& r : w.windows) windows.push_back({r.first, r.last});
  return {{"continuous", w.continuous},
          {"windows", windows},
          {"rows", w.rows},
          {"samples", w.samples},
          {"moving", w.moving},
          {"criterion", w.criterion},
          {"trimmed", w.trimmed},
          {"longest_settling", w.longest_settling},
          {"quasi_static", w.quasi_static},
          {"inertia_checked", w.inertia_checked},
          {"max_speed", w.max_speed},
          {"inertial_force", w.inertial_force},
          {"inertial_moment", w.inertial_moment},
          {"noise_force", w.noise_force},
          {"noise_moment", w.noise_moment},
          {"windowed_samples", w.windowed_samples}};
}

// The settings by name, in the order of Hint::Setting (a record names them:
// the enumeration may grow).
constexpr const char* kSettingNames[] = {
    "hold_joints", "offset",       "checks",     "robust",      "drift",         "dynamic",
    "cutoff",      "delay",        "min_height", "limits",      "level_gravity", "tilt_max",
    "physical",    "sensor_link",  "poses",      "sigma_force", "sigma_moment",  "level_poses",
    "rest",        "root_gravity", "columns"};
static_assert(std::size(kSettingNames) == static_cast<std::size_t>(Hint::Setting::Columns) + 1,
              "a name for every setting");

record_json warnings_json(const std::vector<Warning>& warnings, HintSpeller spell) {
  record_json out = record_json::array();
  for (const Warning& w : warnings) {
    record_json hints = record_json::array();
    std::string message = w.message;
    if (spell && !w.hints.empty()) {  // as the caller prints it: cli::with_hints
      message += " (";
      for (std::size_t i = 0; i < w.hints.size(); ++i)
        message += (i ? "; " : "") + spell(w.hints[i]);
      message += ")";
    } else {
      for (const Hint& h : w.hints)
        hints.push_back(
            {{"setting", kSettingNames[static_cast<std::size_t>(h.setting)]}, {"value", h.value}});
    }
    out.push_back({{"message", message}, {"hints", hints}});
  }
  return out;
}

// Either form: {message, hints} or, in older records, the message alone.
std::vector<Warning> warnings_of(const record_json& j) {
  std::vector<Warning> out;
  for (const record_json& w : j) {
    if (w.is_string()) {
      out.push_back({w.get<std::string>(), {}});
      continue;
    }
    Warning warning{w.at("message").get<std::string>(), {}};
    for (const record_json& h : w.at("hints")) {
      const std::string name = h.at("setting").get<std::string>();
      const auto* at = std::find(std::begin(kSettingNames), std::end(kSettingNames), name);
      if (at == std::end(kSettingNames))
        throw std::runtime_error(fmt::format("a warning's hint names no setting ('{}')", name));
      warning.hints.push_back({static_cast<Hint::Setting>(at - std::begin(kSettingNames)),
                               h.at("value").get<std::string>()});
    }
    out.push_back(std::move(warning));
  }
  return out;
}

RestWindows rest_of(const record_json& j) {
  RestWindows w;
  w.continuous = j.at("continuous");
  for (const record_json& r : j.at("windows")) w.windows.push_back({r.at(0), r.at(1)});
  w.rows = j.at("rows");
  w.samples = j.at("samples");
  w.moving = j.at("moving");
  w.criterion = j.at("criterion");
  w.trimmed = j.value("trimmed", 0);  // absent in records written before the settling check
  w.longest_settling = j.value("longest_settling", 0.0);
  // Absent in records written before the quasi-static check.
  w.quasi_static = j.value("quasi_static", false);
  w.inertia_checked = j.value("inertia_checked", false);
  w.max_speed = j.value("max_speed", 0.0);
  w.inertial_force = j.value("inertial_force", 0.0);
  w.inertial_moment = j.value("inertial_moment", 0.0);
  w.noise_force = j.value("noise_force", 0.0);
  w.noise_moment = j.value("noise_moment", 0.0);
  w.windowed_samples = j.value("windowed_samples", 0);
  return w;
}

record_json delay_json(const DelayEstimate& d) {
  return {{"applied", d.applied},
          {"estimated", d.estimated},
          {"value", d.value},
          {"std", d.std},
          {"scan", d.scan}};
}

DelayEstimate delay_of(const record_json& j) {
  DelayEstimate d;
  d.applied = j.at("applied");
  d.estimated = j.at("estimated");
  d.value = j.at("value");
  d.std = j.at("std");
  d.scan = j.at("scan").get<std::vector<std::array<double, 2>>>();
  return d;
}

record_json summary_json(const IdentifySummary& s) {
  record_json outliers = record_json::array();
  for (const Outlier& o : s.outliers) outliers.push_back({o.sample, o.line, o.score});
  return {{"value", matrix(s.value)},
          {"stddev", matrix(s.stddev)},
          {"covariance", matrix(s.covariance)},
          {"condition_number", s.condition_number},
          {"residual_rms", matrix(s.residual_rms)},
          {"residual_max", matrix(s.residual_max)},
          {"sigma", matrix(s.sigma)},
          {"residual_dof", matrix(s.residual_dof)},
          {"sigma_estimated", s.sigma_estimated},
          {"sigma_force_given", s.sigma_force_given},
          {"sigma_moment_given", s.sigma_moment_given},
          {"chi2_per_dof", s.chi2_per_dof},
          {"samples", s.samples},
          {"gravity_from_force", s.gravity_from_force},
          {"gravity_from_upstream", s.gravity_from_upstream},
          {"outliers", outliers},
          {"outlier_threshold", s.outlier_threshold},
          {"per_sample_test", s.per_sample_test},
          {"robust", s.robust},
          {"drift", static_cast<int>(s.drift)},
          {"drift_names", s.drift_names},
          {"drift_value", matrix(s.drift_value)},
          {"drift_stddev", matrix(s.drift_stddev)},
          {"rest", rest_json(s.rest)},
          {"delay", delay_json(s.delay)}};
}

IdentifySummary summary_of(const record_json& j) {
  IdentifySummary s;
  s.value = matrix_of(j.at("value"));
  s.stddev = matrix_of(j.at("stddev"));
  s.covariance = matrix_of(j.at("covariance"));
  s.condition_number = j.at("condition_number");
  s.residual_rms = vector_of<6>(j.at("residual_rms"));
  s.residual_max = vector_of<6>(j.at("residual_max"));
  s.sigma = vector_of<6>(j.at("sigma"));
  s.residual_dof = vector_of<6>(j.at("residual_dof"));
  s.sigma_estimated = j.at("sigma_estimated");
  s.sigma_force_given = j.at("sigma_force_given");
  s.sigma_moment_given = j.at("sigma_moment_given");
  s.chi2_per_dof = j.at("chi2_per_dof");
  s.samples = j.at("samples");
  s.gravity_from_force = j.at("gravity_from_force");
  s.gravity_from_upstream = j.at("gravity_from_upstream");
  for (const record_json& o : j.at("outliers")) s.outliers.push_back({o.at(0), o.at(1), o.at(2)});
  s.outlier_threshold = j.at("outlier_threshold");
  s.per_sample_test = j.at("per_sample_test");
  s.robust = j.at("robust");
  s.drift = static_cast<Drift>(j.at("drift").get<int>());
  s.drift_names = j.at("drift_names").get<std::vector<std::string>>();
  s.drift_value = matrix_of(j.at("drift_value"));
  s.drift_stddev = matrix_of(j.at("drift_stddev"));
  s.rest = rest_of(j.at("rest"));
  s.delay = delay_of(j.at("delay"));
  return s;
}

// The physical fit: its ten parameters per link and figures; the per-link
// summaries are derived again on reading (physical_link).
record_json physical_json(const PhysicalSummary& p) {
  std::vector<bool> prior;
  for (const PhysicalLink& l : p.links) prior.push_back(l.prior_body);
  return {{"standard", matrix(p.standard)},
          {"mismatch", matrix(p.mismatch)},
          {"worst", p.worst},
          {"worst_mismatch", p.worst_mismatch},
          {"static_layout", p.static_layout},
          {"initial_cost", p.initial_cost},
          {"cost", p.cost},
          {"iterations", p.iterations},
          {"solve_seconds", p.solve_seconds},
          {"converged", p.converged},
          {"message", p.message},
          {"prior_body", prior}};
}

PhysicalSummary physical_of(const record_json& j, const Model& model) {
  PhysicalSummary p;
  p.standard = matrix_of(j.at("standard"));
  p.mismatch = matrix_of(j.at("mismatch"));
  p.worst = j.at("worst");
  p.worst_mismatch = j.at("worst_mismatch");
  p.static_layout = j.at("static_layout");
  p.initial_cost = j.at("initial_cost");
  p.cost = j.at("cost");
  p.iterations = j.at("iterations");
  p.solve_seconds = j.at("solve_seconds");
  p.converged = j.at("converged");
  p.message = j.at("message");
  const std::vector<bool> prior = j.at("prior_body").get<std::vector<bool>>();
  if (p.standard.size() != 10 * model.num_links() ||
      prior.size() != static_cast<std::size_t>(model.num_links()))
    throw std::runtime_error("its physical parameters do not fit the model");
  for (int l = 0; l < model.num_links(); ++l) {
    p.links.push_back(physical_link(model.links[l].name, p.standard.segment<10>(10 * l)));
    p.links.back().prior_body = prior[l];
    p.links.back().unseen = prior[l] && p.standard.segment<10>(10 * l).isZero(0.0);
  }
  return p;
}

record_json samples_json(const Samples& s) {
  return {{"source", s.source},
          {"q", matrix(s.q)},
          {"qd", matrix(s.qd)},
          {"qdd", matrix(s.qdd)},
          {"q_upstream", matrix(s.q_upstream)},
          {"qd_upstream", matrix(s.qd_upstream)},
          {"qdd_upstream", matrix(s.qdd_upstream)},
          {"gravity", matrix(s.gravity)},
          {"sensor_motion", matrix(s.sensor_motion)},
          {"wrench", matrix(s.wrench)},
          {"line", s.line},
          {"time", matrix(s.time)},
          {"block", s.block},
          {"gravity_from_force", s.gravity_from_force},
          {"gravity_from_upstream", s.gravity_from_upstream},
          {"derivatives_filtered", s.derivatives_filtered},
          {"noise_lags", s.noise_lags},
          {"root_gravity", matrix(s.root_gravity)}};
}

Samples samples_of(const record_json& j) {
  Samples s;
  s.source = j.at("source");
  s.q = matrix_of(j.at("q"));
  s.qd = matrix_of(j.at("qd"));
  s.qdd = matrix_of(j.at("qdd"));
  s.q_upstream = matrix_of(j.at("q_upstream"));
  s.qd_upstream = matrix_of(j.at("qd_upstream"));
  s.qdd_upstream = matrix_of(j.at("qdd_upstream"));
  s.gravity = matrix_of(j.at("gravity"));
  s.sensor_motion = matrix_of(j.at("sensor_motion"));
  s.wrench = matrix_of(j.at("wrench"));
  s.line = j.at("line").get<std::vector<int>>();
  s.time = matrix_of(j.at("time"));
  s.block = j.at("block").get<std::vector<int>>();
  s.gravity_from_force = j.at("gravity_from_force");
  s.gravity_from_upstream = j.at("gravity_from_upstream");
  s.derivatives_filtered = j.at("derivatives_filtered");
  s.noise_lags = j.value("noise_lags", 0);  // (records before it: independent rows)
  s.root_gravity = vector_of<3>(j.at("root_gravity"));
  return s;
}

}  // namespace

void write_identification(const std::string& path, const Identification& ident, HintSpeller spell) {
  const BaseParameters& b = ident.base;
  record_json held = record_json::array();
  for (const auto& [name, value] : ident.model.held) held.push_back({name, value});
  const MotionDataReport& m = ident.motion;
  const MotionDataOptions& mo = ident.motion_options;
  record_json j = {{"format", kRecordFormat},
                   {"urdf", std::filesystem::absolute(ident.model.source).string()},
                   {"sensor_link", ident.model.sensor_link()},
                   {"held", held},
                   {"base",
                    {{"per_link", b.layout.per_link()},
                     {"sensor_moving", b.sensor_moving},
                     {"fixed_gravity", b.fixed_gravity},
                     {"gravity", matrix(b.sensor_gravity)},
                     {"offset", b.offset},
                     {"rank_tolerance", b.rank_tolerance},
                     {"names",
                      [&] {
                        std::vector<std::string> names;
                        for (const BaseParameter& p : b.params) names.push_back(p.expression);
                        return names;
                      }()}}},
                   {"summary", summary_json(ident.summary)},
                   {"samples", samples_json(ident.samples)},
                   {"fitted", matrix(ident.fitted)},
                   {"warnings", warnings_json(ident.warnings, spell)},
                   {"motion",
                    {{"rows", m.rows},
                     {"derived", m.derived},
                     {"dt", m.kernels.dt},
                     {"cutoff", m.kernels.cutoff},
                     {"decimation", m.decimation},
                     {"option_cutoff", mo.filter.cutoff},
                     {"option_decimation", mo.filter.decimation},
                     {"g0", mo.samples.g0},
                     {"root_gravity", matrix(mo.samples.root_gravity)}}}};
  if (ident.physical) j["physical"] = physical_json(*ident.physical);
  const std::vector<std::uint8_t> bytes = record_json::to_cbor(j);
  write_file_atomically(path, std::string(bytes.begin(), bytes.end()));
}

Identification read_identification(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError(fmt::format("{}: cannot open file", path));
  const std::vector<std::uint8_t> bytes{std::istreambuf_iterator<char>(in), {}};
  Identification out;
  try {
    const record_json j = record_json::from_cbor(bytes);
    if (j.at("format") != kRecordFormat)
      throw std::runtime_error(fmt::format("format is not {}", kRecordFormat));
    std::vector<std::pair<std::string, double>> held;
    for (const record_json& h : j.at("held")) held.emplace_back(h.at(0), h.at(1));
    out.model = hold_joints(load_urdf(j.at("urdf"), j.at("sensor_link")), held);
    const record_json& b = j.at("base");
    BaseParameterOptions bo;
    bo.layout = ParameterLayout::of_size(b.at("per_link"));
    bo.sensor_moving = b.at("sensor_moving");
    bo.fixed_gravity = b.at("fixed_gravity");
    bo.sensor_gravity = vector_of<3>(b.at("gravity"));
    bo.offset = b.at("offset");
    bo.rank_tolerance = b.at("rank_tolerance");
    out.base = find_base_parameters(out.model, bo);
    std::vector<std::string> names;
    for (const BaseParameter& p : out.base.params) names.push_back(p.expression);
    if (names != b.at("names").get<std::vector<std::string>>())
      throw std::runtime_error(
          "the URDF's base parameters are no longer those of the fit (was the URDF changed?)");
    out.summary = summary_of(j.at("summary"));
    out.samples = samples_of(j.at("samples"));
    out.fitted = matrix_of(j.at("fitted"));
    out.warnings = warnings_of(j.at("warnings"));
    const record_json& m = j.at("motion");
    out.motion.rows = m.at("rows");
    out.motion.derived = m.at("derived");
    out.motion.decimation = m.at("decimation");
    out.motion_options.filter.cutoff = m.at("option_cutoff");
    out.motion_options.filter.decimation = m.at("option_decimation");
    out.motion_options.samples.g0 = m.at("g0");
    out.motion_options.samples.root_gravity = vector_of<3>(m.at("root_gravity"));
    if (out.motion.derived)
      out.motion.kernels = make_kernels(m.at("dt").get<double>(), m.at("cutoff").get<double>());
    if (j.contains("physical")) out.physical = physical_of(j.at("physical"), out.model);
    if (out.summary.value.size() != out.base.num_unknowns() ||
        out.fitted.rows() != out.samples.size())
      throw std::runtime_error("its parts do not fit together");
  } catch (const InputError&) {
    throw;
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{}: not a massid identification record: {}", path, e.what()));
  }
  return out;
}

// Declared in identified_model.hpp (live), defined here with the
// identification it reads, so that the live part needs nothing of identify.
IdentifiedModel IdentifiedModel::from_identification(const Identification& ident,
                                                     const IdentifiedModelOptions& options) {
  Eigen::VectorXd values = ident.summary.value;
  if (options.physical) {
    if (!ident.physical)
      throw InputError("predicting from physical parameters needs an identification with them");
    values.head(ident.base.num_mass()) =
        base_values_of_standard(ident.model, ident.base, ident.physical->standard);
  }
  return from_values(ident.model, ident.base, std::move(values),
                     options.physical ? Eigen::VectorXd() : ident.summary.stddev,
                     options.physical ? Eigen::MatrixXd() : ident.summary.covariance,
                     "the identification")
      .with_delay(ident.summary.delay.applied ? ident.summary.delay.value : 0.0)
      .with_residual_rms(ident.summary.residual_rms);
}

}  // namespace massid
