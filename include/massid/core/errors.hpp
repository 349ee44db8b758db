// Error types. Each carries the CLI exit code that the spec assigns to it, and
// the hints: what the caller can change, in the library's own terms.
#pragma once

#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace massid {

// A setting the caller can change to get past an error or a warning, or the
// setting at fault. Library messages name no command-line option: each front
// end spells the hint its own way, the CLI as an option ("--fixed
// elbow=0.3"), Python as a keyword ("fixed={'elbow': 0.3}"); the message says
// in words what the hint does.
struct Hint {
  enum class Setting {
    HoldJoints,    // hold joints at values: value "JOINT=VALUE[ JOINT=VALUE...]"
    Offset,        // estimate the sensor offsets: value "on" / "off"
    Checks,        // the set-up checks: value "off"
    Robust,        // the robust fit: value "on"
    Drift,         // a drifting offset: "linear", "per-block" or "off"
    Dynamic,       // the log is in motion (ten parameters per link): "on" / "off"
    Cutoff,        // the low-pass cut-off for derivatives, Hz: a value or "higher"
    Delay,         // the wrench's delay behind the joints: seconds, "auto" or "off"
    MinHeight,     // the clearance above the platform plane, m: a value, "lower" or "none"
    Limits,        // joint ranges for the design: "JOINT=LO:HI"
    LevelGravity,  // the level gravity vector of the design
    TiltMax,       // the largest platform tilt of the design, degrees
    Physical,      // physically consistent parameters: "on"
    SensorLink,    // the sensor link: a link name
    Poses,         // the number of poses of the design
    SigmaForce,    // the force noise, N
    SigmaMoment,   // the moment noise, N m
    LevelPoses,    // the share of level poses of a tilted design
    // Identification (identify_request.hpp):
    Rest,         // the rest windows of a static log: "auto" or "off"
    RootGravity,  // gravity in the URDF root frame, gx,gy,gz
    // Reading a log (read_samples.hpp):
    Columns,  // columns bound to roles by name: "ROLE=NAME,ROLE=NAME..." (NAME unknown: "NAME")
  };
  Setting setting;
  std::string value;  // empty: the setting itself
  bool operator==(const Hint&) const = default;
};

// A hint spelled in the caller's terms: the CLI's cli::spell ("--robust"),
// Python's ("robust=True"). Reports that mention settings in their prose take
// one (report.hpp).
using HintSpeller = std::string (*)(const Hint&);

// A message followed by its hints in one door's spelling, the way every door
// prints an error or a warning: "MESSAGE (HINT; HINT)", or MESSAGE alone.
inline std::string with_hints(const std::string& message, const std::vector<Hint>& hints,
                              HintSpeller spell) {
  if (hints.empty()) return message;
  std::string out = message + " (";
  for (size_t i = 0; i < hints.size(); ++i) out += (i ? "; " : "") + spell(hints[i]);
  return out + ")";
}

// A warning about a result: the message in words, naming no option, and the
// settings that address it. Front ends print the message followed by the
// hints in their own spelling, e.g. "... or give the sensor's noise
// (--sigma-force; --sigma-moment)".
struct Warning {
  std::string message;  // one line, without a prefix ("massid: warning: ") or newline
  std::vector<Hint> hints;
  bool operator==(const Warning&) const = default;
};

// Base of massid's errors: a message and its hints.
class Error : public std::runtime_error {
 public:
  explicit Error(const std::string& message, std::vector<Hint> hints = {})
      : std::runtime_error(message), hints_(std::move(hints)) {}
  const std::vector<Hint>& hints() const noexcept { return hints_; }

 private:
  std::vector<Hint> hints_;
};

// Bad usage or bad input: a file that cannot be read, a malformed cell, an
// unsupported joint. The message names the file, line and column (or joint) at
// fault. CLI exit code 2.
class InputError : public Error {
 public:
  using Error::Error;
};

// The data cannot determine every base parameter. The message names the
// undetermined parameters and the poses that would determine them. Exit code 3.
class IdentifiabilityError : public Error {
 public:
  using Error::Error;
};

// A caller passed arrays of the wrong size to a library function (q of the
// wrong length, a workspace built for another model): a programming error,
// not bad data. The message names the function, the argument and both sizes.
// Checked by every public function, one comparison each (the real-time paths
// included). Not a CLI exit code of its own (1, as any internal error).
class ArgumentError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

}  // namespace massid
