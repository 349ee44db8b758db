/* The C interface (massid.h), compiled as C11.
 *
 * A pendulum written here (a sensor link carrying a mass, one revolute arm
 * about y) is simulated and identified by the CLI from noise-free data: at
 * rest with a sensor offset (static params) and along an exciting trajectory
 * with tilts (dynamic params). Its wrench is then computed by hand, Newton and
 * Euler for two rigid bodies, and compared with what massid_predict,
 * massid_predict_motion and massid_predict_motion_sensor return; the offset
 * with the one the data were simulated with. Then every error path, and (when
 * built with MASSID_TEST_COUNT_ALLOCATIONS, outside the sanitizers) that no
 * predict call allocates: malloc is interposed and counted.
 *
 * Usage: massid_c_api_tests MASSID_CLI WORK_DIR
 */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "c_test_support.h"
#include "massid.h"

/* |got - want| <= tol * max(1, max |want|) for each of the six components. */
static void check_wrench(const double got[6], const double want[6], double tol, const char* what,
                         int line) {
  double scale = 1.0;
  int k;
  for (k = 0; k < 6; ++k)
    if (fabs(want[k]) > scale) scale = fabs(want[k]);
  ++g_checks;
  for (k = 0; k < 6; ++k)
    if (!(fabs(got[k] - want[k]) <= tol * scale)) {
      ++g_failures;
      fprintf(stderr,
              "line %d: %s: component %d is %.17g, the hand computation %.17g (tolerance %g)\n",
              line, what, k, got[k], want[k], tol * scale);
      return;
    }
}

static int all_nan(const double w[6]) {
  int k;
  for (k = 0; k < 6; ++k)
    if (!isnan(w[k])) return 0;
  return 1;
}

/* ---------------------------------------------------------------- the pendulum by hand */

static const double kG0 = 9.80665;

/* The sensor link's inertial (sensor frame) and the arm's (arm frame), as in
 * the URDF below; the joint "swing" at kJoint, axis y, rotates the arm by q. */
static const double kSensorMass = 0.4;
static const double kSensorCom[3] = {0.01, -0.02, 0.03};
/* Inertia matrices about the centre of mass: 3x3, row-major. */
static const double kSensorInertia[9] = {0.002,   0.0001, 0.0,     0.0001, 0.003,
                                         -0.0002, 0.0,    -0.0002, 0.004};
static const double kJoint[3] = {0.05, 0.01, 0.2};
static const double kArmMass = 1.7;
static const double kArmCom[3] = {0.3, 0.04, -0.02};
static const double kArmInertia[9] = {0.004,  0.0003,  -0.0005, 0.0003, 0.06,
                                      0.0002, -0.0005, 0.0002,  0.058};
static const double kOffset[6] = {1.5, -2.0, 3.0, 0.1, -0.2, 0.3};

static const char* const kUrdf =
    "<?xml version=\"1.0\"?>\n"
    "<robot name=\"pendulum\">\n"
    "  <link name=\"sensor\">\n"
    "    <inertial><origin xyz=\"0.01 -0.02 0.03\" rpy=\"0 0 0\"/><mass value=\"0.4\"/>\n"
    "      <inertia ixx=\"0.002\" ixy=\"0.0001\" ixz=\"0\" iyy=\"0.003\" iyz=\"-0.0002\" "
    "izz=\"0.004\"/></inertial>\n"
    "  </link>\n"
    "  <joint name=\"swing\" type=\"revolute\">\n"
    "    <parent link=\"sensor\"/><child link=\"arm\"/>\n"
    "    <origin xyz=\"0.05 0.01 0.2\" rpy=\"0 0 0\"/><axis xyz=\"0 1 0\"/>\n"
    "    <limit lower=\"-2.5\" upper=\"2.5\" effort=\"50\" velocity=\"3\"/>\n"
    "  </joint>\n"
    "  <link name=\"arm\">\n"
    "    <inertial><origin xyz=\"0.3 0.04 -0.02\" rpy=\"0 0 0\"/><mass value=\"1.7\"/>\n"
    "      <inertia ixx=\"0.004\" ixy=\"0.0003\" ixz=\"-0.0005\" iyy=\"0.06\" iyz=\"0.0002\" "
    "izz=\"0.058\"/></inertial>\n"
    "  </link>\n"
    "</robot>\n";

static void cross(const double a[3], const double b[3], double out[3]) {
  const double x = a[1] * b[2] - a[2] * b[1], y = a[2] * b[0] - a[0] * b[2],
               z = a[0] * b[1] - a[1] * b[0];
  out[0] = x;
  out[1] = y;
  out[2] = z;
}

/* out = m v, m 3x3 row-major. */
static void mat_vec(const double* m, const double v[3], double out[3]) {
  int i;
  for (i = 0; i < 3; ++i) out[i] = m[3 * i] * v[0] + m[3 * i + 1] * v[1] + m[3 * i + 2] * v[2];
}

/* Adds the wrench one rigid body exerts on the sensor (sensor frame, moment
 * about its origin): F = m (g - a), M = c x F - (I dw + w x I w), with c its
 * centre of mass, a the acceleration of c, w and dw its angular velocity and
 * acceleration, I its inertia about c (all absolute, in sensor-frame axes). */
