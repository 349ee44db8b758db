#include "massid/live/compensator.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <algorithm>
#include <chrono>
#include <limits>
#include <optional>
#include <vector>

#include "io/csv_fields.hpp"
#include "io/csv_stream.hpp"
#include "massid/core/base_parameters.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/gravity.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/motion_predictor.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {

namespace {

int find(const std::vector<std::string>& header, const std::string& name) {
  const auto it = std::find(header.begin(), header.end(), name);
  return it == header.end() ? -1 : static_cast<int>(it - header.begin());
}

}  // namespace

struct Compensator::Impl {
  IdentifiedModel identified;
  Model reading;  // identified's model as the header asks (with_pose_columns: the sensor's pose)
  std::optional<IdentifiedModelData> data;  // identified's workspace
  detail::SampleColumns columns;
  CompensatorOptions options;
  bool upstream_motion = false;         // the sensor frame's motion from the upstream joints' rates
  std::vector<double> values;           // [columns.num_values] the line's values, binding order
  std::string header, note;             // output header; notes on the columns
  std::string line_out;                 // the output line, reused (capacity kept)
  Wrench compensated = Wrench::Zero();  // the last good line's fx..mz_comp
  std::optional<Tracker> tracker;       // options.track
  long long tracker_ns = 0;             // its last update's time (time_tracker)
  // The last line's t (tracking, the clock delay: time in order).
  double last_t = -std::numeric_limits<double>::infinity();
  double last_quaternion[4] = {0, 0, 0, 0};  // the sensor's pose's, the last line's
  bool pose_signed = false;                  // last_quaternion holds a line's

  // The clock delay (IdentifiedModel::delay, > 0): line i is predicted for the
  // joint stream at t_i - delay, interpolated linearly between the two lines
  // around that instant as predict does (delay_wrench, delay.hpp), or the
  // stream's first line before it. The lines since the latest one at or before
  // t_i - delay are kept, oldest first, in a ring that grows to the delay's
  // span once and is then reused.
  double delay = 0.0;
  std::vector<double> ring;    // [capacity x num_values] the kept lines' values
  std::vector<double> ring_t;  // [capacity] their t
  std::size_t first = 0, count = 0;
  std::vector<double> delayed;  // [num_values] the joint stream at t_i - delay

  Eigen::Vector3d gravity(const double* v, FrameMotion& sensor) const;
  const double* delayed_values(const double* v);
};

const double* Compensator::Impl::delayed_values(const double* v) {
  const std::size_t n = values.size(), cap = ring_t.size();
  const double t = v[columns.time];
  const double target = t - delay;
  // Lines before the latest at or before the target are no longer needed.
  while (count >= 2 && ring_t[(first + 1) % cap] <= target) {
    first = (first + 1) % cap;
    --count;
  }
  if (count == cap) {  // grow (while the ring learns the delay's span), oldest first
    const std::size_t grown = std::max<std::size_t>(2 * cap, 8);
    std::rotate(ring.begin(), ring.begin() + first * n, ring.end());  // full: oldest at 0
    std::rotate(ring_t.begin(), ring_t.begin() + first, ring_t.end());
    ring.resize(grown * n), ring_t.resize(grown), first = 0;
  }
  const std::size_t at = (first + count) % ring_t.size();
  std::copy_n(v, n, ring.data() + at * n);
  ring_t[at] = t;
  ++count;
  // j: the latest line at or before the target (the first one before the
  // stream reached it), frac as delay_wrench computes it.
  const std::size_t size = ring_t.size();
  const std::size_t j = first, j1 = count >= 2 ? (first + 1) % size : first;
  const double span = ring_t[j1] - ring_t[j];
  const double frac = span > 0 ? std::clamp((target - ring_t[j]) / span, 0.0, 1.0) : 0.0;
  const double* a = ring.data() + j * n;
  const double* b = ring.data() + j1 * n;
  for (std::size_t k = 0; k < n; ++k) delayed[k] = (1 - frac) * a[k] + frac * b[k];
  return delayed.data();
}

