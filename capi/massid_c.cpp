// The C interface (include/massid.h) over the library: loading as `massid
// predict` does (params_file.hpp, model.hpp), predicting with the static
// predictor (predictor.hpp) or the motion predictor (motion_predictor.hpp).
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
#include "massid/base_parameters.hpp"
#include "massid/errors.hpp"
#include "massid/kinematics.hpp"
#include "massid/model.hpp"
#include "massid/motion_predictor.hpp"
#include "massid/params_file.hpp"
#include "massid/predictor.hpp"

namespace {

using massid::Wrench;

// The static predictor compiled WITHOUT the offset (Predictor::offset zeroed
// after it was kept in the handle), so that predict() gives the mechanism's
// wrench alone, to the bit what it computes before adding the offset.
struct StaticPart {
  massid::Predictor predictor;
  massid::PredictorData data;  // predict()'s workspace
  explicit StaticPart(massid::Predictor p) : predictor(std::move(p)), data(predictor) {}
};

// The motion predictor (its predict_motion never adds the offset).
struct MotionPart {
  massid::MotionPredictor predictor;
  massid::MotionPredictorData data;  // predict_motion()'s workspace
  std::vector<double> zeros;         // [num_joints] qd = qdd = 0 for massid_predict
  explicit MotionPart(massid::MotionPredictor p)
      : predictor(std::move(p)), data(predictor), zeros(predictor.num_joints, 0.0) {}
};

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
  // The model at the sensor link: its chain from the URDF root (Model::upstream,
  // upstream_joints) turns root gravity into the sensor frame (upstream_kinematics).
  massid::Model model;
  std::string sensor_link;
  Wrench offset = Wrench::Zero();  // the identified offsets, zero without
  bool has_offset = false;
  bool sensor_moving = false;  // identified with the sensor frame moving (dynamic)
  // One of the two, by the params file's model; mutable: the workspace is
  // written by every predict call through the C API's const handle.
  mutable std::optional<StaticPart> rest;
  mutable std::optional<MotionPart> motion;

  int num_joints() const { return static_cast<int>(joint_names.size()); }
};

namespace {

// massid predict's loading (apps/main.cpp run_predict): the params file, the
// URDF at its sensor link with its held joints, its values in this model's basis.
std::unique_ptr<massid_predictor> load(const char* urdf_path, const char* params_path) {
  massid::ParamsFile params;
  try {
    params = massid::read_params(params_path);
  } catch (const massid::InputError& e) {
    throw LoadError{MASSID_ERROR_FILE, e.what()};
  }
  massid::Model model;
  try {
    model = massid::load_urdf(urdf_path, params.sensor_link);
  } catch (const massid::InputError& e) {
    // A URDF that loads at its root but lacks the file's sensor link is another robot.
    int code = MASSID_ERROR_FILE;
    try {
      (void)massid::load_urdf(urdf_path);
      code = MASSID_ERROR_MODEL_MISMATCH;
    } catch (const massid::InputError&) {
    }
    throw LoadError{code, e.what()};
  }
  auto p = std::make_unique<massid_predictor>();
  try {
    model = massid::hold_joints(std::move(model), params.held);
    const massid::BaseParameters base =
        massid::find_base_parameters(model, massid::base_parameter_options(params));
    const Eigen::VectorXd values = massid::values_in_basis(params, model, base);
    if (params.dynamic) {
      p->motion.emplace(massid::compile_motion_predictor(model, base, values));
      p->offset = p->motion->predictor.offset;
    } else {
      massid::Predictor predictor = massid::compile_predictor(model, base, values);
      p->offset = predictor.offset;
      predictor.offset = Wrench::Zero();
      p->rest.emplace(std::move(predictor));
    }
    p->has_offset = base.offset;
    p->sensor_moving = params.sensor_moving;
  } catch (const massid::InputError& e) {
    throw LoadError{MASSID_ERROR_MODEL_MISMATCH, e.what()};
  }
  for (const massid::Joint& j : model.joints) p->joint_names.push_back(j.name);
  p->sensor_link = model.sensor_link();
  p->model = std::move(model);
  return p;
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
    if (code == MASSID_OK && !p->motion) code = MASSID_ERROR_STATIC_PARAMS;
    if (code == MASSID_OK && sensor_motion && !p->sensor_moving)
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
    MotionPart& m = *p->motion;
    const int n = p->num_joints();
    Eigen::Map<Wrench>{wrench} =
        massid::predict_motion(m.predictor, m.data, joint_array(q, n), joint_array(qd, n),
                               joint_array(qdd, n), Eigen::Vector3d(gravity), frame);
    return MASSID_OK;
  } catch (...) {
    fill_nan(wrench);
    return MASSID_ERROR_INTERNAL;
  }
}

