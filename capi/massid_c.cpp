// The C interface (include/massid.h): a thin adapter over the identified
// model every door shares (identified_model.hpp): loading as `massid predict`
// does, predicting the mechanism's wrench (static or dynamic parameters)
// without the offset; and over the library's Tracker (tracker.hpp), as
// `massid compensate --track` uses it.
// Every entry point catches everything: no exception crosses the C boundary.
#include <Eigen/Core>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <new>
#include <optional>
#include <string>
#include <vector>

#include "massid.h"
#include "massid/core/errors.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/model.hpp"
#include "massid/core/predictor.hpp"
#include "massid/io/params_file.hpp"
#include "massid/io/urdf.hpp"
#include "massid/live/identified_model.hpp"
#include "massid/live/tracker.hpp"

namespace {

using massid::Wrench;

// Writes msg into the caller's buffer, truncated to fit, NUL-terminated.
void copy_message(const char* msg, char* error, size_t error_size) {
  if (!error || error_size == 0) return;
  const size_t n = std::min(std::strlen(msg), error_size - 1);
  std::memcpy(error, msg, n);
  error[n] = '\0';
}

bool finite(const double* x, int n) {
  for (int i = 0; i < n; ++i)
    if (!std::isfinite(x[i])) return false;
  return true;
}

// What a mechanism without joints gets for its (possibly NULL) joint arrays:
// the predictors read element 0 of them for the lanes without a joint.
constexpr double kNoJoints[1] = {0.0};

const double* joint_array(const double* x, int num_joints) {
  return num_joints > 0 ? x : kNoJoints;
}

void fill_nan(double wrench[6]) {
  if (wrench)
    for (int k = 0; k < 6; ++k) wrench[k] = std::numeric_limits<double>::quiet_NaN();
}

// A load error with the status it maps to.
struct LoadError {
  int code;
  std::string message;
};

}  // namespace

struct massid_predictor {
  std::vector<std::string> joint_names;  // [num_joints] Model::joints, the order of q
  // The model, parameters and compiled predictor (identified_model.hpp): its
  // Model's chain from the URDF root (Model::upstream, upstream_joints) turns
  // root gravity into the sensor frame (upstream_kinematics).
  massid::IdentifiedModel identified;
  std::string sensor_link;
  // The workspace, mutable: written by every predict call through the C API's
  // const handle (a clone copies it: each handle has its own).
  mutable massid::IdentifiedModelData data;

  explicit massid_predictor(massid::IdentifiedModel m)
      : identified(std::move(m)), sensor_link(identified.model().sensor_link()), data(identified) {
    for (const massid::Joint& j : identified.model().joints) joint_names.push_back(j.name);
  }
  int num_joints() const { return static_cast<int>(joint_names.size()); }
  const massid::Model& model() const { return identified.model(); }
};

// A tracker: the library's, nothing beside it (its model, its time order:
// massid::Tracker's own).
struct massid_tracker {
  massid::Tracker tracker;
  const massid::IdentifiedModel& identified() const { return tracker.identified(); }
};

