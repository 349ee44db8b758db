#include "massid/identify/motion_data.hpp"

#include <fmt/format.h>

#include "identify/motion_pipeline.hpp"
#include "massid/core/base_regressor.hpp"
#include "massid/core/errors.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {

Samples prepare_motion_samples(const Model& model, Samples raw, const MotionDataOptions& options,
                               MotionDataReport* report) {
  MotionDataReport r;
  r.rows = raw.size();
  const bool joints_missing = model.num_joints() > 0 && raw.qd.cols() != model.num_joints();
  const bool upstream_missing =
      raw.q_upstream.cols() > 0 && raw.qd_upstream.cols() == 0 && !raw.has_sensor_motion();
  Samples s;
  if (!joints_missing && !upstream_missing) {
    s = std::move(raw);
  } else {
    detail::require_time_column(raw.source, raw.time.size() == raw.size());
    r.derived = true;
    s = filter_motion(raw, options.filter, &r.kernels);
    r.decimation = options.filter.decimation > 0
                       ? options.filter.decimation
                       : default_decimation(1.0 / r.kernels.dt, r.kernels.cutoff);
    resolve_upstream(model, s);
  }
  if (report) *report = r;
  return s;
}

Samples read_motion_samples(const Model& model, const std::string& path, WrenchColumns wrench,
                            const MotionDataOptions& options, MotionDataReport* report) {
  return prepare_motion_samples(model, read_samples(model, read_csv(path), wrench, options.samples),
                                options, report);
}

BaseParameterOptions motion_base_options(const Samples& s, bool offset) {
  BaseParameterOptions o;
  o.layout = ParameterLayout::full();
  o.offset = offset;
  if (s.size() > 0) {
    const Eigen::Vector3d g0 = s.gravity.row(0).transpose();
    double spread = 0.0;
    for (int i = 0; i < s.size(); ++i)
      spread = std::max(spread, (s.gravity.row(i).transpose() - g0).norm());
    o.fixed_gravity = spread <= detail::fixed_gravity_tolerance(g0);
    o.sensor_gravity = g0;
    o.sensor_moving = s.has_sensor_motion() && s.sensor_motion.cwiseAbs().maxCoeff() > 0.0;
  }
  return o;
}

}  // namespace massid
