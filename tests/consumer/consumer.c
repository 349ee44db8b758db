/* Outside massid's tree, in C: loads a URDF and a params file through the
 * installed libmassid_c and predicts the wrench at every row of a noise-free
 * measurement file (the columns found by name in its header: the joints,
 * gx,gy,gz and fx..mz, as `massid simulate` writes them). Exit 0 when the
 * largest difference is below 1e-9 of the measured range.
 *
 *   consumer_c ROBOT.urdf PARAMS.json MEASUREMENTS.csv */
#include <massid.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int main(int argc, char** argv) {
  if (argc != 4) {
    fprintf(stderr, "usage: consumer_c ROBOT.urdf PARAMS.json MEASUREMENTS.csv\n");
    return 2;
  }
  char error[512];
  massid_predictor* p = massid_predictor_load(argv[1], argv[2], error, sizeof error);
  if (!p) {
    fprintf(stderr, "consumer_c: %s\n", error);
    return 2;
  }
  const int n = massid_predictor_num_joints(p);
  FILE* f = fopen(argv[3], "r");
  if (!f || n != 3) {
    fprintf(stderr, "consumer_c: cannot read %s, or not the 3-joint PUMA\n", argv[3]);
    return 2;
  }
  /* The header (after any '#' comment lines): the columns each value comes from. */
  char line[4096];
  do {
    if (!fgets(line, sizeof line, f)) return 2;
  } while (line[0] == '#');
  const char* wanted[3 + 3 + 6] = {0};
  for (int j = 0; j < n; ++j) wanted[j] = massid_predictor_joint_name(p, j);
  const char* fixed_names[9] = {"gx", "gy", "gz", "fx", "fy", "fz", "mx", "my", "mz"};
  for (int k = 0; k < 9; ++k) wanted[3 + k] = fixed_names[k];
  int column[12];
  for (int k = 0; k < 12; ++k) column[k] = -1;
  int c = 0;
  for (char* name = strtok(line, ",\r\n"); name; name = strtok(NULL, ",\r\n"), ++c)
    for (int k = 0; k < 12; ++k)
      if (strcmp(name, wanted[k]) == 0) column[k] = c;
  for (int k = 0; k < 12; ++k)
    if (column[k] < 0 || column[k] >= 64) {
      fprintf(stderr, "consumer_c: %s has no column %s\n", argv[3], wanted[k]);
      return 2;
    }
  double worst = 0.0, range = 0.0;
  int rows = 0;
  while (fgets(line, sizeof line, f)) {
    if (line[0] == '#') continue;
    double cells[64];
    char* cell = line;
    for (int i = 0; i < 64 && *cell && *cell != '\n'; ++i) {
      cells[i] = strtod(cell, &cell);
      if (*cell == ',') ++cell;
    }
    double v[12];
    for (int k = 0; k < 12; ++k) v[k] = cells[column[k]];
    double w[6], offset[6];
    if (massid_predict(p, v, v + 3, w) != 0 || massid_predictor_offset(p, offset) != 0) return 1;
    for (int k = 0; k < 6; ++k) {
      const double d = fabs(w[k] + offset[k] - v[6 + k]);
      worst = d > worst ? d : worst;
      range = fabs(v[6 + k]) > range ? fabs(v[6 + k]) : range;
    }
    ++rows;
  }
  fclose(f);
  massid_predictor_free(p);
  printf("massid %s (C): %d samples, largest difference %.3g (range %.3g)\n", massid_version(),
         rows, worst, range);
  return rows > 0 && worst <= 1e-9 * range ? 0 : 1;
}
