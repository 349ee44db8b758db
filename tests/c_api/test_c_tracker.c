/* The C interface's tracker (massid_tracker_*, massid.h), compiled as C11.
 *
 * The tracked logs of tests/tracker_support.hpp (massid_tracker_fixture: the
 * UR-like arm with a tool, an object grasped and put down, drifting offsets,
 * a contact), on a wrist sensor and on a base sensor, go through
 * `massid compensate --track` on stdin, the reference; their rows then go
 * through massid_tracker_update_upstream (wrist) and massid_tracker_update
 * (base), and every column the CLI wrote, fx_comp .. mz_comp and payload_m ..
 * event, must be the same double, bit for bit (parsed back from the CLI's
 * shortest round-trip text). Then the error paths (a wrong payload link names
 * the measured links) and, with MASSID_TEST_COUNT_ALLOCATIONS, that updating
 * does not allocate.
 *
 * Usage: massid_c_tracker_tests MASSID_CLI MASSID_TRACKER_FIXTURE URDF WORK_DIR
 */
#define _POSIX_C_SOURCE 200809L

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

#include "c_test_support.h"
#include "massid.h"

static char g_cli[1024], g_fixture[1024], g_urdf[1024], g_dir[1024];

static int tracker_run(const char* what, const char* cmd) {
  const int rc = system(cmd);
  if (rc != 0) fprintf(stderr, "%s failed (%d): %s\n", what, rc, cmd);
  return rc == 0;
}

/* The fixture's logs, their params (identify --dynamic on the free log) and
 * the CLI's tracked output NAME_out.csv, for NAME wrist and base. */
static int tracker_make_files(void) {
  char cmd[8192];
  const char* names[2] = {"wrist", "base"};
  const char* sensor[2] = {"--sensor wrist_3_link", ""};
  int k;
  snprintf(cmd, sizeof cmd, "'%s' '%s'", g_fixture, g_dir);
  if (!tracker_run("the fixture", cmd)) return 0;
  for (k = 0; k < 2; ++k) {
    snprintf(cmd, sizeof cmd,
             "cd '%s' && '%s' identify '%s' %s_free.csv --dynamic %s -o %s.json > /dev/null", g_dir,
             g_cli, g_urdf, names[k], sensor[k], names[k]);
    if (!tracker_run("identify", cmd)) return 0;
    snprintf(cmd, sizeof cmd,
             "cd '%s' && '%s' compensate '%s' %s.json --track < %s_tracked.csv > %s_out.csv "
             "2> %s_err.txt",
             g_dir, g_cli, g_urdf, names[k], names[k], names[k], names[k]);
    if (!tracker_run("compensate --track", cmd)) return 0;
  }
  return 1;
}

/* ---------------------------------------------------------------- CSV */

enum { kTrackerMaxFields = 128, kTrackerLine = 16384 };

/* Splits line (its '\n' dropped) at commas in place, empty fields kept. */
static int tracker_split(char* line, char** fields) {
  int n = 0;
  char* p = line;
  line[strcspn(line, "\r\n")] = '\0';
  fields[n++] = p;
  for (; *p; ++p)
    if (*p == ',' && n < kTrackerMaxFields) {
      *p = '\0';
      fields[n++] = p + 1;
    }
  return n;
}

static int tracker_column(char** header, int n, const char* name) {
  int i;
  for (i = 0; i < n; ++i)
    if (strcmp(header[i], name) == 0) return i;
  return -1;
}

/* The same double, bit for bit. */
static int tracker_same(double a, double b) { return memcmp(&a, &b, sizeof a) == 0; }

/* ---------------------------------------------------------------- the logs */

static const char* const kTrackerColumns[] = {
    "payload_m",   "payload_cx",  "payload_cy",  "payload_cz",  "payload_m_std", "payload_c_std",
    "payload_ixx", "payload_ixy", "payload_ixz", "payload_iyy", "payload_iyz",   "payload_izz",
    "offset_fx",   "offset_fy",   "offset_fz",   "offset_mx",   "offset_my",     "offset_mz"};
static const char* const kTrackerWrench[] = {"fx", "fy", "fz", "mx", "my", "mz"};

/* The estimate's value of a tracker column (kTrackerColumns' order). */
static double tracker_value(const massid_tracker_estimate* e, int k) {
  if (k == 0) return e->payload_m;
  if (k <= 3) return e->payload_c[k - 1];
  if (k == 4) return e->payload_m_std;
  if (k == 5) return e->payload_c_std;
  if (k <= 11) return e->payload_inertia[k - 6];
  return e->offset[k - 12];
}

