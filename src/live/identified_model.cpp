#include "massid/live/identified_model.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <cmath>
#include <optional>

#include "core/argument_checks.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/standard_parameters.hpp"
#include "massid/io/urdf.hpp"

namespace massid {

struct IdentifiedModel::Impl {
  Model model;
  BaseParameters base;
  Eigen::VectorXd values, stddev;
  Eigen::MatrixXd covariance;
  std::string source;
  Wrench offset = Wrench::Zero();
  double delay = 0.0;                    // s, with_delay
  Wrench residual_rms = Wrench::Zero();  // with_residual_rms
  Predictor predictor;                   // static
  MotionPredictor motion;                // dynamic
};

IdentifiedModel IdentifiedModel::from_values(Model model, BaseParameters base,
                                             Eigen::VectorXd values, Eigen::VectorXd stddev,
                                             Eigen::MatrixXd covariance, std::string source) {
  detail::check_size("IdentifiedModel::from_values", "values", values.size(), base.num_unknowns(),
                     "the base parameters, then the offsets");
  auto impl = std::make_shared<Impl>();
  if (base.motion())
    impl->motion = compile_motion_predictor(model, base, values);
  else
    impl->predictor = compile_predictor(model, base, values);
  if (base.offset) impl->offset = values.tail<6>();
  impl->model = std::move(model);
  impl->base = std::move(base);
  impl->values = std::move(values);
  impl->stddev = std::move(stddev);
  impl->covariance = std::move(covariance);
  impl->source = std::move(source);
  IdentifiedModel out;
  out.impl_ = std::move(impl);
  return out;
}

IdentifiedModel IdentifiedModel::from_params(Model model, const ParamsFile& params,
                                             const IdentifiedModelOptions& options) {
  if (model.sensor_link() != params.sensor_link)
    throw InputError(fmt::format("{}: the parameters are for sensor link '{}', the model's is '{}'",
                                 params.source, params.sensor_link, model.sensor_link()));
  BaseParameters base = find_base_parameters(model, base_parameter_options(params));
  Eigen::VectorXd values = options.physical ? physical_values_in_basis(params, model, base)
                                            : values_in_basis(params, model, base);
  // The file's std where its basis is this one (the same names in order).
  Eigen::VectorXd stddev;
  const std::vector<ParamsFile::Entry>& file = params.base_parameters;
  if (!options.physical &&
      std::equal(file.begin(), file.end(), base.params.begin(), base.params.end(),
                 [](const auto& e, const auto& p) { return e.name == p.name; })) {
    stddev.resize(base.num_unknowns());
    for (int i = 0; i < base.num_mass(); ++i) stddev[i] = file[static_cast<std::size_t>(i)].stddev;
    if (base.offset) stddev.tail<6>() = params.offset_std;
  }
  return from_values(std::move(model), std::move(base), std::move(values), std::move(stddev), {},
                     params.source)
      .with_delay(params.delay)
      .with_residual_rms(params.residual_rms);
}

IdentifiedModel IdentifiedModel::with_residual_rms(const Wrench& rms) const {
  auto impl = std::make_shared<Impl>(checked("IdentifiedModel::with_residual_rms"));
  impl->residual_rms = rms;
  IdentifiedModel out;
  out.impl_ = std::move(impl);
  return out;
}

IdentifiedModel IdentifiedModel::with_delay(double seconds) const {
  if (!std::isfinite(seconds))
    throw ArgumentError(
        fmt::format("massid::IdentifiedModel::with_delay: the delay is not finite ({})", seconds));
  auto impl = std::make_shared<Impl>(checked("IdentifiedModel::with_delay"));
  impl->delay = seconds;
  IdentifiedModel out;
  out.impl_ = std::move(impl);
  return out;
}

IdentifiedModel IdentifiedModel::load(const std::string& urdf_path, const ParamsFile& params,
                                      const IdentifiedModelOptions& options) {
  // The file's sensor link, or a link of its terms, not in this URDF (the
  // user named none: they are the file's): identified on another robot.
  std::optional<Model> model, whole;
  std::vector<std::string> missing;
  try {
    model = load_urdf(urdf_path, params.sensor_link);
  } catch (const InputError&) {
    try {
      whole = load_urdf(urdf_path);
    } catch (const InputError&) {
    }
    if (!whole || whole->find_link(params.sensor_link) >= 0) throw;
    missing.push_back(params.sensor_link);
  }
  const Model& links = model ? *model : *whole;
  for (const ParamsFile::Entry& e : params.base_parameters)
    for (const auto& t : e.terms)
      if (links.find_link(t.link) < 0 &&
          std::find(missing.begin(), missing.end(), t.link) == missing.end())
        missing.push_back(t.link);
  if (!missing.empty()) {
    const std::size_t shown = std::min<std::size_t>(missing.size(), 8);
    std::string names =
        fmt::format("'{}'", fmt::join(missing.begin(), missing.begin() + shown, "', '"));
    if (missing.size() > 8) names += fmt::format(" and {} more", missing.size() - 8);
    throw InputError(fmt::format(
        "{}: the params file belongs to another robot (its links {} are not in {}): give the URDF "
        "it was identified with",
        params.source, names, urdf_path));
  }
  return from_params(hold_joints(std::move(*model), params.held), params, options);
}

IdentifiedModel IdentifiedModel::load(const std::string& urdf_path, const std::string& params_path,
                                      const IdentifiedModelOptions& options) {
  return load(urdf_path, read_params(params_path), options);
}

const IdentifiedModel::Impl& IdentifiedModel::checked(const char* function) const {
  if (!impl_)
    throw ArgumentError(fmt::format(
        "{}: the IdentifiedModel is empty (made by load, from_params, from_identification or "
        "from_values)",
        function));
  return *impl_;
}

const Model& IdentifiedModel::model() const { return checked("IdentifiedModel::model").model; }
double IdentifiedModel::delay() const { return checked("IdentifiedModel::delay").delay; }
const Wrench& IdentifiedModel::residual_rms() const {
  return checked("IdentifiedModel::residual_rms").residual_rms;
}
const BaseParameters& IdentifiedModel::base() const {
  return checked("IdentifiedModel::base").base;
}
const Eigen::VectorXd& IdentifiedModel::values() const {
  return checked("IdentifiedModel::values").values;
}
const Eigen::VectorXd& IdentifiedModel::stddev() const {
  return checked("IdentifiedModel::stddev").stddev;
}
const Eigen::MatrixXd& IdentifiedModel::covariance() const {
  return checked("IdentifiedModel::covariance").covariance;
}
const std::string& IdentifiedModel::source() const {
  return checked("IdentifiedModel::source").source;
}
int IdentifiedModel::num_joints() const {
  return checked("IdentifiedModel::num_joints").model.num_joints();
}
bool IdentifiedModel::dynamic() const { return checked("IdentifiedModel::dynamic").base.motion(); }
bool IdentifiedModel::has_offset() const {
  return checked("IdentifiedModel::has_offset").base.offset;
}
bool IdentifiedModel::sensor_moving() const {
  return checked("IdentifiedModel::sensor_moving").base.sensor_moving;
}
std::optional<Eigen::Vector3d> IdentifiedModel::fixed_gravity() const {
  const BaseParameters& b = checked("IdentifiedModel::fixed_gravity").base;
  if (b.motion() && b.fixed_gravity) return b.sensor_gravity;
  return std::nullopt;
}
const Wrench& IdentifiedModel::offset() const { return checked("IdentifiedModel::offset").offset; }

const Predictor& IdentifiedModel::predictor() const {
  const Impl& m = checked("IdentifiedModel::predictor");
  if (m.base.motion())
    throw ArgumentError(
        "IdentifiedModel::predictor: dynamic parameters have the motion predictor "
        "(motion_predictor())");
  return m.predictor;
}

const MotionPredictor& IdentifiedModel::motion_predictor() const {
  const Impl& m = checked("IdentifiedModel::motion_predictor");
  if (!m.base.motion())
    throw ArgumentError(
        "IdentifiedModel::motion_predictor: static parameters have the gravity predictor "
        "(predictor())");
  return m.motion;
}

Eigen::MatrixXd IdentifiedModel::sensor_reading_rows(
    const Eigen::Ref<const Eigen::MatrixXd>& predicted) const {
  const Wrench& o = offset();
  detail::check_size("IdentifiedModel::sensor_reading_rows", "predicted columns", predicted.cols(),
                     6, "fx fy fz mx my mz");
  return predicted.rowwise() + o.transpose();
}

Eigen::MatrixXd IdentifiedModel::compensate_rows(
    const Eigen::Ref<const Eigen::MatrixXd>& measured,
    const Eigen::Ref<const Eigen::MatrixXd>& predicted) const {
  const Wrench& o = offset();
  detail::check_size("IdentifiedModel::compensate_rows", "measured columns", measured.cols(), 6,
                     "fx fy fz mx my mz");
  detail::check_size("IdentifiedModel::compensate_rows", "predicted rows", predicted.rows(),
                     measured.rows(), "one per measured row");
  detail::check_size("IdentifiedModel::compensate_rows", "predicted columns", predicted.cols(), 6,
                     "fx fy fz mx my mz");
  return (measured - predicted).rowwise() - o.transpose();
}

Wrench IdentifiedModel::predict_gravity(IdentifiedModelData& data, const double* q,
                                        const Eigen::Vector3d& g) const {
  checked("IdentifiedModel::predict_gravity");
  return predict(data, q, data.zeros.data(), data.zeros.data(), g);  // at rest
}

Wrench IdentifiedModel::predict_gravity(IdentifiedModelData& data,
                                        const Eigen::Ref<const Eigen::VectorXd>& q,
                                        const Eigen::Vector3d& g) const {
  detail::check_size("IdentifiedModel::predict_gravity", "q", q.size(), num_joints(),
                     "the model's joints");
  return predict_gravity(data, q.data(), g);
}

Wrench IdentifiedModel::predict(IdentifiedModelData& data, const double* q, const double* qd,
                                const double* qdd, const Eigen::Vector3d& g,
                                const FrameMotion& sensor) const {
  const Impl& m = checked("IdentifiedModel::predict");
  const int n = m.model.num_joints();
  if (n == 0) q = qd = qdd = data.zeros.data();  // no joints: may be null
  if (!m.base.motion())
    return massid::predict(m.predictor, *data.rest, Eigen::Map<const Eigen::VectorXd>(q, n), g);
  return predict_motion(m.motion, *data.motion, q, qd, qdd, g, sensor);
}

Eigen::MatrixXd IdentifiedModel::predict_samples(IdentifiedModelData& data,
                                                 const Samples& samples) const {
  const Impl& m = checked("IdentifiedModel::predict_samples");
  if (m.base.motion()) return massid::predict_samples(m.motion, *data.motion, samples);
  Eigen::MatrixXd P(samples.size(), 6);
  massid::predict(m.predictor, *data.rest, samples.q, samples.gravity, P);
  return P;
}

IdentifiedModelData::IdentifiedModelData(const IdentifiedModel& model) {
  if (model.dynamic())
    motion.emplace(model.motion_predictor());
  else
    rest.emplace(model.predictor());
  zeros.assign(static_cast<std::size_t>(std::max(1, model.num_joints())), 0.0);
}

}  // namespace massid
