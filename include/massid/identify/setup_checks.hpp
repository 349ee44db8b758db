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
//   joint-derivatives   error            a _vel (_acc) column is not the derivative of the
//                                        position (_vel) over t: another unit or a scale
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
//
// A wiring verdict (wrench-sign, force-channels, moment-channels,
// frame-rotation) must hold over the file, not come from a minority of rows:
// at rest the force is a linear function of gravity, f_i = A g_i + b, whatever
// the wiring (A = M R, M P, -M), so the rows that a robust fit of that map
// leaves far beyond the noise (an external wrench acting for a while: contact)
// are set aside before those checks, as long as they are a minority. Which
// rows carry an external wrench against a model's prediction is
// find_contact_episodes' verdict (predict, compensate: the expected result;
// identify: outliers that --robust rejects).
#pragma once

#include <Eigen/Core>
#include <optional>
#include <string>
#include <vector>

#include "massid/core/errors.hpp"
#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/io/read_samples.hpp"

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
  // and gravity checks are, and check_setup_file reads t, _vel and _acc for
  // joint-derivatives.
  bool motion = false;
  // check_setup_file reads the file with these (the root gravity for a sensor
  // below movable joints).
  SampleOptions read;
};

// The checks on samples read with read_samples. Without a wrench (a plan, or
// a file given to predict), only the joint, gravity and joint-column checks.
// `header` is the roles of the file's columns (column_roles, read_samples.hpp:
// the names, with the bindings of SampleOptions::columns applied), to tell
// JOINT from JOINT_deg columns; empty: every joint column is named as the joint.
std::vector<SetupFinding> check_setup(const Model& model, const Samples& samples,
                                      const std::vector<std::string>& header,
                                      const SetupCheckOptions& options = {});

// The first max_rows samples of a data file, read by the one streaming reader
// of data files (memory-mapped; memory bounded by max_rows, whatever the
// file's size; lines after the last sample read are not looked at), with
// read_csv's and read_samples' rules and errors. header: the roles of the
// file's columns (column_roles). `motion`: t and the joints' _vel and _acc
// too (the sensor motion wx..az bound as a motion log binds it).
Samples read_samples_head(const Model& model, const std::string& path, int max_rows,
                          std::vector<std::string>* header = nullptr,
                          const SampleOptions& read = {}, bool motion = false);

// read_samples_head, then check_setup.
std::vector<SetupFinding> check_setup_file(const Model& model, const std::string& path,
                                           const SetupCheckOptions& options = {});

bool has_error(const std::vector<SetupFinding>& findings);

// The verdict of the checks on a file a command reads besides identify's data
// (simulate's plan, predict's log, design's evaluated plan): refused when a
// finding is an error.
struct SetupVerdict {
  std::vector<SetupFinding> findings;  // in check_setup's order
  bool refused() const { return has_error(findings); }
  // What a door shows: with an error the errors alone (each on its own line),
  // else the warnings.
  std::vector<SetupFinding> shown() const;
  // The warnings with their hints (empty when refused).
  std::vector<Warning> warnings() const;
};

// check_setup for such a file: joints that never move are not reported (a
// plan may hold a joint still on purpose); `motion`: a log in motion (no
// force-against-gravity checks). `header` as check_setup's.
SetupVerdict check_input_setup(const Model& model, const Samples& samples,
                               const std::vector<std::string>& header, bool motion);

// wrench-sign after the fit, for motion logs (whose force is not M g row by
// row, so check_setup cannot compare it with gravity) and any log the checks
// did not see: an error when the identified total mass M is negative beyond
// noise, M + 5 std(M) < 0 (a negated wrench, or gravity pointing up, negates
// every parameter). None when M is not identifiable or the fit is plausible.
std::optional<SetupFinding> check_fitted_weight(const Model& model, const BaseParameters& base,
                                                const IdentifySummary& summary,
                                                const std::string& source);