namespace {

// The one loading of every door (IdentifiedModel::load, as `massid predict`):
// the params file, the URDF at its sensor link with its held joints, its
// values in this model's basis. A params file that cannot be read is a file
// error; a URDF that loads at its root but does not fit the file is another
// robot.
std::unique_ptr<massid_predictor> load(const char* urdf_path, const char* params_path) {
  massid::ParamsFile params;
  try {
    params = massid::read_params(params_path);
  } catch (const massid::InputError& e) {
    throw LoadError{MASSID_ERROR_FILE, e.what()};
  }
  try {
    return std::make_unique<massid_predictor>(massid::IdentifiedModel::load(urdf_path, params));
  } catch (const massid::InputError& e) {
    int code = MASSID_ERROR_FILE;
    try {
      (void)massid::load_urdf(urdf_path);
      code = MASSID_ERROR_MODEL_MISMATCH;
    } catch (const massid::InputError&) {
    }
    throw LoadError{code, e.what()};
  }
}

// The checks every predict call makes; MASSID_OK when the call may go on.
int check_inputs(const massid_predictor* p, const double* q, const double* qd, const double* qdd,
                 const double* gravity, const double* sensor_motion, double* wrench) {
  if (!p || !gravity || !wrench) return MASSID_ERROR_INVALID_ARGUMENT;
  const int n = p->num_joints();
  if (n > 0 && (!q || !qd || !qdd)) return MASSID_ERROR_INVALID_ARGUMENT;
  if (!finite(gravity, 3) || !finite(q, n) || !finite(qd, n) || !finite(qdd, n) ||
      (sensor_motion && !finite(sensor_motion, 9)))
    return MASSID_ERROR_NOT_FINITE;
  return MASSID_OK;
}

int predict_motion(const massid_predictor* p, const double* q, const double* qd, const double* qdd,
                   const double* gravity, const double* sensor_motion, double* wrench) noexcept {
  try {
    int code = check_inputs(p, q, qd, qdd, gravity, sensor_motion, wrench);
    if (code == MASSID_OK && !p->identified.dynamic()) code = MASSID_ERROR_STATIC_PARAMS;
    if (code == MASSID_OK && sensor_motion && !p->identified.sensor_moving())
      for (int k = 0; k < 9; ++k)
        if (sensor_motion[k] != 0.0) code = MASSID_ERROR_SENSOR_MOTION;
    if (code != MASSID_OK) {
      fill_nan(wrench);
      return code;
    }
    massid::FrameMotion frame;
    if (sensor_motion) {
      frame.omega = Eigen::Vector3d(sensor_motion);
      frame.omega_dot = Eigen::Vector3d(sensor_motion + 3);
      frame.accel = Eigen::Vector3d(sensor_motion + 6);
    }
    Eigen::Map<Wrench>{wrench} =
        p->identified.predict(p->data, q, qd, qdd, Eigen::Vector3d(gravity), frame);
    return MASSID_OK;
  } catch (...) {
    fill_nan(wrench);
    return MASSID_ERROR_INTERNAL;
  }
}

// Gravity [3] in the sensor frame and, when sensor_motion is given, the sensor
// frame's motion [9] (wx..wz, dwx..dwz, ax..az) from the joints above the
// sensor link (Model::upstream) and gravity in the root frame.
int sensor_frame(const massid::Model* model, const double* qu, const double* qdu,
                 const double* qddu, const double* root_gravity, double* gravity,
                 double* sensor_motion) {
  if (!model || !root_gravity) return MASSID_ERROR_INVALID_ARGUMENT;
  const int nu = model->num_upstream_joints();
  const bool moving = sensor_motion != nullptr;
  if (nu > 0 && (!qu || (moving && (!qdu || !qddu)))) return MASSID_ERROR_INVALID_ARGUMENT;
  if (!finite(root_gravity, 3) || !finite(qu, nu) ||
      (moving && (!finite(qdu, nu) || !finite(qddu, nu))))
    return MASSID_ERROR_NOT_FINITE;
  massid::upstream_sensor_frame(*model, joint_array(qu, nu),
                                moving ? joint_array(qdu, nu) : nullptr,
                                moving ? joint_array(qddu, nu) : nullptr,
                                Eigen::Vector3d(root_gravity), gravity, sensor_motion);
  return MASSID_OK;
}

}  // namespace