Eigen::Vector3d Compensator::Impl::gravity(const double* v, FrameMotion& sensor) const {
  // Gravity from gx,gy,gz, else the upstream joints, else the platform's tilt
  // (tilt_x_deg in rad at tilt_value, then tilt_y_deg), as the reader bound it.
  const detail::SampleColumns& c = columns;
  if (c.gravity_from_tilt)
    return tilted_gravity(c.level_gravity, Tilt{v[c.tilt_value], v[c.tilt_value + 1]});
  // The joints above the sensor link (upstream_sensor_frame, kinematics.hpp).
  if (c.gravity_from_upstream || upstream_motion) {
    Eigen::Vector3d g;
    Eigen::Matrix<double, 9, 1> m;
    upstream_sensor_frame(reading, v + c.q_up, upstream_motion ? v + c.qd_up : nullptr,
                          upstream_motion ? v + c.qdd_up : nullptr, options.root_gravity, g.data(),
                          upstream_motion ? m.data() : nullptr);
    if (upstream_motion) sensor = {m.head<3>(), m.segment<3>(3), m.tail<3>()};
    if (c.gravity_from_upstream) return g;
  }
  return Eigen::Vector3d(v[c.gravity], v[c.gravity + 1], v[c.gravity + 2]);
}

Compensator::Compensator(const IdentifiedModel& identified, std::string_view text,
                         const std::string& source, const CompensatorOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.identified = identified;
  const std::string& params_name = identified.source();
  m.options = options;
  const bool dynamic = identified.dynamic();
  SampleOptions read;
  read.root_gravity = options.root_gravity;
  read.level_gravity = options.level_gravity;
  read.columns = options.columns;
  detail::SampleColumns head;
  detail::read_header(text, source, head);
  // The sensor's pose from columns, when the header has them.
  m.reading = with_pose_columns(identified.model(), head.header,
                                fmt::format("{}:{}", source, head.header_line), read);
  const Model& model = m.reading;
  m.columns = detail::bind_header(model, std::move(head), read, dynamic);
  detail::SampleColumns& c = m.columns;
  const std::vector<std::string>& header = c.header;
  const std::string where = fmt::format("{}:{}", source, c.header_line);
  for (const char* w : kWrenchColumns)
    if (find(header, std::string(w) + "_comp") >= 0)
      throw InputError(fmt::format(
          "{}: column '{}_comp' is already in the header: compensate appends fx_comp..mz_comp; "
          "drop or rename it",
          where, w));

  // Gravity: gx,gy,gz, else the upstream joints, else the platform's tilt
  // (Impl::gravity), never the measured force.
  if (c.gravity_from_force)
    throw InputError(fmt::format(
        "{}: no gravity: add columns gx,gy,gz (m/s^2, sensor frame), or tilt_x_deg,tilt_y_deg "
        "(the platform's tilt){}; compensate does not take gravity from the measured force",
        where,
        model.num_upstream_joints() > 0 ? ", or the columns of the joints above the sensor link"
                                        : ""));

  std::vector<std::string> notes;
  if (!c.note.empty()) notes.push_back(c.note);
  if (dynamic) {
    if (c.num_joints > 0 && c.qd < 0) {
      std::vector<std::string> need;
      for (const Joint& j : model.joints) {
        need.push_back(j.name + "_vel");
        need.push_back(j.name + "_acc");
      }
      throw InputError(fmt::format(
          "{}: {} is a dynamic fit (identified in motion): compensating its full wrench needs the "
          "joint velocities and accelerations, columns {} (compensate does not derive them from "
          "t: that filter needs later samples)",
          where, params_name, fmt::join(need, ",")));
    }
    m.upstream_motion = c.q_up >= 0 && c.qd_up >= 0 && c.sensor < 0;
    if (c.q_up >= 0 && c.qd_up < 0 && c.sensor < 0)
      notes.push_back(
          model.pose != SensorPoseColumns::None
              ? "the sensor's pose has no _vel,_acc columns (its rates, as qx_vel..qw_vel or "
                "r11_vel..r33_vel, x_vel,y_vel,z_vel and the _acc alike; compensate does not "
                "derive them from t: that filter needs later samples): the sensor frame is taken "
                "at rest"
              : "the joints above the sensor link have no _vel,_acc columns (and there are no "
                "wx..az): the sensor frame is taken at rest");
  } else {
    // Velocity columns of the joints below the sensor or above it (a wrist).
    bool moving = false;
    for (const auto* joints : {&model.joints, &model.upstream_joints})
      for (const Joint& j : *joints) moving |= find(header, j.name + "_vel") >= 0;
    if (moving)
      notes.push_back(fmt::format(
          "{} is a static fit: the weight is compensated, not the inertial forces of the "
          "motion (a dynamic fit compensates those)",
          params_name));
  }
  // Tracking and the clock delay need t (a static binding leaves it); a
  // wrench ahead of the joints would need lines not read yet.
  m.delay = identified.delay();
  const int t_column = find(header, "t");
  if ((options.track || m.delay != 0.0) && c.time < 0 && t_column >= 0 && c.target[t_column] < 0)
    c.time = detail::bind_value(c, t_column, 1.0);
  if (options.track) {
    if (c.time < 0)
      throw InputError(fmt::format(
          "{}: --track needs the time column t (the offsets drift with time); add t", where));
    for (const char* name : kTrackerColumns)
      if (find(header, name) >= 0)
        throw InputError(fmt::format(
            "{}: column '{}' is already in the header: compensate --track appends it; drop or "
            "rename it",
            where, name));
    m.tracker.emplace(identified, options.tracker);
    notes.push_back(fmt::format(
        "tracking a payload on link '{}' and the sensor's offsets; sensor noise taken as {:.4g} "
        "N, {:.4g} N m",
        m.tracker->payload_link_name(), options.tracker.noise.head<3>().maxCoeff(),
        options.tracker.noise.tail<3>().maxCoeff()));
  }
  if (m.delay != 0.0) {
    if (m.delay < 0.0)
      throw InputError(fmt::format(
          "{}: {} has a negative clock delay ({:.4g} ms: the wrench ahead of the joints): "
          "compensating it live needs lines not read yet; massid predict applies it to a file",
          where, params_name, 1e3 * m.delay));
    if (c.time < 0)
      throw InputError(fmt::format(
          "{}: {} has the wrench's clock delay ({:.4g} ms, identify --delay): compensate applies "
          "it from the time column t, which the stream lacks; add t",
          where, params_name, 1e3 * m.delay));
    notes.push_back(fmt::format(
        "the wrench's clock delay of {:.4g} ms ({}) applied: each line compensated with the joint "
        "state {:.4g} ms earlier (the stream's first line until then)",
        1e3 * m.delay, params_name, 1e3 * m.delay));
  }
  for (const std::string& n : notes) m.note += n + "\n";
  m.data.emplace(identified);

  m.values.assign(c.num_values, 0.0);
  m.delayed.assign(c.num_values, 0.0);
  // The header's own text (line ends and surrounding blank lines dropped).
  std::string_view h = text;
  while (!h.empty() && (h.back() == '\n' || h.back() == '\r')) h.remove_suffix(1);
  h = h.substr(h.rfind('\n') == std::string_view::npos ? 0 : h.rfind('\n') + 1);
  if (h.substr(0, 3) == "\xEF\xBB\xBF") h.remove_prefix(3);  // UTF-8 BOM
  m.header = fmt::format("{},{}_comp", h, fmt::join(kWrenchColumns, "_comp,"));
  if (m.tracker) m.header += fmt::format(",{}", fmt::join(kTrackerColumns, ","));
  m.header += '\n';
  m.line_out.reserve(4096);
}