// A refusing verdict as an error: the message is the errors' messages, one
// per line (a single error: its message, as a door prints it), the hints
// theirs (skipping the checks among them). errors(): the findings, for a door
// that prints each on its own line.
class SetupRefused : public InputError {
 public:
  explicit SetupRefused(std::vector<SetupFinding> errors);
  const std::vector<SetupFinding>& errors() const noexcept { return errors_; }

 private:
  std::vector<SetupFinding> errors_;
};

// The rows of a file that a robust fit of f_i = A g_i + b (any wiring, any
// offset) leaves beyond the noise, in Samples order: what the wiring checks
// set aside. Empty when the force is not comparable with gravity (no wrench,
// gravity from the force) or when such rows would not be a minority.
std::vector<int> rows_against_gravity(const Samples& samples);

// --- contact: rows that carry an external wrench for a while ----------------

// An episode: consecutive rows whose residual (measured minus the model's
// wrench) lies beyond the noise.
struct ContactEpisode {
  int first = 0, last = 0;            // rows in Samples (inclusive)
  int first_line = 0, last_line = 0;  // the file's lines
  int rows = 0;                       // rows beyond the threshold in [first, last]
  double score = 0.0;      // largest standardised residual d in it (chi, 6 dof; 4 with gravity
                           // from the force)
  double threshold = 0.0;  // the d a clean row exceeds with probability 1 % per file
  // Largest |force| (N) and |moment| (N m) of the residual about its median
  // (the external wrench); NaN when only the scores are known (identify).
  double force = 0.0, moment = 0.0;
};

struct ContactOptions {
  int min_rows = 3;           // an episode has at least this many rows beyond the threshold...
  int max_gap = 2;            // ...with at most this many rows within the noise between two
  double probability = 0.01;  // a clean file has a row beyond the threshold with this probability
};

// From a model's prediction: residual [N x 6] = measured - predicted, per
// row of samples. Each axis is standardised by the robust scale of its
// residual (1.4826 MAD about the median), so a constant offset and the model's
// small errors stay within the noise; a row is beyond it when d = |r / s|
// exceeds chi_6 at probability / N.
std::vector<ContactEpisode> find_contact_episodes(const Samples& samples,
                                                  const Eigen::MatrixXd& residual,
                                                  const ContactOptions& options = {});

// The same from a stream (compensate): the file line of each residual row
// and the measured wrench's RMS of force (N) and moment (N m) over the rows,
// the floor of each axis' scale (noise-free data: round-off is no contact).
// With the samples' lines and wrench, the same episodes as above.
std::vector<ContactEpisode> find_contact_episodes(const std::vector<int>& line,
                                                  const Eigen::MatrixXd& residual,
                                                  const Eigen::Vector2d& measured_rms,
                                                  const ContactOptions& options = {});

// The rows that rule finds beyond the noise, before they are grouped
// (identify without the robust fit: IdentifySummary::beyond_noise); threshold
// receives the d they exceed (0 when fewer than two rows are finite).
std::vector<Outlier> rows_beyond_noise(const Samples& samples, const Eigen::MatrixXd& residual,
                                       double* threshold, const ContactOptions& options = {});

// From rows an outlier test already flagged (identify: IdentifySummary::outliers,
// with its threshold): the same grouping rule; force and moment NaN.
std::vector<ContactEpisode> find_contact_episodes(const std::vector<Outlier>& flagged,
                                                  double threshold,
                                                  const ContactOptions& options = {});

// "lines 122-342 (221 rows)": an episode's place, for messages.
std::string contact_place(const ContactEpisode& e);

// The note predict and compensate print for an episode: "FILE: lines L1-L2
// (n rows) carry an external wrench of up to X N, Y N m (d up to D, beyond
// the noise's T) (contact): fx_comp..mz_comp hold it".
std::string contact_note(const std::string& source, const ContactEpisode& e);

}  // namespace massid
