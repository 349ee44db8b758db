// massid.Tracker: the library's Tracker (massid/live/tracker.hpp) of a
// payload and the sensor's drifting offsets, as `massid compensate --track`
// uses it; the same samples give the CLI's columns to the bit. Only the
// arguments are translated here (shapes checked, gravity and the sensor's
// motion from the joints above the sensor as compensate takes them).
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/stl.h>

#include <cmath>
#include <limits>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "bindings.hpp"
#include "convert.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/samples.hpp"
#include "massid/live/identified_model.hpp"
#include "massid/live/tracker.hpp"

namespace massid::python {

namespace {

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// The inertia's six values in the CLI's order, ixx ixy ixz iyy iyz izz.
constexpr int kTrackInertia[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};

// The samples of an update or track call, checked, one row per sample.
struct TrackInputs {
  Eigen::VectorXd t;
  RowMatrix q, qd, qdd, sensor_motion, wrench, gravity;  // qd..: 0 x 0 when not given
  RowMatrix qu, qdu, qddu;                               // the joints above the sensor
  Eigen::Vector3d root_gravity;
  bool upstream_gravity = false;  // gravity from qu (no gravity given)
  bool upstream_motion = false;   // the sensor's motion from qu, qdu, qddu

  Eigen::Index rows() const { return t.size(); }
};

std::string track_joint_list(const char* what, const std::vector<Joint>& joints) {
  std::vector<std::string> names;
  for (const Joint& j : joints) names.push_back(j.name);
  return fmt::format("{} (joints {})", what, fmt::join(names, ", "));
}

// [rows x cols] of a per-sample argument, checked against the samples' count.
RowMatrix track_rows(const py::handle& array, Eigen::Index rows, int cols,
                     const std::string& what) {
  RowMatrix m = to_matrix(array, cols, what);
  if (m.rows() != rows)
    throw InputError(
        fmt::format("{} has {} rows and t {}: one of each per sample", what, m.rows(), rows));
  return m;
}

TrackInputs track_inputs(const IdentifiedModel& identified, const py::object& t,
                         const py::object& q, const py::object& wrench, const py::object& qd,
                         const py::object& qdd, const py::object& gravity,
                         const py::object& sensor_motion, const py::object& q_upstream,
                         const py::object& qd_upstream, const py::object& qdd_upstream,
                         const std::optional<std::vector<double>>& root_gravity) {
  const Model& model = identified.model();
  TrackInputs in;
  const py::object ndim = py::module_::import("numpy").attr("ndim");
  in.t = to_vector(ndim(t).cast<int>() == 0 ? py::object(py::make_tuple(t)) : t, "t");
  const Eigen::Index n = in.rows();
  const int nj = model.num_joints(), nu = model.num_upstream_joints();
  if (q.is_none() && nj > 0)
    throw InputError(fmt::format("q is needed: {}", track_joint_list("q", model.joints)));
  in.q = q.is_none() ? RowMatrix(n, 0) : track_rows(q, n, nj, track_joint_list("q", model.joints));
  in.wrench = track_rows(wrench, n, 6, "wrench (fx, fy, fz, mx, my, mz)");
  if (!identified.dynamic() && (!qd.is_none() || !qdd.is_none() || !sensor_motion.is_none() ||
                                !qd_upstream.is_none() || !qdd_upstream.is_none()))
    throw InputError(
        "static (first-moment) parameters track from q and gravity alone: qd, qdd, "
        "sensor_motion, qd_upstream and qdd_upstream go with dynamic parameters");
  const MotionArrays motion = motion_arrays(model, n, qd, qdd, sensor_motion);
  if (motion.present) {
    in.qd = motion.qd;
    in.qdd = motion.qdd;
    in.sensor_motion = motion.sensor_motion;
  }
  if (q_upstream.is_none() && (!qd_upstream.is_none() || !qdd_upstream.is_none()))
    throw InputError("qd_upstream and qdd_upstream go with q_upstream");
  if (qd_upstream.is_none() != qdd_upstream.is_none())
    throw InputError("qd_upstream and qdd_upstream: give both, or neither");
  if (!q_upstream.is_none()) {
    in.qu = track_rows(q_upstream, n, nu, track_joint_list("q_upstream", model.upstream_joints));
    if (!qd_upstream.is_none()) {
      in.qdu =
          track_rows(qd_upstream, n, nu, track_joint_list("qd_upstream", model.upstream_joints));
      in.qddu =
          track_rows(qdd_upstream, n, nu, track_joint_list("qdd_upstream", model.upstream_joints));
    }
  }
  in.root_gravity = root_gravity_of(root_gravity);
  // Gravity: given, else from the joints above the sensor, else the one
  // gravity of parameters identified at one (as Predictor); the sensor's
  // motion: given, else from the upstream joints' rates for dynamic
  // parameters (as compensate takes its columns).
  if (!gravity.is_none()) {
    in.gravity = track_rows(gravity, n, 3, "gravity (gx, gy, gz)");
  } else if (!q_upstream.is_none()) {
    in.upstream_gravity = true;
  } else if (const auto fixed = identified.fixed_gravity()) {
    in.gravity = fixed->transpose().replicate(n, 1);
  } else {
    throw InputError(fmt::format(
        "gravity (gx, gy, gz, sensor frame) is needed{}",
        nu > 0 ? ", or q_upstream: the joints above the sensor link turn root_gravity" : ""));
  }
  in.upstream_motion =
      identified.dynamic() && !qd_upstream.is_none() && in.sensor_motion.cols() == 0;
  if (!in.upstream_gravity && !in.upstream_motion && !q_upstream.is_none())
    throw InputError(
        "q_upstream goes without gravity (it turns root_gravity into the sensor frame), or with "
        "qd_upstream and qdd_upstream for the sensor's motion (dynamic parameters)");
  return in;
}

// massid.Tracker.
struct PyTracker {
  Tracker tracker;

