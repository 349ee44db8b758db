/* massid.h: the C interface of massid (library libmassid_c, pkg-config massid-c,
 * CMake target massid::c).
 *
 * Loads a URDF and a params file (massid identify -o PARAMS.json, static or
 * --dynamic) and predicts the wrench the mechanism exerts on the sensor, at
 * rest or in motion, into arrays the caller owns; tracks a payload and the
 * sensor's drifting offsets online (massid_tracker_*, as `massid compensate
 * --track`). Pure C (C99 and later, and
 * C++); for C programs, Simulink/LabVIEW targets and foreign-function
 * interfaces (Python ctypes, Julia ccall, ...).
 *
 * Conventions (as the command-line tool's, docs/method.md, docs/motion.md):
 *  - SI units: m, kg, N, N m, rad, m/s^2 (m and m/s for prismatic joints).
 *  - A wrench is double[6]: fx, fy, fz (N), mx, my, mz (N m): what the
 *    mechanism exerts on the sensor, in the sensor frame, the moment about
 *    the sensor-frame origin, as `massid predict` writes in fx_pred .. mz_pred.
 *    It never includes the sensor offset; massid_predictor_offset gives that.
 *  - gravity is double[3], the gravity acceleration in the sensor frame
 *    (level, sensor z up: 0, 0, -9.80665).
 *  - Joint arrays (q, qd, qdd) have massid_predictor_num_joints entries in the
 *    order of massid_predictor_joint_name: the independent movable joints
 *    below the sensor link, as the CLI's CSV columns (URDF mimic joints follow
 *    their masters and have no entry; joints the params file holds still have
 *    none either). Radians for revolute joints, metres for prismatic ones.
 *    When there are no joints the joint arrays may be NULL.
 *
 * Return codes: 0 (MASSID_OK) on success, a negative massid_status otherwise;
 * massid_error_string(code) says what it means. A predict call that fails
 * fills wrench with NaN (when wrench is not NULL), so that a caller that does
 * not check the code does not act on a stale value.
 *
 * Allocation: only massid_predictor_load/open/clone and massid_tracker_create
 * allocate (the model, the compiled predictor and its workspace). The predict
 * calls, the tracker updates and every query never allocate, never lock and
 * never throw.
 *
 * Thread safety: a handle holds its own workspace, which every predict call
 * writes, so one handle must not be used by two threads at once: give each
 * thread its own handle (massid_predictor_clone copies one without reading
 * the files again). Different handles are independent; a tracker is a handle
 * of its own (one thread at a time), independent of the predictor it was made
 * from. The queries
 * (num_joints, joint_name, offset, ...) only read what loading wrote and may
 * run alongside anything but massid_predictor_free. massid_error_string and
 * massid_version return static strings. The library has no global state.
 */
#ifndef MASSID_H
#define MASSID_H

#include <stddef.h>

#include "massid_version.h" /* MASSID_VERSION_MAJOR, _MINOR, _PATCH, MASSID_VERSION_STRING */

#if defined(_WIN32)
#define MASSID_C_API
#else
#define MASSID_C_API __attribute__((visibility("default")))
#endif