/* NAME_tracked.csv's rows through the C tracker against NAME_out.csv, the
 * CLI's; wrist: the arm's joints above the sensor. */
static void test_tracker_log(const char* name, int wrist) {
  char path[1200], params[1200], error[512];
  static char in_line[kTrackerLine], out_line[kTrackerLine];
  char *in_f[kTrackerMaxFields], *out_f[kTrackerMaxFields];
  int joint[6], vel[6], acc[6], wrench[6], comp[6], tracked[18], gravity[3];
  int n_in, n_out, i, k, event, time_col, nj, rows = 0, differ = 0, changes = 0, contacts = 0;
  long allocations = 0;
  FILE *in, *out;
  massid_predictor* p;
  massid_tracker* tr = NULL;
  const char* names[6] = {NULL};
  const double root_gravity[3] = {0.0, 0.0, -9.80665};

  snprintf(params, sizeof params, "%s/%s.json", g_dir, name);
  p = massid_predictor_load(g_urdf, params, error, sizeof error);
  CHECK(p != NULL);
  if (!p) {
    fprintf(stderr, "%s\n", error);
    return;
  }
  CHECK_CODE(massid_tracker_create(p, NULL, NULL, &tr, error, sizeof error), MASSID_OK);
  /* The joints: the arm's six, above the sensor (wrist) or below it. */
  nj = wrist ? massid_predictor_num_upstream_joints(p) : massid_predictor_num_joints(p);
  CHECK(nj == 6);
  for (i = 0; i < 6 && i < nj; ++i)
    names[i] =
        wrist ? massid_predictor_upstream_joint_name(p, i) : massid_predictor_joint_name(p, i);
  if (!tr || nj != 6) {
    massid_predictor_free(p);
    massid_tracker_free(tr);
    return;
  }
  CHECK(strcmp(massid_tracker_payload_link(tr), "tool") == 0);

  snprintf(path, sizeof path, "%s/%s_tracked.csv", g_dir, name);
  in = fopen(path, "r");
  snprintf(path, sizeof path, "%s/%s_out.csv", g_dir, name);
  out = fopen(path, "r");
  CHECK(in != NULL && out != NULL);
  if (!in || !out || !fgets(in_line, sizeof in_line, in) || !fgets(out_line, sizeof out_line, out))
    goto done;
  n_in = tracker_split(in_line, in_f);
  n_out = tracker_split(out_line, out_f);
  for (i = 0; i < nj; ++i) {
    char col[256];
    joint[i] = tracker_column(in_f, n_in, names[i]);
    snprintf(col, sizeof col, "%s_vel", names[i]);
    vel[i] = tracker_column(in_f, n_in, col);
    snprintf(col, sizeof col, "%s_acc", names[i]);
    acc[i] = tracker_column(in_f, n_in, col);
    CHECK(joint[i] > 0 && vel[i] > 0 && acc[i] > 0);
  }
  for (k = 0; k < 6; ++k) {
    char col[16];
    wrench[k] = tracker_column(in_f, n_in, kTrackerWrench[k]);
    snprintf(col, sizeof col, "%s_comp", kTrackerWrench[k]);
    comp[k] = tracker_column(out_f, n_out, col);
    CHECK(wrench[k] > 0 && comp[k] > 0);
  }
  for (k = 0; k < 18; ++k) {
    tracked[k] = tracker_column(out_f, n_out, kTrackerColumns[k]);
    CHECK(tracked[k] > 0);
  }
  event = tracker_column(out_f, n_out, "event");
  time_col = tracker_column(in_f, n_in, "t");
  gravity[0] = tracker_column(in_f, n_in, "gx");
  gravity[1] = tracker_column(in_f, n_in, "gy");
  gravity[2] = tracker_column(in_f, n_in, "gz");
  CHECK(event > 0 && time_col == 0 && (wrist || gravity[2] > 0));

  while (fgets(in_line, sizeof in_line, in)) {
    double t, q[6], qd[6], qdd[6], w[6], g[3];
    massid_tracker_estimate e;
    long before;
    int code;
    if (!fgets(out_line, sizeof out_line, out)) {
      CHECK(0); /* the CLI wrote fewer rows */
      break;
    }
    n_in = tracker_split(in_line, in_f);
    n_out = tracker_split(out_line, out_f);
    t = strtod(in_f[time_col], NULL);
    for (i = 0; i < nj; ++i) {
      q[i] = strtod(in_f[joint[i]], NULL);
      qd[i] = strtod(in_f[vel[i]], NULL);
      qdd[i] = strtod(in_f[acc[i]], NULL);
    }
    for (k = 0; k < 6; ++k) w[k] = strtod(in_f[wrench[k]], NULL);
    if (!wrist)
      for (k = 0; k < 3; ++k) g[k] = strtod(in_f[gravity[k]], NULL);
    before = g_allocations;
    code = wrist ? massid_tracker_update_upstream(tr, t, q, qd, qdd, root_gravity, NULL, NULL, NULL,
                                                  w, &e)
                 : massid_tracker_update(tr, t, q, qd, qdd, g, NULL, w, &e);
    allocations += g_allocations - before;
    CHECK_CODE(code, MASSID_OK);
    ++rows;
    /* Every column the CLI wrote, the same double. */
    for (k = 0; k < 6; ++k) differ += !tracker_same(e.comp[k], strtod(out_f[comp[k]], NULL));
    for (k = 0; k < 18; ++k) {
      const char* cell = out_f[tracked[k]];
      if (k >= 6 && k < 12 && !e.inertia_determined)
        differ += cell[0] != '\0'; /* undetermined: the CLI leaves it empty */
      else
        differ += cell[0] == '\0' || !tracker_same(tracker_value(&e, k), strtod(cell, NULL));
    }
    differ += strcmp(massid_tracker_event_name(e.event), out_f[event]) != 0;
    changes += e.event == MASSID_EVENT_CHANGE;
    contacts += e.event == MASSID_EVENT_CONTACT;
    if (differ > 0 && differ < 5)
      fprintf(stderr, "%s: row %d (t = %s) differs\n", name, rows, in_f[0]);
  }
  CHECK(fgets(out_line, sizeof out_line, out) == NULL); /* no more rows either */
  CHECK(rows == 20000);
  CHECK(differ == 0);
  /* The log exercises the events: grasp and release, a two-second contact. */
  CHECK(changes == 2);
  CHECK(contacts >= 900);
#if defined(MASSID_TEST_COUNT_ALLOCATIONS)
  CHECK(allocations == 0);
  if (allocations != 0) fprintf(stderr, "%s: %ld allocations in the updates\n", name, allocations);
#else
  (void)allocations;
#endif
  printf("%s: %d rows, %d differing values, %d changes, %d contact rows\n", name, rows, differ,
         changes, contacts);
done:
  if (in) fclose(in);
  if (out) fclose(out);
  massid_tracker_free(tr);
  massid_predictor_free(p); /* the joint names were its */
}