static void add_body(double m, const double c[3], const double* inertia, const double w[3],
                     const double dw[3], const double a[3], const double g[3], double out[6]) {
  double f[3], moment[3], iw[3], idw[3], gyro[3];
  int k;
  for (k = 0; k < 3; ++k) f[k] = m * (g[k] - a[k]);
  cross(c, f, moment);
  mat_vec(inertia, w, iw);
  mat_vec(inertia, dw, idw);
  cross(w, iw, gyro);
  for (k = 0; k < 3; ++k) {
    out[k] += f[k];
    out[3 + k] += moment[k] - idw[k] - gyro[k];
  }
}

/* The acceleration of a point at r from a frame origin whose acceleration is
 * a0, the frame turning at w, dw: a0 + dw x r + w x (w x r). */
static void point_accel(const double a0[3], const double w[3], const double dw[3],
                        const double r[3], double out[3]) {
  double t1[3], t2[3], t3[3];
  int k;
  cross(dw, r, t1);
  cross(w, r, t2);
  cross(w, t2, t3);
  for (k = 0; k < 3; ++k) out[k] = a0[k] + t1[k] + t3[k];
}

/* The pendulum's wrench on the sensor at swing angle q, rate qd, acceleration
 * qdd and gravity g (sensor frame), the sensor frame moving with angular
 * velocity ws, angular acceleration dws and origin acceleration as (NULL: at rest). */
static void pendulum_wrench(double q, double qd, double qdd, const double g[3],
                            const double* sensor_motion, double out[6]) {
  static const double zero[3] = {0.0, 0.0, 0.0};
  const double* ws = sensor_motion ? sensor_motion : zero;
  const double* dws = sensor_motion ? sensor_motion + 3 : zero;
  const double* as = sensor_motion ? sensor_motion + 6 : zero;
  const double c = cos(q), s = sin(q);
  /* R = Ry(q): the arm frame in the sensor frame. */
  const double R[9] = {c, 0.0, s, 0.0, 1.0, 0.0, -s, 0.0, c};
  double RI[9], Iw[9], r[3], com[3], w[3], dw[3], wrel[3], dwrel[3], t1[3], a[3], a_s[3], vrel[3],
      coriolis[3];
  int i, j, k;
  for (k = 0; k < 6; ++k) out[k] = 0.0;

  /* The sensor link: fixed in the sensor frame. */
  point_accel(as, ws, dws, kSensorCom, a_s);
  add_body(kSensorMass, kSensorCom, kSensorInertia, ws, dws, a_s, g, out);

  /* The arm: r = R c_arm from the joint, turning at qd about y relative to the sensor. */
  mat_vec(R, kArmCom, r);
  for (k = 0; k < 3; ++k) com[k] = kJoint[k] + r[k];
  for (i = 0; i < 3; ++i)
    for (j = 0; j < 3; ++j)
      RI[3 * i + j] = R[3 * i] * kArmInertia[j] + R[3 * i + 1] * kArmInertia[3 + j] +
                      R[3 * i + 2] * kArmInertia[6 + j];
  for (i = 0; i < 3; ++i)
    for (j = 0; j < 3; ++j)
      Iw[3 * i + j] =
          RI[3 * i] * R[3 * j] + RI[3 * i + 1] * R[3 * j + 1] + RI[3 * i + 2] * R[3 * j + 2];
  wrel[0] = 0.0, wrel[1] = qd, wrel[2] = 0.0;
  dwrel[0] = 0.0, dwrel[1] = qdd, dwrel[2] = 0.0;
  /* Absolute: w = ws + wrel, dw = dws + dwrel + ws x wrel;
   * a = (sensor frame point at com) + 2 ws x vrel + (relative acceleration). */
  cross(ws, wrel, t1);
  for (k = 0; k < 3; ++k) {
    w[k] = ws[k] + wrel[k];
    dw[k] = dws[k] + dwrel[k] + t1[k];
  }
  point_accel(as, ws, dws, com, a);
  {
    double arel[3];
    point_accel(zero, wrel, dwrel, r, arel);
    cross(wrel, r, vrel);
    cross(ws, vrel, coriolis);
    for (k = 0; k < 3; ++k) a[k] += arel[k] + 2.0 * coriolis[k];
  }
  add_body(kArmMass, com, Iw, w, dw, a, g, out);
}

/* ---------------------------------------------------------------- files and the CLI */

static char g_cli[1024];
static char g_dir[1024];

static void path_in(char* out, size_t size, const char* name) {
  snprintf(out, size, "%s/%s", g_dir, name);
}

static int write_text(const char* name, const char* text) {
  char path[1200];
  FILE* f;
  path_in(path, sizeof path, name);
  f = fopen(path, "w");
  if (!f) {
    fprintf(stderr, "cannot write %s\n", path);
    return 0;
  }
  fputs(text, f);
  fclose(f);
  return 1;
}

/* Runs the CLI with arguments (file names relative to the work directory). */
static int run_cli(const char* args) {
  char cmd[4096];
  int rc;
  snprintf(cmd, sizeof cmd, "cd '%s' && '%s' %s > /dev/null", g_dir, g_cli, args);
  rc = system(cmd);
  if (rc != 0) fprintf(stderr, "failed (%d): %s\n", rc, cmd);
  return rc == 0;
}

/* gravity of magnitude g0 tilted by ax about x, then ay about y, from level. */
static void tilted_gravity(double ax, double ay, double g[3]) {
  /* Ry(ay) Rx(ax) (0, 0, -g0) */
  const double gy = kG0 * sin(ax), gz0 = -kG0 * cos(ax);
  g[0] = gz0 * sin(ay);
  g[1] = gy;
  g[2] = gz0 * cos(ay);
}