Compensator::~Compensator() = default;
Compensator::Compensator(Compensator&&) noexcept = default;
Compensator& Compensator::operator=(Compensator&&) noexcept = default;

const std::string& Compensator::output_header() const { return impl_->header; }
const std::string& Compensator::note() const { return impl_->note; }
const Wrench& Compensator::compensated() const { return impl_->compensated; }
const Tracker* Compensator::tracker() const { return impl_->tracker ? &*impl_->tracker : nullptr; }
long long Compensator::tracker_update_ns() const { return impl_->tracker_ns; }
Eigen::Map<const Wrench> Compensator::measured() const {
  return Eigen::Map<const Wrench>(impl_->values.data() + impl_->columns.wrench);
}

std::string_view Compensator::compensate(std::string_view line, int line_no) {
  Impl& m = *impl_;
  const detail::SampleColumns& c = m.columns;
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  double* v = m.values.data();
  int kind = detail::csv_fast::parse_line(line.data(), line.data() + line.size(), c, v);
  if (kind == 0) {
    if (detail::trim(line).empty())
      throw InputError(fmt::format("{}:{}: empty line, a sample is expected", c.source, line_no));
    return {};  // a comment
  }
  if (kind < 0 && !detail::parse_row_slow(line, line_no, c, v)) return {};
  if (c.pose != SensorPoseColumns::None && c.q_up >= 0) {
    // The sensor's pose: checked, normalised, a quaternion's sign continuous
    // from line to line (with its given rates: the clock delay interpolates).
    detail::check_pose_line(c, line_no, v);
    if (m.pose_signed)
      continue_pose_sign(c.pose, m.last_quaternion, v + c.q_up,
                         c.qd_up >= 0 ? v + c.qd_up : nullptr,
                         c.qdd_up >= 0 ? v + c.qdd_up : nullptr);
    std::copy_n(v + c.q_up, 4, m.last_quaternion);
    m.pose_signed = true;
  }

  if (m.tracker || m.delay > 0.0) {  // t in order
    const double t = v[c.time];
    if (!(t > m.last_t))
      throw InputError(fmt::format(
          "{}:{}: t = {} does not increase (the previous line's is {}): {} needs time in order",
          c.source, line_no, t, m.last_t, m.delay > 0.0 ? "the clock delay" : "tracking"));
    m.last_t = t;
  }
  // The joint stream: this line's, or with a clock delay the one at t - delay.
  const double* js = m.delay > 0.0 ? m.delayed_values(v) : v;
  FrameMotion sensor;
  const Eigen::Vector3d g = m.gravity(js, sensor);
  if (c.sensor >= 0) {  // wx..az (bound for a dynamic fit only)
    const Eigen::Map<const Eigen::Matrix<double, 9, 1>> s(js + c.sensor);
    sensor = {s.head<3>(), s.segment<3>(3), s.tail<3>()};
  }
  const double* qd = c.qd >= 0 ? js + c.qd : js;  // static, or no joints: never read
  const double* qdd = c.qdd >= 0 ? js + c.qdd : js;
  const Eigen::Map<const Wrench> measured(v + c.wrench);
  if (m.tracker) {
    // measured - predicted(mechanism and payload) - offset, by the tracker.
    using Clock = std::chrono::steady_clock;
    const Clock::time_point t0 = m.options.time_tracker ? Clock::now() : Clock::time_point{};
    m.compensated = m.tracker->update(m.last_t, js, qd, qdd, g, sensor, measured).compensated;
    if (m.options.time_tracker)
      m.tracker_ns =
          std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now() - t0).count();
  } else {
    // The mechanism's wrench; measured - predicted - offset (identified_model.hpp).
    const Wrench predicted = m.identified.predict(*m.data, js, qd, qdd, g, sensor);
    m.compensated = m.identified.compensate(measured, predicted);
  }

  // The input text, then the six values as format_number writes them.
  std::string& out = m.line_out;
  out.assign(line);
  char number[40];
  const auto put = [&](double x) {
    number[0] = ',';
    const char* end = fmt::format_to(number + 1, "{}", x);
    out.append(number, static_cast<std::size_t>(end - number));
  };
  for (int k = 0; k < 6; ++k) put(m.compensated[k]);
  if (m.tracker) {
    const TrackerEstimate& e = m.tracker->estimate();
    put(e.mass);
    for (int k = 0; k < 3; ++k) put(e.com[k]);
    put(e.mass_std);
    put(e.com_std);
    const int upper[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
    for (const auto& ij : upper) {
      if (e.inertia_determined)
        put(e.inertia(ij[0], ij[1]));
      else
        out += ',';
    }
    for (int k = 0; k < 6; ++k) put(e.offset[k]);
    out += ',';
    out += tracker_event_name(e.event);
  }
  out += '\n';
  return out;
}

}  // namespace massid