/* ---------------------------------------------------------------- errors */

static void test_tracker_errors(void) {
  char params[1200], error[512];
  const double noise_zero[6] = {0.05, 0.05, 0.0, 0.003, 0.003, 0.003};
  const double noise_nan[6] = {0.05, NAN, 0.05, 0.003, 0.003, 0.003};
  const double noise[6] = {0.05, 0.05, 0.05, 0.003, 0.003, 0.003};
  const double q[6] = {0.3, -1.3, 1.4, -1.2, -1.4, 0.4}, zero[6] = {0};
  const double root_gravity[3] = {0.0, 0.0, -9.80665}, g[3] = {0.0, 0.0, -9.80665};
  double w[6] = {0.0, 0.0, -20.0, 0.0, 0.0, 0.0};
  massid_tracker_estimate e, before, after;
  massid_tracker* tr = (massid_tracker*)&e; /* set to NULL on failure */
  massid_predictor* p;

  /* Zeroed, padding included, for memcmp. */
  memset(&e, 0, sizeof e);
  memset(&before, 0, sizeof before);
  memset(&after, 0, sizeof after);
  snprintf(params, sizeof params, "%s/wrist.json", g_dir);
  p = massid_predictor_load(g_urdf, params, error, sizeof error);
  CHECK(p != NULL);
  if (!p) return;

  /* A payload link the model does not measure: the message names it and the
   * measured links. */
  CHECK_CODE(massid_tracker_create(p, "gripper", NULL, &tr, error, sizeof error),
             MASSID_ERROR_INVALID_ARGUMENT);
  CHECK(tr == NULL);
  CHECK(strstr(error, "'gripper'") != NULL);
  CHECK(strstr(error, "measured links") != NULL && strstr(error, "tool") != NULL);
  if (!strstr(error, "'gripper'")) fprintf(stderr, "message: %s\n", error);
  CHECK_CODE(massid_tracker_create(p, NULL, noise_zero, &tr, error, sizeof error),
             MASSID_ERROR_INVALID_ARGUMENT);
  CHECK(strstr(error, "noise") != NULL);
  CHECK_CODE(massid_tracker_create(p, NULL, noise_nan, &tr, error, sizeof error),
             MASSID_ERROR_NOT_FINITE);
  CHECK_CODE(massid_tracker_create(NULL, NULL, NULL, &tr, error, sizeof error),
             MASSID_ERROR_INVALID_ARGUMENT);
  CHECK_CODE(massid_tracker_create(p, NULL, NULL, NULL, error, sizeof error),
             MASSID_ERROR_INVALID_ARGUMENT);

  /* The default link by name, the noise given. */
  CHECK_CODE(massid_tracker_create(p, "tool", noise, &tr, error, sizeof error), MASSID_OK);
  CHECK(strcmp(error, "") == 0);
  if (!tr) {
    massid_predictor_free(p);
    return;
  }
  CHECK_CODE(
      massid_tracker_update_upstream(tr, 0.0, q, zero, zero, root_gravity, NULL, NULL, NULL, w, &e),
      MASSID_OK);
  CHECK_CODE(massid_tracker_get_estimate(tr, &before), MASSID_OK);
  CHECK(memcmp(&before, &e, sizeof e) == 0);
  /* Time that does not increase, a NaN, a NULL: refused, the tracker as it was. */
  CHECK_CODE(
      massid_tracker_update_upstream(tr, 0.0, q, zero, zero, root_gravity, NULL, NULL, NULL, w, &e),
      MASSID_ERROR_TIME_ORDER);
  w[2] = NAN;
  CHECK_CODE(massid_tracker_update_upstream(tr, 0.002, q, zero, zero, root_gravity, NULL, NULL,
                                            NULL, w, &e),
             MASSID_ERROR_NOT_FINITE);
  w[2] = -20.0;
  CHECK_CODE(massid_tracker_update_upstream(tr, 0.002, NULL, NULL, NULL, root_gravity, NULL, NULL,
                                            NULL, w, &e),
             MASSID_ERROR_INVALID_ARGUMENT);
  CHECK_CODE(massid_tracker_update_upstream(tr, 0.002, q, zero, NULL, root_gravity, NULL, NULL,
                                            NULL, w, &e),
             MASSID_ERROR_INVALID_ARGUMENT); /* qdu without qddu */
  CHECK_CODE(massid_tracker_update(tr, 0.002, NULL, NULL, NULL, NULL, NULL, w, &e),
             MASSID_ERROR_INVALID_ARGUMENT);
  CHECK_CODE(massid_tracker_update(NULL, 0.002, NULL, NULL, NULL, g, NULL, w, &e),
             MASSID_ERROR_INVALID_ARGUMENT);
  CHECK_CODE(massid_tracker_get_estimate(tr, &after), MASSID_OK);
  CHECK(memcmp(&before, &after, sizeof e) == 0);
  CHECK_CODE(massid_tracker_get_estimate(tr, NULL), MASSID_ERROR_INVALID_ARGUMENT);
  CHECK_CODE(massid_tracker_update_upstream(tr, 0.002, q, zero, zero, root_gravity, NULL, NULL,
                                            NULL, w, NULL),
             MASSID_OK);

  CHECK(strcmp(massid_tracker_event_name(MASSID_EVENT_NONE), "") == 0);
  CHECK(strcmp(massid_tracker_event_name(MASSID_EVENT_CHANGE), "change") == 0);
  CHECK(strcmp(massid_tracker_event_name(MASSID_EVENT_CONTACT), "contact") == 0);
  CHECK(massid_tracker_event_name(3) == NULL);
  CHECK(strstr(massid_error_string(MASSID_ERROR_TIME_ORDER), "does not increase") != NULL);
  CHECK(massid_tracker_payload_link(NULL) == NULL);
  massid_tracker_free(tr);
  massid_tracker_free(NULL);
  massid_predictor_free(p);
}

int main(int argc, char** argv) {
  if (argc != 5) {
    fprintf(stderr, "usage: %s MASSID_CLI MASSID_TRACKER_FIXTURE URDF WORK_DIR\n", argv[0]);
    return 2;
  }
  snprintf(g_cli, sizeof g_cli, "%s", argv[1]);
  snprintf(g_fixture, sizeof g_fixture, "%s", argv[2]);
  snprintf(g_urdf, sizeof g_urdf, "%s", argv[3]);
  snprintf(g_dir, sizeof g_dir, "%s", argv[4]);
  mkdir(g_dir, 0755);
  if (!tracker_make_files()) return 1;
  test_tracker_log("wrist", 1);
  test_tracker_log("base", 0);
  test_tracker_errors();
  printf("%d checks, %d failed\n", g_checks, g_failures);
  return g_failures == 0 ? 0 : 1;
}