/* A static plan: four angles at level and two tilts, noise-free data with
 * the offset kOffset, identified with offsets. */
static int make_static_params(void) {
  char plan[4096] = "swing,gx,gy,gz\n";
  static const double angles[] = {-1.9, -0.7, 0.4, 1.3, 2.2};
  static const double tilts[][2] = {{0.0, 0.0}, {0.5, 0.0}, {0.0, 0.5}, {-0.4, 0.3}};
  size_t i, j;
  for (i = 0; i < sizeof angles / sizeof angles[0]; ++i)
    for (j = 0; j < sizeof tilts / sizeof tilts[0]; ++j) {
      double g[3];
      char row[200];
      tilted_gravity(tilts[j][0], tilts[j][1], g);
      snprintf(row, sizeof row, "%.17g,%.17g,%.17g,%.17g\n", angles[i], g[0], g[1], g[2]);
      strcat(plan, row);
    }
  return write_text("plan.csv", plan) &&
         run_cli(
             "simulate pendulum.urdf plan.csv -o data.csv "
             "--offset 1.5,-2.0,3.0,0.1,-0.2,0.3") &&
         run_cli("identify pendulum.urdf data.csv --offset -o static.json");
}

/* An exciting trajectory with tilts, the noise-free wrench along it, its
 * dynamic parameters (no offset). */
static int make_dynamic_params(void) {
  return run_cli(
             "design pendulum.urdf --dynamic -o traj.csv --duration 8 --rate 200 "
             "--tilts 0:0,0:30,30:0 --seed 4") &&
         run_cli("simulate pendulum.urdf traj.csv -o log.csv --dynamic") &&
         run_cli("identify pendulum.urdf log.csv --dynamic -o dynamic.json");
}

/* The sensor's own motion at time t (a platform that turns and shakes):
 * wx wy wz, dwx dwy dwz (their derivatives), ax ay az. */
static void platform_motion(double t, double sm[9]) {
  sm[0] = 0.6 * sin(1.1 * t);
  sm[1] = 0.5 * cos(0.7 * t);
  sm[2] = 0.4 * sin(1.9 * t + 1.0);
  sm[3] = 0.66 * cos(1.1 * t);
  sm[4] = -0.35 * sin(0.7 * t);
  sm[5] = 0.76 * cos(1.9 * t + 1.0);
  sm[6] = 1.2 * sin(1.3 * t);
  sm[7] = 0.9 * cos(1.7 * t);
  sm[8] = 0.7 * sin(0.8 * t);
}

/* A log on a moving platform (the wx .. az columns), varying gravity, the
 * swing joint's rates given: dynamic parameters that see the sensor's motion. */
static int make_platform_params(void) {
  char path[1200];
  FILE* f;
  int i;
  path_in(path, sizeof path, "platform_traj.csv");
  f = fopen(path, "w");
  if (!f) return 0;
  fputs("t,swing,swing_vel,swing_acc,gx,gy,gz,wx,wy,wz,dwx,dwy,dwz,ax,ay,az\n", f);
  for (i = 0; i < 600; ++i) {
    const double t = 0.01 * i;
    const double q = 1.0 * sin(0.9 * t) + 0.5 * sin(2.3 * t + 0.4);
    const double qd = 0.9 * cos(0.9 * t) + 1.15 * cos(2.3 * t + 0.4);
    const double qdd = -0.81 * sin(0.9 * t) - 2.645 * sin(2.3 * t + 0.4);
    double g[3], sm[9];
    int k;
    tilted_gravity(0.3 * sin(0.5 * t), 0.3 * cos(0.4 * t), g);
    platform_motion(t, sm);
    fprintf(f, "%.17g,%.17g,%.17g,%.17g,%.17g,%.17g,%.17g", t, q, qd, qdd, g[0], g[1], g[2]);
    for (k = 0; k < 9; ++k) fprintf(f, ",%.17g", sm[k]);
    fputc('\n', f);
  }
  fclose(f);
  return run_cli("simulate pendulum.urdf platform_traj.csv -o platform_log.csv --dynamic") &&
         run_cli("identify pendulum.urdf platform_log.csv --dynamic -o platform.json");
}

static massid_predictor* load(const char* urdf, const char* params) {
  char u[1200], p[1200], error[2048];
  massid_predictor* h;
  path_in(u, sizeof u, urdf);
  path_in(p, sizeof p, params);
  h = massid_predictor_load(u, p, error, sizeof error);
  if (!h) fprintf(stderr, "massid_predictor_load(%s, %s): %s\n", u, p, error);
  return h;
}

/* ---------------------------------------------------------------- tests */