  PyTracker(const IdentifiedModel& identified, const std::optional<std::string>& link,
            std::optional<double> sigma_force, std::optional<double> sigma_moment, bool exact_d2)
      : tracker(identified,
                options(identified.residual_rms(), link, sigma_force, sigma_moment, exact_d2)) {}

  static TrackerOptions options(const Wrench& residual_rms, const std::optional<std::string>& link,
                                std::optional<double> sigma_force,
                                std::optional<double> sigma_moment, bool exact_d2) {
    for (const auto& [name, sigma] :
         {std::pair{"sigma_force", sigma_force}, std::pair{"sigma_moment", sigma_moment}})
      if (sigma && !(*sigma > 0.0 && std::isfinite(*sigma)))
        throw InputError(fmt::format("{} = {}: the sensor noise is a std > 0", name, *sigma));
    TrackerOptions o;
    o.payload_link = link.value_or("");
    o.noise = tracker_noise(residual_rms, sigma_force.value_or(0.0), sigma_moment.value_or(0.0));
    o.exact_d2 = exact_d2;
    return o;
  }

  // Sample i of `in` through the tracker.
  const TrackerEstimate& step(const TrackInputs& in, Eigen::Index i) {
    FrameMotion sensor;
    if (in.sensor_motion.cols() == 9) {
      sensor.omega = in.sensor_motion.block<1, 3>(i, 0).transpose();
      sensor.omega_dot = in.sensor_motion.block<1, 3>(i, 3).transpose();
      sensor.accel = in.sensor_motion.block<1, 3>(i, 6).transpose();
    }
    Eigen::Vector3d g;
    if (in.upstream_gravity || in.upstream_motion) {
      const Model& model = tracker.identified().model();
      Eigen::Matrix<double, 9, 1> m;
      upstream_sensor_frame(model, in.qu.row(i).data(),
                            in.upstream_motion ? in.qdu.row(i).data() : nullptr,
                            in.upstream_motion ? in.qddu.row(i).data() : nullptr, in.root_gravity,
                            g.data(), in.upstream_motion ? m.data() : nullptr);
      if (in.upstream_motion) sensor = {m.head<3>(), m.segment<3>(3), m.tail<3>()};
    }
    if (!in.upstream_gravity) g = in.gravity.row(i).transpose();
    const bool motion = in.qd.rows() > 0;
    const Wrench w = in.wrench.row(i).transpose();
    try {
      return tracker.update(in.t[i], in.q.row(i).data(), motion ? in.qd.row(i).data() : nullptr,
                            motion ? in.qdd.row(i).data() : nullptr, g, sensor, w);
    } catch (const ArgumentError& e) {  // t not increasing
      throw InputError(in.rows() > 1 ? fmt::format("t[{}]: {}", i, e.what()) : e.what());
    }
  }
};

// The columns of track(): compensate --track's, in its order.
py::dict track_columns(const Eigen::MatrixXd& values, const std::vector<TrackerEvent>& events) {
  py::dict out;
  int c = 0;
  for (const char* w : kWrenchColumns)
    out[py::str(std::string(w) + "_comp")] = Eigen::VectorXd(values.col(c++));
  for (const char* name : kTrackerColumns) {
    if (std::string(name) == "event") break;
    out[name] = Eigen::VectorXd(values.col(c++));
  }
  std::vector<std::string> names;
  for (TrackerEvent e : events) names.emplace_back(tracker_event_name(e));
  out["event"] = py::module_::import("numpy").attr("array")(names, py::arg("dtype") = "U7");
  return out;
}

}  // namespace

void bind_track(py::module_& m) {
  using E = TrackerEstimate;
  py::class_<E>(m, "TrackerEstimate",
                "The tracker's estimate after a sample (compensate --track's columns): "
                "physically consistent (mass >= 0, the inertia positive semi-definite and within "
                "the triangle inequalities).")
      .def_readonly("payload_m", &E::mass, "mass, kg")
      .def_readonly("payload_c", &E::com,
                    "[3] centre of mass in the payload link's frame, m (0 while the mass is "
                    "not seen)")
      .def_readonly("payload_m_std", &E::mass_std, "kg")
      .def_readonly("payload_c_std", &E::com_std,
                    "the largest std of the three centre-of-mass coordinates, m")
      .def_readonly("payload_c_stds", &E::com_stds, "[3] std of each coordinate, m")
      .def_property_readonly(
          "payload_inertia",
          [](const E& e) -> std::optional<Eigen::Matrix3d> {
            if (!e.inertia_determined) return std::nullopt;
            return e.inertia;
          },
          "[3, 3] inertia about the centre of mass, the link's axes, kg m^2; None while the "
          "motion does not determine it (the CLI's empty payload_ixx..izz)")
      .def_readonly("offset", &E::offset, "[6] the sensor offsets fx..mz, N and N m")
      .def_readonly("offset_std", &E::offset_std, "[6] their std")
      .def_property_readonly(
          "event", [](const E& e) { return std::string(tracker_event_name(e.event)); },
          "'' , 'change' (a payload change detected on this sample) or 'contact' (it carries "
          "an external wrench)")
      .def_readonly("comp", &E::compensated,
                    "[6] fx_comp..mz_comp: measured - predicted(mechanism and payload) - offset")
      .def_readonly("d2", &E::d2,
                    "the sample's innovation chi^2 e^T S^-1 e (6 degrees of freedom), flagged "
                    "beyond the gate (25); a sample within the gate by the noise alone reports "
                    "that bound e^T R^-1 e (>= d2) unless the Tracker has exact_d2=True")
      .def("__repr__", [](const E& e) {
        return fmt::format(
            "TrackerEstimate(payload_m={:.6g}, payload_c=[{:.4g}, {:.4g}, {:.4g}], "
            "event='{}')",
            e.mass, e.com[0], e.com[1], e.com[2], tracker_event_name(e.event));
      });

  const char* sample_doc =
      "t: s, increasing; q [num_joints] (or None without joints below the sensor); wrench [6] "
      "measured fx..mz; qd, qdd as Predictor.predict takes them (dynamic parameters; None: at "
      "rest); gravity [3] in the sensor frame, or None: from q_upstream (the joints above the "
      "sensor link, root_gravity in the root frame, default 0, 0, -9.80665) or the one gravity "
      "of parameters identified at one; sensor_motion [9] as Predictor's, or from q_upstream "
      "with qd_upstream and qdd_upstream. The parameters' clock delay is the caller's: pass the "
      "joint state of t - delay.";
  py::class_<PyTracker>(
      m, "Tracker",
      "The payload on a link and the sensor's drifting offsets, tracked online one sample at a "
      "time, with payload changes and contacts detected: massid compensate --track's tracker "
      "(docs/tracking.md), the same numbers to the bit.")
      .def(py::init([](const py::object& predictor, const py::object& params,
                       const std::optional<std::string>& payload_link,
                       std::optional<double> sigma_force, std::optional<double> sigma_moment,
                       bool exact_d2) {
             return std::make_unique<PyTracker>(identified_of(predictor, params), payload_link,
                                                sigma_force, sigma_moment, exact_d2);
           }),
           py::arg("predictor"), py::arg("params") = py::none(), py::kw_only(),
           py::arg("payload_link") = py::none(), py::arg("sigma_force") = py::none(),
           py::arg("sigma_moment") = py::none(), py::arg("exact_d2") = false,
           "predictor: a massid.Predictor, or a URDF path or Model with params (as Predictor "
           "takes them). payload_link: the payload's link (default: the measured link farthest "
           "from the sensor); sigma_force, sigma_moment: the sensor noise per axis, N and N m "
           "(default: the params file's residual RMS per axis, as compensate --track); "
           "exact_d2: every estimate's d2 exact (otherwise a sample within the gate by the noise "
           "alone reports that bound; the same flags and estimates either way).")
      .def_property_readonly("payload_link",
                             [](const PyTracker& t) { return t.tracker.payload_link_name(); })
      .def_property_readonly(
          "estimate", [](const PyTracker& t) { return t.tracker.estimate(); },
          "the estimate after the last sample")
      .def(
          "update",
          [](PyTracker& self, const py::object& t, const py::object& q, const py::object& wrench,
             const py::object& qd, const py::object& qdd, const py::object& gravity,
             const py::object& sensor_motion, const py::object& q_upstream,
             const py::object& qd_upstream, const py::object& qdd_upstream,
             const std::optional<std::vector<double>>& root_gravity) {
            const py::object ndim = py::module_::import("numpy").attr("ndim");
            if (ndim(t).cast<int>() != 0)
              throw InputError("t: one time (a number) per update; track() takes arrays");
            const TrackInputs in =
                track_inputs(self.tracker.identified(), t, q, wrench, qd, qdd, gravity,
                             sensor_motion, q_upstream, qd_upstream, qdd_upstream, root_gravity);
            return self.step(in, 0);
          },
          py::arg("t"), py::arg("q"), py::arg("wrench"), py::arg("qd") = py::none(),
          py::arg("qdd") = py::none(), py::arg("gravity") = py::none(), py::kw_only(),
          py::arg("sensor_motion") = py::none(), py::arg("q_upstream") = py::none(),
          py::arg("qd_upstream") = py::none(), py::arg("qdd_upstream") = py::none(),
          py::arg("root_gravity") = py::none(),
          (std::string("One sample; returns the TrackerEstimate after it. ") + sample_doc).c_str())
      .def(
          "track",
          [](PyTracker& self, const py::object& t, const py::object& q, const py::object& wrench,
             const py::object& qd, const py::object& qdd, const py::object& gravity,
             const py::object& sensor_motion, const py::object& q_upstream,
             const py::object& qd_upstream, const py::object& qdd_upstream,
             const std::optional<std::vector<double>>& root_gravity) {
            const TrackInputs in =
                track_inputs(self.tracker.identified(), t, q, wrench, qd, qdd, gravity,
                             sensor_motion, q_upstream, qd_upstream, qdd_upstream, root_gravity);
            const Eigen::Index n = in.rows();
            const double nan = std::numeric_limits<double>::quiet_NaN();
            Eigen::MatrixXd values(n, 24);
            std::vector<TrackerEvent> events(static_cast<std::size_t>(n));
            {
              py::gil_scoped_release release;
              for (Eigen::Index i = 0; i < n; ++i) {
                const TrackerEstimate& e = self.step(in, i);
                auto row = values.row(i);
                row.head<6>() = e.compensated.transpose();
                row[6] = e.mass;
                row.segment<3>(7) = e.com.transpose();
                row[10] = e.mass_std;
                row[11] = e.com_std;
                for (int k = 0; k < 6; ++k)
                  row[12 + k] = e.inertia_determined
                                    ? e.inertia(kTrackInertia[k][0], kTrackInertia[k][1])
                                    : nan;
                row.tail<6>() = e.offset.transpose();
                events[static_cast<std::size_t>(i)] = e.event;
              }
            }
            return track_columns(values, events);
          },
          py::arg("t"), py::arg("q"), py::arg("wrench"), py::arg("qd") = py::none(),
          py::arg("qdd") = py::none(), py::arg("gravity") = py::none(), py::kw_only(),
          py::arg("sensor_motion") = py::none(), py::arg("q_upstream") = py::none(),
          py::arg("qd_upstream") = py::none(), py::arg("qdd_upstream") = py::none(),
          py::arg("root_gravity") = py::none(),
          (std::string(
               "Samples [N] in order, looped in C++, continuing from the tracker's state; "
               "returns compensate --track's columns by name: fx_comp..mz_comp, payload_m, "
               "payload_cx..cz, payload_m_std, payload_c_std, payload_ixx..izz (NaN while "
               "undetermined), offset_fx..mz ([N] floats) and event ([N] str). The arguments "
               "as update()'s with one row per sample: ") +
           sample_doc)
              .c_str())
      .def("__repr__", [](const PyTracker& t) {
        return fmt::format("Tracker(payload_link='{}')", t.tracker.payload_link_name());
      });
}

}  // namespace massid::python
