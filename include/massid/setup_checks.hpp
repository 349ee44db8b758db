// Set-up checks: the usual mistakes of a new set-up, found in a data file
// before identifying from it, each a specific diagnosis that says the fix.
//
//   code                severity         what it means
//   wrench-sign         error            the force points against gravity (reaction convention)
//   force-channels      error            a force channel negated or two swapped (a reflection)
//   moment-channels     error            the same for the moment channels
//   frame-rotation      warning / error  the wrench frame is rotated against gx,gy,gz (2 / 5 deg)
//   joint-degrees       error / warning  a radian joint column holds degrees
//   joint-millimetres   error            a prismatic joint column holds millimetres
//   force-units         error            forces in mN (total mass ~1000 x the URDF's)
//   moment-units        error            moments in N mm (lever arms ~1000 x the robot)
//                                        (without URDF masses both judged by the robot's reach)
//   gravity-magnitude   error / warning  |g| of gx,gy,gz far from 9.81 m/s^2
//   duplicate-columns   error / warning  two wrench (error) or joint (warning) columns identical
//   constant-wrench     error            a wrench channel that never changes but should
//   constant-joint      warning          a joint that never moves
//
// Errors are mistakes that make the identified parameters meaningless (a wrong
// sign, unit or frame); warnings are likely mistakes the identification
// survives, or that its own identifiability check diagnoses. Each statistic
// is independent of the others and of the sensor offset, and its threshold is
// far from what realistic noise and offsets produce (setup_checks.cpp).
#pragma once

#include <string>
#include <vector>

#include "massid/errors.hpp"
#include "massid/model.hpp"
#include "massid/samples.hpp"

namespace massid {

struct SetupFinding {
  enum class Severity { Warning, Error };
  Severity severity = Severity::Warning;
  std::string code;     // stable short name, e.g. "wrench-sign"
  std::string message;  // one line: names the file, columns and lines, and says the fix
  // The settings the fix names (errors.hpp): an error's hints include
  // skipping the set-up checks.
  std::vector<Hint> hints;
};

struct SetupCheckOptions {
  // check_setup_file: the checks look at the first max_rows samples only (a
  // big file is never read whole).
  int max_rows = 20000;  // 20 000 rows: statistics far beyond the noise, ~50 ms
  // Report joints that never move. `identify` turns this off: its
  // identifiability check already names such a joint (exit 3) and the fix.
  bool constant_joints = true;
  // A motion log: the force is the weight minus the rate of change of
  // momentum, not M g, so the checks that compare each sample's force with
  // its gravity (wrench-sign, frame-rotation) are not made; the unit, column
  // and gravity checks are.
  bool motion = false;
  // check_setup_file reads the file with these (the root gravity for a sensor
  // below movable joints).
  SampleOptions read;
};

// The checks on samples read with read_samples. Without a wrench (a plan, or
// a file given to predict), only the joint, gravity and joint-column checks.
// `header` is the file's column names (to tell JOINT from JOINT_deg columns);
// empty: every joint column is named as the joint.
std::vector<SetupFinding> check_setup(const Model& model, const Samples& samples,
                                      const std::vector<std::string>& header,
                                      const SetupCheckOptions& options = {});

// The first max_rows samples of a data file, read by the one streaming reader
// of data files (memory-mapped; memory bounded by max_rows, whatever the
// file's size; lines after the last sample read are not looked at), with
// read_csv's and read_samples' rules and errors. header: the file's column names.
Samples read_samples_head(const Model& model, const std::string& path, int max_rows,
                          std::vector<std::string>* header = nullptr,
                          const SampleOptions& read = {});

// read_samples_head, then check_setup.
std::vector<SetupFinding> check_setup_file(const Model& model, const std::string& path,
                                           const SetupCheckOptions& options = {});

bool has_error(const std::vector<SetupFinding>& findings);

}  // namespace massid