static void test_codes_and_version(void) {
  static const int codes[] = {MASSID_OK,
                              MASSID_ERROR_INVALID_ARGUMENT,
                              MASSID_ERROR_FILE,
                              MASSID_ERROR_MODEL_MISMATCH,
                              MASSID_ERROR_STATIC_PARAMS,
                              MASSID_ERROR_NOT_FINITE,
                              MASSID_ERROR_INTERNAL,
                              MASSID_ERROR_SENSOR_MOTION};
  const size_t n = sizeof codes / sizeof codes[0];
  size_t i, j;
  char version[64];
  CHECK(strcmp(massid_version(), MASSID_VERSION_STRING) == 0);
  snprintf(version, sizeof version, "%d.%d.%d", MASSID_VERSION_MAJOR, MASSID_VERSION_MINOR,
           MASSID_VERSION_PATCH);
  CHECK(strcmp(massid_version(), version) == 0);
  for (i = 0; i < n; ++i) {
    CHECK(i == 0 || codes[i] < 0);
    CHECK(strlen(massid_error_string(codes[i])) > 0);
    CHECK(strcmp(massid_error_string(codes[i]), "unknown massid status code") != 0);
    for (j = 0; j < i; ++j)
      CHECK(strcmp(massid_error_string(codes[i]), massid_error_string(codes[j])) != 0);
  }
  CHECK(strcmp(massid_error_string(-100), "unknown massid status code") == 0);
  CHECK(strcmp(massid_error_string(7), "unknown massid status code") == 0);
}

static void test_static(massid_predictor* p) {
  static const double qs[] = {-2.1, -0.3, 0.0, 0.8, 1.7};
  static const double tilts[][2] = {{0.0, 0.0}, {0.7, -0.2}, {-0.3, 1.1}, {2.5, 0.4}};
  double offset[6] = {9, 9, 9, 9, 9, 9}, w[6], want[6];
  size_t i, j;
  int k;
  CHECK(massid_predictor_num_joints(p) == 1);
  CHECK(massid_predictor_joint_name(p, 0) &&
        strcmp(massid_predictor_joint_name(p, 0), "swing") == 0);
  CHECK(massid_predictor_joint_name(p, 1) == NULL);
  CHECK(massid_predictor_joint_name(p, -1) == NULL);
  CHECK(massid_predictor_sensor_link(p) && strcmp(massid_predictor_sensor_link(p), "sensor") == 0);
  CHECK(massid_predictor_is_dynamic(p) == 0);
  CHECK(massid_predictor_has_offset(p) == 1);
  CHECK_CODE(massid_predictor_offset(p, offset), MASSID_OK);
  for (k = 0; k < 6; ++k) CHECK(fabs(offset[k] - kOffset[k]) < 1e-9);

  /* Gravity directions the plan never had (one upside down), and angles it never had. */
  for (i = 0; i < sizeof qs / sizeof qs[0]; ++i)
    for (j = 0; j < sizeof tilts / sizeof tilts[0]; ++j) {
      double g[3];
      tilted_gravity(tilts[j][0], tilts[j][1], g);
      CHECK_CODE(massid_predict(p, &qs[i], g, w), MASSID_OK);
      pendulum_wrench(qs[i], 0.0, 0.0, g, NULL, want);
      check_wrench(w, want, 1e-9, "static massid_predict", __LINE__);
    }

  /* Static parameters hold no inertia. */
  {
    const double q = 0.2, qd = 0.5, qdd = -1.0, g[3] = {0.0, 0.0, -kG0};
    CHECK_CODE(massid_predict_motion(p, &q, &qd, &qdd, g, w), MASSID_ERROR_STATIC_PARAMS);
    CHECK(all_nan(w));
    CHECK_CODE(massid_predict_motion_sensor(p, &q, &qd, &qdd, g, NULL, w),
               MASSID_ERROR_STATIC_PARAMS);
  }
}

static void test_dynamic(massid_predictor* p) {
  double offset[6] = {9, 9, 9, 9, 9, 9}, w[6], want[6];
  int i, k;
  CHECK(massid_predictor_num_joints(p) == 1);
  CHECK(massid_predictor_is_dynamic(p) == 1);
  CHECK(massid_predictor_has_offset(p) == 0);
  CHECK_CODE(massid_predictor_offset(p, offset), MASSID_OK);
  for (k = 0; k < 6; ++k) CHECK(offset[k] == 0.0);

  for (i = 0; i < 12; ++i) {
    const double q = -2.0 + 0.37 * i, qd = 2.5 * sin(1.3 * i), qdd = 9.0 * cos(0.7 * i + 0.2);
    double g[3];
    tilted_gravity(0.25 * sin(i), 0.3 * cos(2.0 * i), g);
    CHECK_CODE(massid_predict_motion(p, &q, &qd, &qdd, g, w), MASSID_OK);
    pendulum_wrench(q, qd, qdd, g, NULL, want);
    check_wrench(w, want, 1e-8, "massid_predict_motion", __LINE__);

    /* At rest: massid_predict is predict_motion at zero rates. */
    CHECK_CODE(massid_predict(p, &q, g, w), MASSID_OK);
    pendulum_wrench(q, 0.0, 0.0, g, NULL, want);
    check_wrench(w, want, 1e-8, "dynamic massid_predict", __LINE__);

    /* Identified with the sensor at rest: a moving sensor frame is refused,
     * one at rest (NULL or zeros) is not. */
    {
      const double sm[9] = {0.3 * sin(i), -0.5, 0.2 * cos(i), 1.5, 0, 0, 0, 0, 0};
      const double still[9] = {0, 0, 0, 0, 0, 0, 0, 0, 0};
      CHECK_CODE(massid_predict_motion_sensor(p, &q, &qd, &qdd, g, sm, w),
                 MASSID_ERROR_SENSOR_MOTION);
      CHECK(all_nan(w));
      CHECK_CODE(massid_predict_motion_sensor(p, &q, &qd, &qdd, g, still, w), MASSID_OK);
      pendulum_wrench(q, qd, qdd, g, NULL, want);
      check_wrench(w, want, 1e-8, "massid_predict_motion_sensor at rest", __LINE__);
      CHECK_CODE(massid_predict_motion_sensor(p, &q, &qd, &qdd, g, NULL, w), MASSID_OK);
      check_wrench(w, want, 1e-8, "massid_predict_motion_sensor, NULL motion", __LINE__);
    }
  }
}

