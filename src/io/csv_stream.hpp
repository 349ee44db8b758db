// Private: a data CSV read in place from a memory-mapped file, for streaming
// identification. The same rules and messages as read_csv + read_samples
// (csv.hpp, samples.hpp): a UTF-8 BOM, CRLF, blank and `#` lines, quoted
// fields (csv_fields.hpp), the header bound by the one binding of
// column_map.hpp, errors as file:line:column.
//
// Rows are parsed straight into doubles with fast_float; a line the fast path
// does not understand (quotes, stray characters, a bad cell, a wrong field
// count) is re-read by the slow path that mirrors read_csv exactly, which
// either accepts it or throws read_csv's message for it.
#pragma once

#include <fast_float/fast_float.h>

#include <Eigen/Core>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "io/column_map.hpp"
#include "massid/core/gravity.hpp"
#include "massid/core/model.hpp"
#include "massid/core/samples.hpp"
#include "massid/io/read_samples.hpp"

namespace massid::detail {

// A read-only private mapping of a whole file (an empty file maps nothing).
class MappedFile {
 public:
  explicit MappedFile(const std::string& path);  // InputError "PATH: cannot open file"
  ~MappedFile();
  MappedFile(const MappedFile&) = delete;
  MappedFile& operator=(const MappedFile&) = delete;
  std::string_view text() const { return {data_, size_}; }
  // Drops the whole pages inside [begin, end) from the process (they stay in the
  // page cache and fault back in if read again): keeps the resident set small.
  void release(std::size_t begin, std::size_t end) const;