#ifdef __cplusplus
extern "C" {
#endif

/* Return codes. Zero is success; errors are negative. */
typedef enum massid_status {
  MASSID_OK = 0,
  /* A NULL pointer where an array or handle is needed, a size or index out of
   * range. */
  MASSID_ERROR_INVALID_ARGUMENT = -1,
  /* A URDF or params file that cannot be read or is malformed (load only; the
   * message names the file, line and column). */
  MASSID_ERROR_FILE = -2,
  /* The params file does not belong to the URDF: another robot, a sensor link
   * the URDF lacks, joints it does not have (load only). */
  MASSID_ERROR_MODEL_MISMATCH = -3,
  /* A prediction in motion asked of static (first-moment) parameters: they
   * hold no inertia. Identify with `massid identify --dynamic`. */
  MASSID_ERROR_STATIC_PARAMS = -4,
  /* An input number is NaN or infinite. */
  MASSID_ERROR_NOT_FINITE = -5,
  /* Out of memory, or a defect of massid (the message says which). */
  MASSID_ERROR_INTERNAL = -6,
  /* A moving sensor frame asked of parameters identified with the sensor at
   * rest: they do not hold what its motion shows (the sensor link's inertia,
   * the inertia about axes the joints never turned about). Identify from a log
   * with the sensor's motion (wx .. az columns, or joints above the sensor). */
  MASSID_ERROR_SENSOR_MOTION = -7,
  /* A tracker update whose time t does not increase past the previous
   * update's (massid_tracker_update*): the sample is ignored. */
  MASSID_ERROR_TIME_ORDER = -8
} massid_status;

/* What a return code means: a static, NUL-terminated English sentence; an
 * unknown code gets "unknown massid status code". Thread-safe. */
MASSID_C_API const char* massid_error_string(int code);

/* The library's version, "MAJOR.MINOR.PATCH" (static string). Compare with
 * MASSID_VERSION_STRING to check that the header matches the library. */
MASSID_C_API const char* massid_version(void);

/* A loaded model and params file with its compiled predictor and workspace. */
typedef struct massid_predictor massid_predictor;

/* Loads the URDF at urdf_path and the params file at params_path (static or
 * dynamic), as `massid predict` does: the URDF at the params file's sensor
 * link, with the joints the file holds still held, the file's base
 * parameters mapped onto this model, the predictor compiled.
 *   error, error_size: a buffer of error_size bytes for the message on
 *   failure (file, line and column, and what to do), truncated to fit and
 *   always NUL-terminated; may be NULL (or error_size 0) for no message.
 *   Cleared to "" on success.
 * Returns the handle (free it with massid_predictor_free), NULL on failure. */
MASSID_C_API massid_predictor* massid_predictor_load(const char* urdf_path, const char* params_path,
                                                     char* error, size_t error_size);

/* massid_predictor_load with the return code: *out is the handle, or NULL on
 * failure. Returns MASSID_OK, MASSID_ERROR_INVALID_ARGUMENT (a NULL path or
 * out), MASSID_ERROR_FILE, MASSID_ERROR_MODEL_MISMATCH or
 * MASSID_ERROR_INTERNAL. */
MASSID_C_API int massid_predictor_open(const char* urdf_path, const char* params_path,
                                       massid_predictor** out, char* error, size_t error_size);

/* A new handle with the same model and parameters and its own workspace (one
 * per thread); NULL when p is NULL or memory runs out. Allocates. */
MASSID_C_API massid_predictor* massid_predictor_clone(const massid_predictor* p);

/* Frees the handle; NULL is allowed (nothing happens). */
MASSID_C_API void massid_predictor_free(massid_predictor* p);

/* Number of joints, the length of q, qd and qdd (0 for a mechanism without
 * movable joints); MASSID_ERROR_INVALID_ARGUMENT when p is NULL. */
MASSID_C_API int massid_predictor_num_joints(const massid_predictor* p);

/* The URDF name of joint i (0 <= i < num_joints), valid until the handle is
 * freed; NULL when p is NULL or i is out of range. */
MASSID_C_API const char* massid_predictor_joint_name(const massid_predictor* p, int i);

/* The sensor link of the params file, whose frame is the sensor frame; NULL
 * when p is NULL. */
MASSID_C_API const char* massid_predictor_sensor_link(const massid_predictor* p);

/* 1 for dynamic parameters (identify --dynamic: massid_predict_motion works),
 * 0 for static ones, MASSID_ERROR_INVALID_ARGUMENT when p is NULL. */
MASSID_C_API int massid_predictor_is_dynamic(const massid_predictor* p);

/* 1 when the params file has identified sensor offsets (identify --offset),
 * 0 when not, MASSID_ERROR_INVALID_ARGUMENT when p is NULL. */
MASSID_C_API int massid_predictor_has_offset(const massid_predictor* p);

/* offset[6]: the identified sensor offsets (fx, fy, fz, mx, my, mz), zeros
 * when the file has none. What the sensor reads is the predicted wrench plus
 * the offset; the compensated measurement is measured - wrench - offset. */
MASSID_C_API int massid_predictor_offset(const massid_predictor* p, double offset[6]);

/* *delay: the wrench's clock delay in seconds from the params file's "delay"
 * (identify --dynamic --delay; positive: the wrench arrives late), 0 when it
 * has none. The predict calls take the joint state they are given: to
 * compensate the wrench logged at t, pass the joint state of t - delay (as
 * massid predict and compensate do). */
MASSID_C_API int massid_predictor_delay(const massid_predictor* p, double* delay);

/* The mechanism's wrench at rest.
 *   q: [num_joints] joint positions; gravity: [3] in the sensor frame;
 *   wrench: [6] out, fx, fy, fz, mx, my, mz, without the offset.
 * Static parameters: the gravity wrench (docs/method.md); dynamic ones: the
 * wrench in motion at zero joint velocity and acceleration. Returns MASSID_OK,
 * MASSID_ERROR_INVALID_ARGUMENT (a NULL pointer) or MASSID_ERROR_NOT_FINITE.
 * No allocation. */
MASSID_C_API int massid_predict(const massid_predictor* p, const double* q, const double gravity[3],
                                double wrench[6]);

/* The mechanism's wrench in motion, weight and inertial forces, the sensor
 * frame at rest (docs/motion.md).
 *   q, qd, qdd: [num_joints] joint positions, velocities (rad/s, m/s) and
 *   accelerations (rad/s^2, m/s^2); gravity: [3] in the sensor frame;
 *   wrench: [6] out, without the offset.
 * Returns MASSID_OK, MASSID_ERROR_INVALID_ARGUMENT, MASSID_ERROR_NOT_FINITE
 * or MASSID_ERROR_STATIC_PARAMS (static parameters). No allocation. */
MASSID_C_API int massid_predict_motion(const massid_predictor* p, const double* q, const double* qd,
                                       const double* qdd, const double gravity[3],
                                       double wrench[6]);

/* massid_predict_motion with the sensor frame itself moving (a moving
 * platform; the log's wx .. az columns):
 *   sensor_motion: [9] angular velocity wx, wy, wz (rad/s), angular
 *   acceleration dwx, dwy, dwz (rad/s^2) and the acceleration of its origin
 *   without gravity ax, ay, az (m/s^2), all in the sensor frame; NULL: at rest.
 * Same return codes as massid_predict_motion, and MASSID_ERROR_SENSOR_MOTION
 * for a moving sensor frame (any of the nine non-zero) with parameters
 * identified with the sensor at rest. No allocation. */
MASSID_C_API int massid_predict_motion_sensor(const massid_predictor* p, const double* q,
                                              const double* qd, const double* qdd,
                                              const double gravity[3],
                                              const double sensor_motion[9], double wrench[6]);

/* A sensor below movable joints (a wrist sensor), as `massid predict` with the
 * columns of the joints above the sensor link: gravity in the sensor frame is
 * root_gravity turned by them, and in motion their rates give the sensor
 * frame's motion. */

/* Number of movable joints above the sensor link, the length of qu, qdu and
 * qddu (0 when the sensor link is the URDF root);
 * MASSID_ERROR_INVALID_ARGUMENT when p is NULL. */
MASSID_C_API int massid_predictor_num_upstream_joints(const massid_predictor* p);

/* The URDF name of upstream joint i (0 <= i < num_upstream_joints), root
 * first; NULL when p is NULL or i is out of range. */
MASSID_C_API const char* massid_predictor_upstream_joint_name(const massid_predictor* p, int i);

/* massid_predict with gravity from the joints above the sensor:
 *   qu: [num_upstream_joints] their positions; root_gravity: [3] gravity in
 *   the URDF root link's frame (0, 0, -9.80665 for a level root, z up);
 *   q: [num_joints]; wrench: [6] out, without the offset.
 * Same return codes as massid_predict. No allocation. */
MASSID_C_API int massid_predict_upstream(const massid_predictor* p, const double* qu,
                                         const double root_gravity[3], const double* q,
                                         double wrench[6]);

/* massid_predict_motion with the joints above the sensor moving too:
 *   qu, qdu, qddu: [num_upstream_joints] their positions, velocities and
 *   accelerations (the URDF root at rest); root_gravity: [3], root frame;
 *   q, qd, qdd: [num_joints]; wrench: [6] out, without the offset.
 * Same return codes as massid_predict_motion_sensor (the upstream joints
 * moving move the sensor frame). No allocation. */
MASSID_C_API int massid_predict_motion_upstream(const massid_predictor* p, const double* qu,
                                                const double* qdu, const double* qddu,
                                                const double root_gravity[3], const double* q,
                                                const double* qd, const double* qdd,
                                                double wrench[6]);

/* ---------------------------------------------------------------- tracking
 *
 * The payload and the sensor's drifting offsets, tracked online one sample at
 * a time, as `massid compensate --track` does (docs/tracking.md; the library's
 * massid::Tracker, the same code): a rigid payload on a link (zero at the
 * start) and the sensor's six offsets (starting from the params file's, or
 * zero), a change of payload (an object grasped or put down) and rows that
 * carry an external wrench (contact) detected. The same samples give the same
 * numbers, to the bit, as the CLI's columns. */

/* A tracker: its own copy of the predictor's model and its own workspace. */
typedef struct massid_tracker massid_tracker;

/* massid_tracker_estimate.event */
typedef enum massid_tracker_event {
  MASSID_EVENT_NONE = 0,   /* the CLI's event column empty */
  MASSID_EVENT_CHANGE = 1, /* "change": a payload change detected on this sample */
  MASSID_EVENT_CONTACT = 2 /* "contact": the sample carries an external wrench */
} massid_tracker_event;

/* The estimate after a sample: the CLI's columns payload_m .. event and
 * fx_comp .. mz_comp (interface.md, "Tracking"). Physically consistent: mass
 * >= 0, the inertia positive semi-definite and within the triangle
 * inequalities. */
typedef struct massid_tracker_estimate {
  double payload_m;          /* payload_m: mass, kg */
  double payload_c[3];       /* payload_cx, _cy, _cz: centre of mass in the link's frame, m
                                (0 while the mass is not seen) */
  double payload_m_std;      /* payload_m_std, kg */
  double payload_c_std;      /* payload_c_std: the largest of payload_c_stds, m */
  double payload_c_stds[3];  /* std of each centre-of-mass coordinate, m */
  double payload_inertia[6]; /* payload_ixx, _ixy, _ixz, _iyy, _iyz, _izz: about the centre of
                                mass, the link's axes, kg m^2; zeros while undetermined */
  int inertia_determined;    /* 1 when the motion determines the inertia (the CLI writes
                                payload_ixx .. izz), 0 while not (it leaves them empty) */
  double offset[6];          /* offset_fx .. offset_mz: the sensor offsets, N and N m */
  double offset_std[6];      /* their std */
  int event;                 /* massid_tracker_event */
  double d2;      /* the sample's innovation chi^2 (6 degrees of freedom); within the gate by the
                     noise alone, that bound e^T R^-1 e (>= d2): docs/tracking.md */
  double comp[6]; /* fx_comp .. mz_comp: measured - predicted(mechanism and
                     payload) - offset: about zero in free motion, the external
                     wrench in contact */
} massid_tracker_estimate;

/* A tracker for the model and parameters of p (p may be freed afterwards):
 *   payload_link: the payload's link, a measured link of the model; NULL or
 *   "" for the default (as the CLI's --payload-link): the measured link
 *   farthest from the sensor;
 *   noise: [6] the sensor noise, std per axis (fx .. mz; N, N m), all > 0;
 *   NULL for what the CLI takes: the params file's residual RMS per axis
 *   where it has one, else 0.05 N and 0.003 N m;
 *   error, error_size: as massid_predictor_open's (the message names the
 *   model's measured links for a wrong payload_link).
 * Returns MASSID_OK (*out the tracker, free it with massid_tracker_free),
 * MASSID_ERROR_INVALID_ARGUMENT (NULL p or out, a payload_link that is no
 * measured link, a noise not > 0), MASSID_ERROR_NOT_FINITE or
 * MASSID_ERROR_INTERNAL; *out is NULL on failure. Allocates. */
MASSID_C_API int massid_tracker_create(const massid_predictor* p, const char* payload_link,
                                       const double noise[6], massid_tracker** out, char* error,
                                       size_t error_size);

/* Frees the tracker; NULL is allowed. */
MASSID_C_API void massid_tracker_free(massid_tracker* tracker);

/* The payload's link (URDF name), valid until the tracker is freed; NULL when
 * tracker is NULL. */
MASSID_C_API const char* massid_tracker_payload_link(const massid_tracker* tracker);

/* One sample, as massid_predict_motion_sensor takes it:
 *   t: time, s, increasing from sample to sample (the offsets drift with it);
 *   q, qd, qdd: [num_joints] the joints below the sensor (qd and qdd read
 *   for dynamic parameters only; both NULL: the joints at rest); gravity: [3] in
 *   the sensor frame; sensor_motion: [9] as massid_predict_motion_sensor's,
 *   NULL at rest (read for dynamic parameters only); measured: [6] the
 *   sensor's wrench, fx .. mz;
 *   estimate: out, the estimate after the sample (may be NULL;
 *   massid_tracker_get_estimate reads it too).
 * The parameters' clock delay (massid_predictor_delay) is the caller's: pass
 * the joint state of t - delay, as the CLI does. Returns MASSID_OK,
 * MASSID_ERROR_INVALID_ARGUMENT (a NULL pointer, qd without qdd or the
 * reverse), MASSID_ERROR_NOT_FINITE (the tracker is left as it was), MASSID_ERROR_TIME_ORDER (t not
 * after the previous sample's: ignored), MASSID_ERROR_SENSOR_MOTION or MASSID_ERROR_INTERNAL. No
 * allocation. */
MASSID_C_API int massid_tracker_update(massid_tracker* tracker, double t, const double* q,
                                       const double* qd, const double* qdd, const double gravity[3],
                                       const double sensor_motion[9], const double measured[6],
                                       massid_tracker_estimate* estimate);

/* massid_tracker_update for a sensor below movable joints, as
 * massid_predict_motion_upstream takes them: qu [num_upstream_joints] their
 * positions and root_gravity [3] (root frame) give gravity in the sensor
 * frame; for dynamic parameters qdu, qddu (both NULL: the sensor frame at
 * rest) its motion. The CLI's columns of a wrist sensor's log. Same return codes;
 * no allocation. */
MASSID_C_API int massid_tracker_update_upstream(massid_tracker* tracker, double t, const double* qu,
                                                const double* qdu, const double* qddu,
                                                const double root_gravity[3], const double* q,
                                                const double* qd, const double* qdd,
                                                const double measured[6],
                                                massid_tracker_estimate* estimate);

/* *estimate: the estimate after the last good update (zero payload and the
 * starting offsets before any). MASSID_ERROR_INVALID_ARGUMENT for NULL. */
MASSID_C_API int massid_tracker_get_estimate(const massid_tracker* tracker,
                                             massid_tracker_estimate* estimate);

/* "", "change" or "contact" (the CLI's event column) for a
 * massid_tracker_event; NULL for another value. */
MASSID_C_API const char* massid_tracker_event_name(int event);

#ifdef __cplusplus
} /* extern "C" */
#endif

#endif /* MASSID_H */