/* Parameters identified on a moving platform predict it moving. */
static void test_platform(massid_predictor* p) {
  double w[6], want[6], sm[9];
  int i;
  CHECK(massid_predictor_is_dynamic(p) == 1);
  for (i = 0; i < 12; ++i) {
    const double q = 2.0 - 0.31 * i, qd = -2.0 * cos(0.9 * i), qdd = 7.0 * sin(1.7 * i + 0.3);
    double g[3];
    tilted_gravity(0.2 * cos(i), -0.25 * sin(3.0 * i), g);
    platform_motion(0.77 * i + 0.1, sm);
    CHECK_CODE(massid_predict_motion_sensor(p, &q, &qd, &qdd, g, sm, w), MASSID_OK);
    pendulum_wrench(q, qd, qdd, g, sm, want);
    check_wrench(w, want, 1e-8, "massid_predict_motion_sensor on a platform", __LINE__);
    CHECK_CODE(massid_predict_motion(p, &q, &qd, &qdd, g, w), MASSID_OK);
    pendulum_wrench(q, qd, qdd, g, NULL, want);
    check_wrench(w, want, 1e-8, "massid_predict_motion, platform params", __LINE__);
  }
}

/* A clone predicts the same bits with its own workspace, and outlives the original. */
static void test_clone(const char* params) {
  massid_predictor* p = load("pendulum.urdf", params);
  massid_predictor* c = massid_predictor_clone(p);
  const double q = 0.9, qd = -1.2, qdd = 3.0, g[3] = {1.0, -2.0, -9.5};
  double a[6], b[6];
  CHECK(c != NULL && c != p);
  CHECK(massid_predictor_clone(NULL) == NULL);
  CHECK_CODE(massid_predict(p, &q, g, a), MASSID_OK);
  massid_predictor_free(p);
  CHECK_CODE(massid_predict(c, &q, g, b), MASSID_OK);
  CHECK(memcmp(a, b, sizeof a) == 0);
  if (massid_predictor_is_dynamic(c) == 1) {
    CHECK_CODE(massid_predict_motion(c, &q, &qd, &qdd, g, b), MASSID_OK);
    CHECK(!all_nan(b));
  }
  CHECK(strcmp(massid_predictor_joint_name(c, 0), "swing") == 0);
  massid_predictor_free(c);
}

/* Opening urdf with params (files in the work directory) fails with code, the
 * handle NULL, the message containing needle. */
static void check_open_fails(const char* urdf, const char* params, int code, const char* needle,
                             int line) {
  char error[2048], u[1200], p[1200];
  massid_predictor* h = NULL;
  int got;
  path_in(u, sizeof u, urdf);
  path_in(p, sizeof p, params);
  got = massid_predictor_open(u, p, &h, error, sizeof error);
  ++g_checks;
  if (got != code || h != NULL || !strstr(error, needle)) {
    ++g_failures;
    fprintf(stderr,
            "line %d: opening %s with %s gave %d (%s), expected %d and a message with '%s'\n", line,
            urdf, params, got, error, code, needle);
  }
  massid_predictor_free(h);
}