 private:
  const char* data_ = nullptr;
  std::size_t size_ = 0;
};

// The header of a data file bound to a model: where each value of a row comes
// from. Row values are laid out in read_samples' order of column groups (so
// that a line with several bad cells reports the one read_samples would):
//   static binding:  [joints (Model::joints order)] [upstream joints (only when
//                    they give gravity)] [fx..mz] [gx gy gz]
//   motion binding:  [joints] [JOINT_vel] [JOINT_acc] [wx..az] [upstream joints]
//                    [their _vel] [their _acc] [fx..mz] [t] [block] [gx gy gz]
// with absent optional groups taking no room. The gravity values are always
// there: read, or from the force (parse_block), or from the upstream joints
// (the caller's, with upstream_kinematics).
struct SampleColumns {
  std::string source;
  int header_line = 0;
  std::vector<std::string> header;
  std::vector<int> target;     // [columns] index into the row values, -1 unused
  std::vector<double> scale;   // [columns] 1, or pi/180 for JOINT_deg
  std::vector<int> column_of;  // [values] the CSV column of each value, -1 when computed
  int num_joints = 0;
  int num_upstream = 0;  // Model::upstream_joints (whether or not the file has them)
  int num_values = 0;
  bool motion = false;  // bound for a motion log (bind_columns' `motion`)
  bool gravity_from_force = false;
  bool gravity_from_upstream = false;  // no gx,gy,gz, upstream joint columns: gravity from them
  // No gx,gy,gz nor upstream joints, tilt_x_deg,tilt_y_deg: gravity is the
  // level gravity turned by them (tilted_gravity), from the values at tilt_value.
  bool gravity_from_tilt = false;
  int tilt_value = -1;
  double g0 = 0.0;                         // |g| for gravity from the force (SampleOptions)
  Eigen::Vector3d root_gravity{0, 0, 0};   // for gravity from the upstream joints (SampleOptions)
  Eigen::Vector3d level_gravity{0, 0, 0};  // with gravity_from_tilt: tilt_level_gravity
  std::size_t data_begin = 0;              // byte offset of the line after the header
  // Value offsets; -1 when the group is absent (or not bound: static binding
  // binds only joints, wrench, gravity and, for gravity, the upstream joints).
  int wrench = 0, gravity = 0;
  int qd = -1, qdd = -1;                   // [num_joints] JOINT_vel, JOINT_acc
  int sensor = -1;                         // [9] wx wy wz dwx dwy dwz ax ay az
  int q_up = -1, qd_up = -1, qdd_up = -1;  // [num_upstream]
  int time = -1, block = -1;               // t, block
  // The sensor's pose from columns (Model::pose): the orientation at q_up is
  // checked and a quaternion normalised as each line is parsed (normalise_pose).
  SensorPoseColumns pose = SensorPoseColumns::None;
  std::string note;                // map_columns' note on the header ("" for none)
  std::vector<std::string> roles;  // map_columns' roles of the columns
  int wrench_value() const { return wrench; }
  int gravity_value() const { return gravity; }
};

// The header alone: c.source, c.header, c.header_line and c.data_begin (the
// first line neither blank nor a comment; a UTF-8 BOM skipped). InputError for
// an empty file or a bad header.
void read_header(std::string_view text, const std::string& source, SampleColumns& c);

// Reads the header and binds it (bind_header; InputError as read_csv/
// read_samples with WrenchColumns::Required, incl. "header but no data rows").
SampleColumns bind_columns(const Model& model, std::string_view text, const std::string& source,
                           const SampleOptions& options, bool motion = false);

// Binds a header that read_header read (the rows may come later: a live
// stream, compensator.hpp) with map_columns (column_map.hpp), with
// options.columns: every optional group is checked (the sensor motion wx..az
// given in part only with `motion`: else ignored); with `motion` they are laid
// out too.
SampleColumns bind_header(const Model& model, SampleColumns header, const SampleOptions& options,
                          bool motion = false);

// Binds one more column (one the binding leaves unused, target -1) as the
// next row value, read as scale * cell; returns its value index.
int bind_value(SampleColumns& c, int column, double scale);

// Throws read_samples' error for a block cell that is not an integer, for
// the line at `line_begin`.
[[noreturn]] void throw_not_integer(std::string_view text, std::size_t line_begin,
                                    const SampleColumns& c, double value);
// read_samples' test of a block cell.
inline bool is_block_number(double b) { return b == std::round(b) && std::abs(b) <= 1e9; }

// normalise_pose (kinematics.hpp) of the pose at c.q_up in a parsed line's
// values (the line at `line_begin`), its InputError naming the file and line.
void check_pose(std::string_view text, std::size_t line_begin, const SampleColumns& c,
                double* vals);
void check_pose_line(const SampleColumns& c, int line_no, double* vals);

// 1-based line number of byte `pos`.
int line_number(std::string_view text, std::size_t pos);

// Byte range [begin, end) of block k of the data area: the lines that start in
// [data_begin + k * block_bytes, data_begin + (k + 1) * block_bytes).
std::size_t num_blocks(std::string_view text, const SampleColumns& c, std::size_t block_bytes);
std::pair<std::size_t, std::size_t> block_range(std::string_view text, const SampleColumns& c,
                                                std::size_t block_bytes, std::size_t k);

// Slow path for one line [line_begin, line_end) of `text` ('\r' removed):
// parse_row_slow, its line number counted only for a row (a count from the
// file's start: a log with many blank or comment lines stays linear).
bool parse_line_slow(std::string_view text, std::size_t line_begin, std::size_t line_end,
                     const SampleColumns& c, double* vals);
// Slow path for one line ('\r' removed), `line_no` its number for messages:
// false for a blank or comment line, true with vals filled, or InputError.
bool parse_row_slow(std::string_view line, int line_no, const SampleColumns& c, double* vals);

// The first max_rows samples of a data file (q, gravity, wrench, line: what
// the static binding reads; with `motion` also t and the joints' _vel and
// _acc, for the set-up checks), with the rules and errors of read_csv +
// read_samples (WrenchColumns::Required); lines after the last sample read are
// not looked at. header: the file's column names. The one reader of a whole
// file (identify_file) and of its head (read_samples_head).
Samples read_file_samples(const Model& model, const std::string& path, int max_rows,
                          const SampleOptions& read, std::vector<std::string>* header = nullptr,
                          bool motion = false);

// Throws read_samples' zero-force error for the row at `where` ("file:line"),
// or for the line at `line_begin`.
[[noreturn]] void throw_zero_force(const std::string& where);
[[noreturn]] void throw_zero_force(std::string_view text, std::size_t line_begin,
                                   const SampleColumns& c);

namespace csv_fast {

inline bool blank(char ch) { return ch == ' ' || ch == '\t'; }
inline bool digit(char ch) { return static_cast<unsigned char>(ch - '0') < 10; }

// A plain decimal "[-]digits[.digits]" of at most 19 digits (how massid and
// most loggers write numbers) to the double fast_float::from_chars gives: the
// same steps (Clinger's exact fast path, else Eisel-Lemire) without its
// general scanning. nullptr for anything else (an exponent, more digits, no
// digit, the rare inputs Eisel-Lemire cannot round), which from_chars reads.
inline const char* plain_decimal(const char* p, const char* end, double& out) {
  using Format = fast_float::binary_format<double>;
  const bool negative = p < end && *p == '-';
  p += negative;
  const char* const first = p;
  std::uint64_t mantissa = 0;  // wraps past 19 digits, then unused
  while (p < end && digit(*p)) mantissa = 10 * mantissa + static_cast<unsigned>(*p++ - '0');
  const int whole = static_cast<int>(p - first);
  int fraction = 0;
  if (p < end && *p == '.') {
    const char* const f = ++p;
    while (end - p >= 8 && fast_float::is_made_of_eight_digits_fast(p)) {
      mantissa = mantissa * 100000000 + fast_float::parse_eight_digits_unrolled(p);
      p += 8;
    }
    while (p < end && digit(*p)) mantissa = 10 * mantissa + static_cast<unsigned>(*p++ - '0');
    fraction = static_cast<int>(p - f);
  }
  const int digits = whole + fraction;
  if (digits == 0 || digits > 19 || (p < end && (*p == 'e' || *p == 'E'))) return nullptr;
  if (fraction <= -Format::min_exponent_fast_path() &&
      mantissa <= Format::max_mantissa_fast_path()) {
    double value = static_cast<double>(mantissa);
    if (fraction > 0) value = value / Format::exact_power_of_ten(fraction);
    out = negative ? -value : value;
    return p;
  }
  const fast_float::adjusted_mantissa am = fast_float::compute_float<Format>(-fraction, mantissa);
  if (am.power2 < 0) return nullptr;
  fast_float::to_float(negative, am, out);
  return p;
}

// 1: a sample, 0: blank or comment, -1: let the slow path decide.
inline int parse_line(const char* p, const char* le, const SampleColumns& c, double* vals) {
  while (p < le && blank(*p)) ++p;
  if (p == le || *p == '#') return 0;
  const int nc = static_cast<int>(c.target.size());
  const int* const target = c.target.data();  // (held in registers across the calls)
  const double* const scale = c.scale.data();
  for (int col = 0; col < nc; ++col) {
    while (p < le && blank(*p)) ++p;
    const int t = target[col];
    if (t >= 0) {
      const char* f = p;
      if (f < le && *f == '+') ++f;
      double x;
      const char* next = plain_decimal(f, le, x);
      if (!next) {
        const auto r = fast_float::from_chars(f, le, x);
        if (r.ec != std::errc() || !std::isfinite(x)) return -1;
        next = r.ptr;
      }
      vals[t] = scale[col] == 1.0 ? x : scale[col] * x;
      p = next;
      while (p < le && blank(*p)) ++p;
    } else {
      if (p < le && *p == '"') return -1;
      const void* comma = std::memchr(p, ',', static_cast<std::size_t>(le - p));
      p = comma ? static_cast<const char*>(comma) : le;
    }
    if (col + 1 < nc) {
      if (p >= le || *p != ',') return -1;
      ++p;
    } else if (p != le) {
      return -1;
    }
  }
  return 1;
}

}  // namespace csv_fast

// Calls sink(vals, pos) -- or sink(vals, pos, line), `line` counting the
// lines from the one at `begin` (0) -- for every sample whose line starts in
// [begin, end), pos the byte offset of its line; gravity from the force
// (eq. 37) when the file has no gx,gy,gz and no upstream joints. Returns the
// number of lines that start in [begin, end).
template <class Sink>
std::size_t parse_block(std::string_view text, const SampleColumns& c, std::size_t begin,
                        std::size_t end, Sink&& sink) {
  std::vector<double> vals(c.num_values);
  const char* const base = text.data();
  const char* const eof = base + text.size();
  const char* p = base + begin;
  const char* const stop = base + end;
  const int w = c.wrench_value(), g = c.gravity_value();
  std::size_t lines = 0;
  while (p < stop) {
    const void* found = std::memchr(p, '\n', static_cast<std::size_t>(eof - p));
    const char* nl = found ? static_cast<const char*>(found) : eof;
    const char* le = nl;
    if (le > p && le[-1] == '\r') --le;
    int kind = csv_fast::parse_line(p, le, c, vals.data());
    if (kind < 0)
      kind = parse_line_slow(text, static_cast<std::size_t>(p - base),
                             static_cast<std::size_t>(le - base), c, vals.data())
                 ? 1
                 : 0;
    if (kind == 1) {
      if (c.pose != SensorPoseColumns::None && c.q_up >= 0)
        check_pose(text, static_cast<std::size_t>(p - base), c, vals.data());
      if (c.gravity_from_tilt) {
        const Eigen::Vector3d gt =
            tilted_gravity(c.level_gravity, Tilt{vals[c.tilt_value], vals[c.tilt_value + 1]});
        vals[g] = gt[0];
        vals[g + 1] = gt[1];
        vals[g + 2] = gt[2];
      } else if (c.gravity_from_force) {
        const double f0 = vals[w], f1 = vals[w + 1], f2 = vals[w + 2];
        const double n = std::sqrt(f0 * f0 + f1 * f1 + f2 * f2);
        if (!(n > 0.0)) throw_zero_force(text, static_cast<std::size_t>(p - base), c);
        vals[g] = c.g0 * f0 / n;  // paper eq. 37
        vals[g + 1] = c.g0 * f1 / n;
        vals[g + 2] = c.g0 * f2 / n;
      }
      if constexpr (std::is_invocable_v<Sink&, const double*, std::size_t, int>)
        sink(static_cast<const double*>(vals.data()), static_cast<std::size_t>(p - base),
             static_cast<int>(lines));
      else
        sink(static_cast<const double*>(vals.data()), static_cast<std::size_t>(p - base));
    }
    ++lines;
    if (nl == eof) break;
    p = nl + 1;
  }
  return lines;
}

}  // namespace massid::detail