extern "C" {

const char* massid_error_string(int code) {
  switch (code) {
    case MASSID_OK:
      return "success";
    case MASSID_ERROR_INVALID_ARGUMENT:
      return "invalid argument: a NULL pointer, or a size or index out of range";
    case MASSID_ERROR_FILE:
      return "a URDF or params file cannot be read or is malformed";
    case MASSID_ERROR_MODEL_MISMATCH:
      return "the params file does not belong to this URDF (another robot, sensor link or "
             "joints)";
    case MASSID_ERROR_STATIC_PARAMS:
      return "static (first-moment) parameters cannot predict in motion: identify with "
             "massid identify --dynamic";
    case MASSID_ERROR_NOT_FINITE:
      return "an input number is NaN or infinite";
    case MASSID_ERROR_INTERNAL:
      return "internal error: out of memory or a defect of massid";
    case MASSID_ERROR_SENSOR_MOTION:
      return "the parameters were identified with the sensor frame at rest and cannot predict "
             "it moving: identify from a log with the sensor's motion";
    case MASSID_ERROR_TIME_ORDER:
      return "the tracker's time t does not increase past the previous sample's: the sample is "
             "ignored";
    default:
      return "unknown massid status code";
  }
}

const char* massid_version(void) { return MASSID_VERSION_STRING; }

int massid_predictor_open(const char* urdf_path, const char* params_path, massid_predictor** out,
                          char* error, size_t error_size) {
  copy_message("", error, error_size);
  if (out) *out = nullptr;
  if (!urdf_path || !params_path || !out) {
    copy_message(!out         ? "massid_predictor_open: out is NULL"
                 : !urdf_path ? "massid_predictor_open: urdf_path is NULL"
                              : "massid_predictor_open: params_path is NULL",
                 error, error_size);
    return MASSID_ERROR_INVALID_ARGUMENT;
  }
  try {
    *out = load(urdf_path, params_path).release();
    return MASSID_OK;
  } catch (const LoadError& e) {
    copy_message(e.message.c_str(), error, error_size);
    return e.code;
  } catch (const std::bad_alloc&) {
    copy_message("massid: out of memory while loading", error, error_size);
  } catch (const std::exception& e) {
    copy_message(e.what(), error, error_size);
  } catch (...) {
    copy_message("massid: unknown internal error while loading", error, error_size);
  }
  return MASSID_ERROR_INTERNAL;
}

massid_predictor* massid_predictor_load(const char* urdf_path, const char* params_path, char* error,
                                        size_t error_size) {
  massid_predictor* p = nullptr;
  if (!urdf_path || !params_path) {
    copy_message(!urdf_path ? "massid_predictor_load: urdf_path is NULL"
                            : "massid_predictor_load: params_path is NULL",
                 error, error_size);
    return nullptr;
  }
  massid_predictor_open(urdf_path, params_path, &p, error, error_size);
  return p;
}

massid_predictor* massid_predictor_clone(const massid_predictor* p) {
  if (!p) return nullptr;
  try {
    return new massid_predictor(*p);
  } catch (...) {
    return nullptr;
  }
}

void massid_predictor_free(massid_predictor* p) { delete p; }

int massid_predictor_num_joints(const massid_predictor* p) {
  return p ? p->num_joints() : MASSID_ERROR_INVALID_ARGUMENT;
}

const char* massid_predictor_joint_name(const massid_predictor* p, int i) {
  if (!p || i < 0 || i >= p->num_joints()) return nullptr;
  return p->joint_names[static_cast<size_t>(i)].c_str();
}

const char* massid_predictor_sensor_link(const massid_predictor* p) {
  return p ? p->sensor_link.c_str() : nullptr;
}

int massid_predictor_is_dynamic(const massid_predictor* p) {
  return p ? (p->identified.dynamic() ? 1 : 0) : MASSID_ERROR_INVALID_ARGUMENT;
}

int massid_predictor_has_offset(const massid_predictor* p) {
  return p ? (p->identified.has_offset() ? 1 : 0) : MASSID_ERROR_INVALID_ARGUMENT;
}

int massid_predictor_delay(const massid_predictor* p, double* delay) {
  if (!p || !delay) return MASSID_ERROR_INVALID_ARGUMENT;
  *delay = p->identified.delay();
  return MASSID_OK;
}

int massid_predictor_offset(const massid_predictor* p, double offset[6]) {
  if (!p || !offset) return MASSID_ERROR_INVALID_ARGUMENT;
  Eigen::Map<Wrench>{offset} = p->identified.offset();
  return MASSID_OK;
}

int massid_predict(const massid_predictor* p, const double* q, const double gravity[3],
                   double wrench[6]) {
  try {
    // Static and dynamic alike: the weight (dynamic: at zero joint velocity
    // and acceleration), without the offset.
    const int code = check_inputs(p, q, q, q, gravity, nullptr, wrench);
    if (code != MASSID_OK) {
      fill_nan(wrench);
      return code;
    }
    Eigen::Map<Wrench>{wrench} = p->identified.predict_gravity(
        p->data, joint_array(q, p->num_joints()), Eigen::Vector3d(gravity));
    return MASSID_OK;
  } catch (...) {
    fill_nan(wrench);
    return MASSID_ERROR_INTERNAL;
  }
}

int massid_predict_motion(const massid_predictor* p, const double* q, const double* qd,
                          const double* qdd, const double gravity[3], double wrench[6]) {
  return predict_motion(p, q, qd, qdd, gravity, nullptr, wrench);
}

int massid_predict_motion_sensor(const massid_predictor* p, const double* q, const double* qd,
                                 const double* qdd, const double gravity[3],
                                 const double sensor_motion[9], double wrench[6]) {
  return predict_motion(p, q, qd, qdd, gravity, sensor_motion, wrench);
}

int massid_predictor_num_upstream_joints(const massid_predictor* p) {
  return p ? p->model().num_upstream_joints() : MASSID_ERROR_INVALID_ARGUMENT;
}

const char* massid_predictor_upstream_joint_name(const massid_predictor* p, int i) {
  if (!p || i < 0 || i >= p->model().num_upstream_joints()) return nullptr;
  return p->model().upstream_joints[static_cast<size_t>(i)].name.c_str();
}

int massid_predict_upstream(const massid_predictor* p, const double* qu,
                            const double root_gravity[3], const double* q, double wrench[6]) {
  try {
    double gravity[3];
    const int code = sensor_frame(p ? &p->model() : nullptr, qu, nullptr, nullptr, root_gravity,
                                  gravity, nullptr);
    if (code != MASSID_OK) {
      fill_nan(wrench);
      return code;
    }
    return massid_predict(p, q, gravity, wrench);
  } catch (...) {
    fill_nan(wrench);
    return MASSID_ERROR_INTERNAL;
  }
}

int massid_predict_motion_upstream(const massid_predictor* p, const double* qu, const double* qdu,
                                   const double* qddu, const double root_gravity[3],
                                   const double* q, const double* qd, const double* qdd,
                                   double wrench[6]) {
  try {
    double gravity[3], sensor_motion[9];
    const int code = sensor_frame(p ? &p->model() : nullptr, qu, qdu, qddu, root_gravity, gravity,
                                  sensor_motion);
    if (code != MASSID_OK) {
      fill_nan(wrench);
      return code;
    }
    return predict_motion(p, q, qd, qdd, gravity, sensor_motion, wrench);
  } catch (...) {
    fill_nan(wrench);
    return MASSID_ERROR_INTERNAL;
  }
}

// ---------------------------------------------------------------- tracking

int massid_tracker_create(const massid_predictor* p, const char* payload_link,
                          const double noise[6], massid_tracker** out, char* error,
                          size_t error_size) {
  copy_message("", error, error_size);
  if (out) *out = nullptr;
  if (!p || !out) {
    copy_message(!out ? "massid_tracker_create: out is NULL" : "massid_tracker_create: p is NULL",
                 error, error_size);
    return MASSID_ERROR_INVALID_ARGUMENT;
  }
  try {
    massid::TrackerOptions options;
    if (payload_link) options.payload_link = payload_link;
    if (noise) {
      if (!finite(noise, 6)) {
        copy_message("massid_tracker_create: noise holds a NaN or infinite value", error,
                     error_size);
        return MASSID_ERROR_NOT_FINITE;
      }
      options.noise = Eigen::Map<const Wrench>(noise);
    } else {
      options.noise = massid::tracker_noise(p->identified.residual_rms());
    }
    *out = new massid_tracker{massid::Tracker(p->identified, options)};
    return MASSID_OK;
  } catch (const massid::InputError& e) {  // the payload link
    copy_message(e.what(), error, error_size);
    return MASSID_ERROR_INVALID_ARGUMENT;
  } catch (const massid::ArgumentError& e) {  // the noise
    copy_message(e.what(), error, error_size);
    return MASSID_ERROR_INVALID_ARGUMENT;
  } catch (const std::bad_alloc&) {
    copy_message("massid: out of memory while making the tracker", error, error_size);
  } catch (const std::exception& e) {
    copy_message(e.what(), error, error_size);
  } catch (...) {
    copy_message("massid: unknown internal error while making the tracker", error, error_size);
  }
  return MASSID_ERROR_INTERNAL;
}

void massid_tracker_free(massid_tracker* tracker) { delete tracker; }

const char* massid_tracker_payload_link(const massid_tracker* tracker) {
  return tracker ? tracker->tracker.payload_link_name().c_str() : nullptr;
}

namespace {

// The library's estimate in the C struct.
void copy_estimate(const massid::TrackerEstimate& e, massid_tracker_estimate* out) {
  if (!out) return;
  out->payload_m = e.mass;
  out->payload_m_std = e.mass_std;
  out->payload_c_std = e.com_std;
  for (int k = 0; k < 3; ++k) {
    out->payload_c[k] = e.com[k];
    out->payload_c_stds[k] = e.com_stds[k];
  }
  const int upper[6][2] = {{0, 0}, {0, 1}, {0, 2}, {1, 1}, {1, 2}, {2, 2}};
  for (int k = 0; k < 6; ++k) out->payload_inertia[k] = e.inertia(upper[k][0], upper[k][1]);
  out->inertia_determined = e.inertia_determined ? 1 : 0;
  for (int k = 0; k < 6; ++k) {
    out->offset[k] = e.offset[k];
    out->offset_std[k] = e.offset_std[k];
    out->comp[k] = e.compensated[k];
  }
  out->event = e.event == massid::TrackerEvent::Change    ? MASSID_EVENT_CHANGE
               : e.event == massid::TrackerEvent::Contact ? MASSID_EVENT_CONTACT
                                                          : MASSID_EVENT_NONE;
  out->d2 = e.d2;
}

// The update both entry points share, the sensor frame given.
int tracker_update(massid_tracker* tr, double t, const double* q, const double* qd,
                   const double* qdd, const double* gravity, const double* sensor_motion,
                   const double* measured, massid_tracker_estimate* estimate) {
  if (!tr || !gravity || !measured) return MASSID_ERROR_INVALID_ARGUMENT;
  const massid::IdentifiedModel& identified = tr->identified();
  const bool dynamic = identified.dynamic();
  const int n = identified.num_joints();
  if ((n > 0 && !q) || (dynamic && n > 0 && !qd != !qdd)) return MASSID_ERROR_INVALID_ARGUMENT;
  const bool motion = dynamic && qd && qdd;
  if (!std::isfinite(t) || !finite(gravity, 3) || !finite(measured, 6) || !finite(q, n) ||
      (motion && (!finite(qd, n) || !finite(qdd, n))) ||
      (dynamic && sensor_motion && !finite(sensor_motion, 9)))
    return MASSID_ERROR_NOT_FINITE;
  if (dynamic && sensor_motion && !identified.sensor_moving())
    for (int k = 0; k < 9; ++k)
      if (sensor_motion[k] != 0.0) return MASSID_ERROR_SENSOR_MOTION;
  massid::FrameMotion frame;
  if (dynamic && sensor_motion) {
    frame.omega = Eigen::Vector3d(sensor_motion);
    frame.omega_dot = Eigen::Vector3d(sensor_motion + 3);
    frame.accel = Eigen::Vector3d(sensor_motion + 6);
  }
  try {
    copy_estimate(
        tr->tracker.update(t, joint_array(q, n), motion ? qd : nullptr, motion ? qdd : nullptr,
                           Eigen::Vector3d(gravity), frame, Eigen::Map<const Wrench>(measured)),
        estimate);
  } catch (const massid::ArgumentError&) {  // t finite, so: it does not increase
    return MASSID_ERROR_TIME_ORDER;
  }
  return MASSID_OK;
}

}  // namespace

int massid_tracker_update(massid_tracker* tracker, double t, const double* q, const double* qd,
                          const double* qdd, const double gravity[3], const double sensor_motion[9],
                          const double measured[6], massid_tracker_estimate* estimate) {
  try {
    return tracker_update(tracker, t, q, qd, qdd, gravity, sensor_motion, measured, estimate);
  } catch (...) {
    return MASSID_ERROR_INTERNAL;
  }
}

int massid_tracker_update_upstream(massid_tracker* tracker, double t, const double* qu,
                                   const double* qdu, const double* qddu,
                                   const double root_gravity[3], const double* q, const double* qd,
                                   const double* qdd, const double measured[6],
                                   massid_tracker_estimate* estimate) {
  try {
    if (!tracker) return MASSID_ERROR_INVALID_ARGUMENT;
    const massid::IdentifiedModel& identified = tracker->identified();
    if (identified.dynamic() && identified.model().num_upstream_joints() > 0 && !qdu != !qddu)
      return MASSID_ERROR_INVALID_ARGUMENT;
    // The sensor frame's motion from the upstream joints' rates for dynamic
    // parameters given them, as compensate takes it (static ones never read it).
    const bool moving = identified.dynamic() && qdu && qddu;
    double gravity[3], sensor_motion[9];
    const int code = sensor_frame(&identified.model(), qu, qdu, qddu, root_gravity, gravity,
                                  moving ? sensor_motion : nullptr);
    if (code != MASSID_OK) return code;
    return tracker_update(tracker, t, q, qd, qdd, gravity, moving ? sensor_motion : nullptr,
                          measured, estimate);
  } catch (...) {
    return MASSID_ERROR_INTERNAL;
  }
}

int massid_tracker_get_estimate(const massid_tracker* tracker, massid_tracker_estimate* estimate) {
  if (!tracker || !estimate) return MASSID_ERROR_INVALID_ARGUMENT;
  copy_estimate(tracker->tracker.estimate(), estimate);
  return MASSID_OK;
}

const char* massid_tracker_event_name(int event) {
  switch (event) {
    case MASSID_EVENT_NONE:
      return massid::tracker_event_name(massid::TrackerEvent::None);
    case MASSID_EVENT_CHANGE:
      return massid::tracker_event_name(massid::TrackerEvent::Change);
    case MASSID_EVENT_CONTACT:
      return massid::tracker_event_name(massid::TrackerEvent::Contact);
    default:
      return nullptr;
  }
}

}  // extern "C"