// Gravity [3] in the sensor frame and, when sensor_motion is given, the sensor
// frame's motion [9] (wx..wz, dwx..dwz, ax..az) from the joints above the
// sensor link (Model::upstream) and gravity in the root frame.
int sensor_frame(const massid_predictor* p, const double* qu, const double* qdu, const double* qddu,
                 const double* root_gravity, double* gravity, double* sensor_motion) {
  if (!p || !root_gravity) return MASSID_ERROR_INVALID_ARGUMENT;
  const int nu = p->model.num_upstream_joints();
  const bool moving = sensor_motion != nullptr;
  if (nu > 0 && (!qu || (moving && (!qdu || !qddu)))) return MASSID_ERROR_INVALID_ARGUMENT;
  if (!finite(root_gravity, 3) || !finite(qu, nu) ||
      (moving && (!finite(qdu, nu) || !finite(qddu, nu))))
    return MASSID_ERROR_NOT_FINITE;
  massid::upstream_sensor_frame(p->model, joint_array(qu, nu),
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
  return p ? (p->motion ? 1 : 0) : MASSID_ERROR_INVALID_ARGUMENT;
}

int massid_predictor_has_offset(const massid_predictor* p) {
  return p ? (p->has_offset ? 1 : 0) : MASSID_ERROR_INVALID_ARGUMENT;
}

int massid_predictor_offset(const massid_predictor* p, double offset[6]) {
  if (!p || !offset) return MASSID_ERROR_INVALID_ARGUMENT;
  Eigen::Map<Wrench>{offset} = p->offset;
  return MASSID_OK;
}

int massid_predict(const massid_predictor* p, const double* q, const double gravity[3],
                   double wrench[6]) {
  try {
    if (p && p->motion) {
      const double* zeros = p->motion->zeros.data();
      return predict_motion(p, q, zeros, zeros, gravity, nullptr, wrench);
    }
    const int code = check_inputs(p, q, q, q, gravity, nullptr, wrench);
    if (code != MASSID_OK) {
      fill_nan(wrench);
      return code;
    }
    StaticPart& s = *p->rest;
    const Eigen::Map<const Eigen::VectorXd> qv(joint_array(q, p->num_joints()), p->num_joints());
    Eigen::Map<Wrench>{wrench} = massid::predict(s.predictor, s.data, qv, Eigen::Vector3d(gravity));
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
  return p ? p->model.num_upstream_joints() : MASSID_ERROR_INVALID_ARGUMENT;
}

const char* massid_predictor_upstream_joint_name(const massid_predictor* p, int i) {
  if (!p || i < 0 || i >= p->model.num_upstream_joints()) return nullptr;
  return p->model.upstream_joints[static_cast<size_t>(i)].name.c_str();
}

int massid_predict_upstream(const massid_predictor* p, const double* qu,
                            const double root_gravity[3], const double* q, double wrench[6]) {
  try {
    double gravity[3];
    const int code = sensor_frame(p, qu, nullptr, nullptr, root_gravity, gravity, nullptr);
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
    const int code = sensor_frame(p, qu, qdu, qddu, root_gravity, gravity, sensor_motion);
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

}  // extern "C"