static void test_load_errors(void) {
  char error[2048], urdf[1200], params[1200], missing[1200];
  static int not_a_handle;
  massid_predictor* p = (massid_predictor*)(void*)&not_a_handle; /* open sets it to NULL */
  path_in(urdf, sizeof urdf, "pendulum.urdf");
  path_in(params, sizeof params, "static.json");

  /* Missing files: NULL, the message names the file. */
  path_in(missing, sizeof missing, "no_such_robot.urdf");
  CHECK(massid_predictor_load(missing, params, error, sizeof error) == NULL);
  CHECK(strstr(error, missing) != NULL);
  CHECK_CODE(massid_predictor_open(missing, params, &p, error, sizeof error), MASSID_ERROR_FILE);
  CHECK(p == NULL);
  path_in(missing, sizeof missing, "no_such_params.json");
  CHECK(massid_predictor_load(urdf, missing, error, sizeof error) == NULL);
  CHECK(strstr(error, missing) != NULL);

  /* A malformed params file (file, line and column), a malformed URDF. */
  CHECK(write_text("broken.json", "{\n  \"format\": \"massid-params-1\",\n  \"joints\": [,]\n}\n"));
  check_open_fails("pendulum.urdf", "broken.json", MASSID_ERROR_FILE, "broken.json:3:14", __LINE__);
  CHECK(write_text("broken.urdf", "<robot name=\"x\"><link name=\"sensor\">\n</robot>\n"));
  check_open_fails("broken.urdf", "static.json", MASSID_ERROR_FILE, "broken.urdf", __LINE__);

  /* Another robot: no link "sensor", or no joint "swing". */
  CHECK(write_text("other.urdf",
                   "<robot name=\"other\"><link name=\"base\"/>\n"
                   "<joint name=\"j\" type=\"revolute\"><parent link=\"base\"/><child link=\"l\"/>"
                   "<axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" "
                   "velocity=\"1\"/></joint>\n"
                   "<link name=\"l\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" ixy=\"0\" "
                   "ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link></robot>\n"));
  check_open_fails("other.urdf", "static.json", MASSID_ERROR_MODEL_MISMATCH, "sensor", __LINE__);
  CHECK(write_text("renamed.urdf",
                   "<robot name=\"renamed\"><link name=\"sensor\"/>\n"
                   "<joint name=\"hinge\" type=\"revolute\"><parent link=\"sensor\"/>"
                   "<child link=\"arm\"/><axis xyz=\"0 1 0\"/><limit lower=\"-1\" upper=\"1\" "
                   "effort=\"1\" velocity=\"1\"/></joint>\n"
                   "<link name=\"arm\"/></robot>\n"));
  check_open_fails("renamed.urdf", "static.json", MASSID_ERROR_MODEL_MISMATCH, "renamed.urdf",
                   __LINE__);

  /* The message is truncated to the buffer and always NUL-terminated. */
  path_in(missing, sizeof missing, "no_such_robot.urdf");
  memset(error, 'x', sizeof error);
  CHECK(massid_predictor_load(missing, params, error, 8) == NULL);
  CHECK(strlen(error) == 7 && strncmp(error, missing, 7) == 0);
  CHECK(error[8] == 'x'); /* nothing written past the buffer */
  memset(error, 'x', sizeof error);
  CHECK(massid_predictor_load(missing, params, error, 1) == NULL);
  CHECK(error[0] == '\0' && error[1] == 'x');
  CHECK(massid_predictor_load(missing, params, error, 0) == NULL);
  CHECK(error[0] == '\0' && error[1] == 'x'); /* untouched */
  CHECK(massid_predictor_load(missing, params, NULL, 100) == NULL);

  /* NULL arguments. */
  CHECK(massid_predictor_load(NULL, params, error, sizeof error) == NULL);
  CHECK(strstr(error, "urdf_path") != NULL);
  CHECK(massid_predictor_load(urdf, NULL, error, sizeof error) == NULL);
  CHECK(strstr(error, "params_path") != NULL);
  CHECK_CODE(massid_predictor_open(urdf, params, NULL, error, sizeof error),
             MASSID_ERROR_INVALID_ARGUMENT);

  /* Success clears the message. */
  strcpy(error, "stale");
  p = massid_predictor_load(urdf, params, error, sizeof error);
  CHECK(p != NULL && error[0] == '\0');
  massid_predictor_free(p);
}

static void test_call_errors(massid_predictor* p) {
  const double q = 0.3, qd = 0.1, qdd = 0.2, g[3] = {0.0, 0.0, -kG0};
  const double bad_q = NAN, bad_g[3] = {0.0, INFINITY, -kG0};
  const double bad_motion[9] = {0, 0, 0, 0, NAN, 0, 0, 0, 0};
  double w[6], offset[6];
  CHECK_CODE(massid_predictor_num_joints(NULL), MASSID_ERROR_INVALID_ARGUMENT);
  CHECK(massid_predictor_joint_name(NULL, 0) == NULL);
  CHECK(massid_predictor_sensor_link(NULL) == NULL);
  CHECK_CODE(massid_predictor_is_dynamic(NULL), MASSID_ERROR_INVALID_ARGUMENT);
  CHECK_CODE(massid_predictor_has_offset(NULL), MASSID_ERROR_INVALID_ARGUMENT);
  CHECK_CODE(massid_predictor_offset(NULL, offset), MASSID_ERROR_INVALID_ARGUMENT);
  CHECK_CODE(massid_predictor_offset(p, NULL), MASSID_ERROR_INVALID_ARGUMENT);
  massid_predictor_free(NULL);

  CHECK_CODE(massid_predict(NULL, &q, g, w), MASSID_ERROR_INVALID_ARGUMENT);
  CHECK(all_nan(w));
  CHECK_CODE(massid_predict(p, NULL, g, w), MASSID_ERROR_INVALID_ARGUMENT);
  CHECK(all_nan(w));
  CHECK_CODE(massid_predict(p, &q, NULL, w), MASSID_ERROR_INVALID_ARGUMENT);
  CHECK_CODE(massid_predict(p, &q, g, NULL), MASSID_ERROR_INVALID_ARGUMENT);
  CHECK_CODE(massid_predict(p, &bad_q, g, w), MASSID_ERROR_NOT_FINITE);
  CHECK(all_nan(w));
  CHECK_CODE(massid_predict(p, &q, bad_g, w), MASSID_ERROR_NOT_FINITE);

  CHECK_CODE(massid_predict_motion(NULL, &q, &qd, &qdd, g, w), MASSID_ERROR_INVALID_ARGUMENT);
  CHECK_CODE(massid_predict_motion(p, &q, NULL, &qdd, g, w), MASSID_ERROR_INVALID_ARGUMENT);
  CHECK_CODE(massid_predict_motion(p, &q, &qd, NULL, g, w), MASSID_ERROR_INVALID_ARGUMENT);
  CHECK(all_nan(w));
  CHECK_CODE(massid_predict_motion(p, &q, &qd, &qdd, g, NULL), MASSID_ERROR_INVALID_ARGUMENT);
  CHECK_CODE(massid_predict_motion(p, &q, &bad_q, &qdd, g, w), MASSID_ERROR_NOT_FINITE);
  CHECK_CODE(massid_predict_motion_sensor(p, &q, &qd, &qdd, g, bad_motion, w),
             MASSID_ERROR_NOT_FINITE);
  CHECK(all_nan(w));
  /* The handle still works after the errors. */
  CHECK_CODE(massid_predict_motion(p, &q, &qd, &qdd, g, w), MASSID_OK);
  CHECK(!all_nan(w));
}

/* Predicting and the queries allocate nothing; loading does (the counter sees it). */
static void test_no_allocation(massid_predictor* rest, massid_predictor* moving,
                               massid_predictor* platform) {
#if defined(MASSID_TEST_COUNT_ALLOCATIONS)
  const double qd = 0.4, qdd = -2.0, g[3] = {0.3, -0.2, -9.7};
  const double sm[9] = {0.1, 0.2, 0.3, 0.4, 0.5, 0.6, 0.7, 0.8, 0.9};
  double w[6], offset[6], sum = 0.0;
  long before;
  int i;
  massid_predictor* c;
  before = g_allocations;
  c = massid_predictor_clone(rest);
  CHECK(g_allocations > before); /* the counter works */
  massid_predictor_free(c);

  before = g_allocations;
  for (i = 0; i < 100; ++i) {
    const double q = -2.0 + 0.04 * i;
    CHECK_CODE(massid_predict(rest, &q, g, w), MASSID_OK);
    sum += w[3];
    CHECK_CODE(massid_predict(moving, &q, g, w), MASSID_OK);
    sum += w[3];
    CHECK_CODE(massid_predict_motion(moving, &q, &qd, &qdd, g, w), MASSID_OK);
    sum += w[4];
    CHECK_CODE(massid_predict_motion_sensor(platform, &q, &qd, &qdd, g, sm, w), MASSID_OK);
    sum += w[5];
    CHECK_CODE(massid_predict_motion(rest, &q, &qd, &qdd, g, w), MASSID_ERROR_STATIC_PARAMS);
    CHECK_CODE(massid_predictor_offset(rest, offset), MASSID_OK);
    CHECK(massid_predictor_joint_name(moving, 0) != NULL);
    CHECK(massid_predictor_num_joints(rest) == 1);
  }
  CHECK(g_allocations == before);
  if (g_allocations != before)
    fprintf(stderr, "%ld allocations in 100 rounds of predict calls\n", g_allocations - before);
  CHECK(isfinite(sum));
#else
  (void)rest;
  (void)moving;
  (void)platform;
  fprintf(stderr, "allocation counting off (sanitizer build)\n");
#endif
}

/* A mechanism without joints (a tool on a wrist sensor): q may be NULL. */
static void test_no_joints(void) {
  static const char* const urdf =
      "<robot name=\"tool\"><link name=\"sensor\"><inertial><origin xyz=\"0.02 -0.01 0.07\"/>"
      "<mass value=\"0.8\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" "
      "izz=\"1\"/></inertial></link></robot>\n";
  char plan[2048] = "gx,gy,gz\n";
  double w[6], want[6];
  const double g[3] = {1.0, -3.0, -9.0}, c[3] = {0.02, -0.01, 0.07};
  massid_predictor* p;
  int k;
  for (k = 0; k < 12; ++k) { /* 12 wrist orientations */
    double gk[3];
    char row[100];
    tilted_gravity(0.5 * k, 1.1 * k, gk);
    snprintf(row, sizeof row, "%.17g,%.17g,%.17g\n", gk[0], gk[1], gk[2]);
    strcat(plan, row);
  }
  CHECK(write_text("tool.urdf", urdf) && write_text("tool_plan.csv", plan));
  CHECK(run_cli("simulate tool.urdf tool_plan.csv -o tool_data.csv"));
  CHECK(run_cli("identify tool.urdf tool_data.csv -o tool.json"));
  p = load("tool.urdf", "tool.json");
  CHECK(p != NULL);
  if (!p) return;
  CHECK(massid_predictor_num_joints(p) == 0);
  CHECK(massid_predictor_joint_name(p, 0) == NULL);
  CHECK_CODE(massid_predict(p, NULL, g, w), MASSID_OK);
  for (k = 0; k < 3; ++k) want[k] = 0.8 * g[k];
  cross(c, want, want + 3);
  check_wrench(w, want, 1e-9, "no joints", __LINE__);
  massid_predictor_free(p);
}

/* The pendulum identified with its joint held still (identify --fixed): the
 * params file holds it, so it is no input; the wrench is the pendulum's there. */
static void test_held_joint(void) {
  char plan[4096] = "swing,gx,gy,gz\n";
  double w[6], want[6];
  const double g[3] = {2.0, 1.0, -9.4};
  massid_predictor* p;
  int k;
  for (k = 0; k < 12; ++k) {
    double gk[3];
    char row[120];
    tilted_gravity(0.5 * k, 1.1 * k, gk);
    snprintf(row, sizeof row, "0.3,%.17g,%.17g,%.17g\n", gk[0], gk[1], gk[2]);
    strcat(plan, row);
  }
  CHECK(write_text("held_plan.csv", plan));
  CHECK(run_cli("simulate pendulum.urdf held_plan.csv -o held_data.csv"));
  CHECK(run_cli("identify pendulum.urdf held_data.csv --fixed swing=0.3 -o held.json"));
  p = load("pendulum.urdf", "held.json");
  CHECK(p != NULL);
  if (!p) return;
  CHECK(massid_predictor_num_joints(p) == 0);
  CHECK_CODE(massid_predict(p, NULL, g, w), MASSID_OK);
  pendulum_wrench(0.3, 0.0, 0.0, g, NULL, want);
  check_wrench(w, want, 1e-9, "joint held by the params file", __LINE__);
  massid_predictor_free(p);
}

/* The sensor on the arm (identify --sensor arm): the swing joint is above it;
 * gravity in the sensor frame follows from it and the root gravity. */
static void test_upstream(void) {
  char plan[4096] = "swing\n";
  double w[6], f[3];
  const double root_gravity[3] = {0.4, -0.3, -9.7};
  massid_predictor* p;
  int k;
  for (k = 0; k < 12; ++k) {
    char row[64];
    snprintf(row, sizeof row, "%.17g\n", -2.4 + 0.41 * k);
    strcat(plan, row);
  }
  CHECK(write_text("wrist_plan.csv", plan));
  CHECK(run_cli("simulate pendulum.urdf wrist_plan.csv --sensor arm -o wrist_data.csv"));
  CHECK(run_cli("identify pendulum.urdf wrist_data.csv --sensor arm -o wrist.json"));
  p = load("pendulum.urdf", "wrist.json");
  CHECK(p != NULL);
  if (!p) return;
  CHECK(massid_predictor_num_joints(p) == 0);
  CHECK(massid_predictor_num_upstream_joints(p) == 1);
  CHECK(strcmp(massid_predictor_upstream_joint_name(p, 0), "swing") == 0);
  CHECK(massid_predictor_upstream_joint_name(p, 1) == NULL);
  CHECK(massid_predictor_num_upstream_joints(NULL) == MASSID_ERROR_INVALID_ARGUMENT);
  for (k = 0; k < 5; ++k) {
    /* By hand: gravity in the arm frame is Ry(qu)^T g_root; F = m g_arm, M = c x F. */
    const double qu = -1.5 + 0.7 * k, c = cos(qu), s = sin(qu);
    const double g_arm[3] = {c * root_gravity[0] - s * root_gravity[2], root_gravity[1],
                             s * root_gravity[0] + c * root_gravity[2]};
    double want[6];
    int i;
    for (i = 0; i < 3; ++i) f[i] = kArmMass * g_arm[i];
    for (i = 0; i < 3; ++i) want[i] = f[i];
    cross(kArmCom, f, want + 3);
    CHECK_CODE(massid_predict_upstream(p, &qu, root_gravity, NULL, w), MASSID_OK);
    check_wrench(w, want, 1e-9, "massid_predict_upstream", __LINE__);
    CHECK_CODE(massid_predict(p, NULL, g_arm, want), MASSID_OK);
    check_wrench(w, want, 1e-12, "massid_predict_upstream against massid_predict", __LINE__);
  }
  {
    const long before = g_allocations;
    const double qu = 0.3, zero = 0.0;
    CHECK_CODE(massid_predict_upstream(p, &qu, root_gravity, NULL, w), MASSID_OK);
    CHECK_CODE(
        massid_predict_motion_upstream(p, &qu, &zero, &zero, root_gravity, NULL, NULL, NULL, w),
        MASSID_ERROR_STATIC_PARAMS);
    CHECK(g_allocations == before); /* 0 == 0 without MASSID_TEST_COUNT_ALLOCATIONS */
  }
  CHECK_CODE(massid_predict_upstream(p, NULL, root_gravity, NULL, w),
             MASSID_ERROR_INVALID_ARGUMENT);
  CHECK(all_nan(w));
  CHECK_CODE(massid_predict_upstream(p, &kG0, NULL, NULL, w), MASSID_ERROR_INVALID_ARGUMENT);
  massid_predictor_free(p);
}

int main(int argc, char** argv) {
  massid_predictor *rest, *moving, *platform;
  if (argc != 3) {
    fprintf(stderr, "usage: %s MASSID_CLI WORK_DIR\n", argv[0]);
    return 2;
  }
  snprintf(g_cli, sizeof g_cli, "%s", argv[1]);
  snprintf(g_dir, sizeof g_dir, "%s", argv[2]);
  mkdir(g_dir, 0755);
  if (!write_text("pendulum.urdf", kUrdf) || !make_static_params() || !make_dynamic_params() ||
      !make_platform_params()) {
    fprintf(stderr, "could not make the test files with %s in %s\n", g_cli, g_dir);
    return 1;
  }

  test_codes_and_version();
  rest = load("pendulum.urdf", "static.json");
  moving = load("pendulum.urdf", "dynamic.json");
  platform = load("pendulum.urdf", "platform.json");
  CHECK(rest != NULL && moving != NULL && platform != NULL);
  if (rest && moving && platform) {
    test_static(rest);
    test_dynamic(moving);
    test_platform(platform);
    test_clone("static.json");
    test_clone("dynamic.json");
    test_call_errors(moving);
    test_no_allocation(rest, moving, platform);
  }
  test_load_errors();
  test_no_joints();
  test_held_joint();
  test_upstream();
  massid_predictor_free(rest);
  massid_predictor_free(moving);
  massid_predictor_free(platform);

  printf("%d checks, %d failed\n", g_checks, g_failures);
  return g_failures == 0 ? 0 : 1;
}
