#include "csv_stream.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <numbers>

#include "csv_fields.hpp"
#include "massid/csv.hpp"
#include "massid/errors.hpp"
#include "massid/samples.hpp"

namespace massid::detail {
namespace {

// CsvTable::number for one cell.
double cell_number(const std::string& cell, const std::string& source, int line, int column,
                   const std::string& name) {
  double value = 0.0;
  const char* first = cell.data();
  const char* last = first + cell.size();
  if (!cell.empty() && *first == '+') ++first;
  auto result = fast_float::from_chars(first, last, value);
  auto where = [&] { return fmt::format("{}:{}:{}: column '{}'", source, line, column, name); };
  if (cell.empty()) throw InputError(where() + ": empty cell, a number is expected");
  if (result.ec != std::errc() || result.ptr != last)
    throw InputError(fmt::format("{}: '{}' is not a number", where(), cell));
  if (!std::isfinite(value))
    throw InputError(fmt::format("{}: '{}' is not a finite number", where(), cell));
  return value;
}

int find(const std::vector<std::string>& header, const std::string& name) {
  for (size_t i = 0; i < header.size(); ++i)
    if (header[i] == name) return static_cast<int>(i);
  return -1;
}

// column_group of samples.cpp.
std::vector<int> column_group(const SampleColumns& c, std::initializer_list<const char*> names) {
  std::vector<int> idx;
  std::vector<std::string> missing;
  for (const char* n : names) {
    idx.push_back(find(c.header, n));
    if (idx.back() < 0) missing.push_back(n);
  }
  const size_t found = std::count_if(idx.begin(), idx.end(), [](int i) { return i >= 0; });
  if (found == 0) return {};
  if (found < idx.size())
    throw InputError(fmt::format(
        "{}:{}: column(s) {} missing (the header has some of {} but not all)", c.source,
        c.header_line, fmt::join(missing, ","), fmt::join(names.begin(), names.end(), ",")));
  return idx;
}

// Next line [begin, line_end) from pos; returns the position after it.
size_t next_line(std::string_view text, size_t pos, std::string_view& line) {
  const size_t nl = text.find('\n', pos);
  const size_t end = nl == std::string_view::npos ? text.size() : nl;
  line = text.substr(pos, end - pos);
  if (!line.empty() && line.back() == '\r') line.remove_suffix(1);
  return nl == std::string_view::npos ? text.size() : nl + 1;
}

}  // namespace

MappedFile::MappedFile(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) throw InputError(fmt::format("{}: cannot open file", path));
  struct stat st {};
  if (::fstat(fd, &st) != 0 || !S_ISREG(st.st_mode)) {
    ::close(fd);
    throw InputError(fmt::format("{}: cannot open file", path));
  }
  size_ = static_cast<size_t>(st.st_size);
  if (size_ > 0) {
    void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
    if (p == MAP_FAILED) {
      ::close(fd);
      throw InputError(fmt::format("{}: cannot open file", path));
    }
    data_ = static_cast<const char*>(p);
  }
  ::close(fd);
}

MappedFile::~MappedFile() {
  if (data_) ::munmap(const_cast<char*>(data_), size_);
}

void MappedFile::release(size_t begin, size_t end) const {
  if (!data_) return;
  const size_t page = static_cast<size_t>(::sysconf(_SC_PAGESIZE));
  const size_t first = (begin + page - 1) / page * page;
  const size_t last = std::min(end, size_) / page * page;
  if (last > first) ::madvise(const_cast<char*>(data_) + first, last - first, MADV_DONTNEED);
}

int line_number(std::string_view text, size_t pos) {
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + pos, '\n'));
}

namespace {

// bind_columns, and with require_rows false bind_header.
SampleColumns bind(const Model& model, std::string_view text, const std::string& source, double g0,
                   bool motion, bool require_rows) {
  SampleColumns c;
  c.source = source;
  c.g0 = g0;
  size_t pos = text.substr(0, 3) == "\xEF\xBB\xBF" ? 3 : 0;  // UTF-8 BOM
  int line_no = 0;
  std::vector<std::string> fields;
  std::vector<int> offsets;
  std::string_view line;
  while (pos < text.size()) {
    pos = next_line(text, pos, line);
    ++line_no;
    const std::string_view content = trim(line);
    if (content.empty() || content.front() == '#') continue;
    split(line, source, line_no, fields, offsets);
    for (size_t i = 0; i < fields.size(); ++i) {
      if (fields[i].empty())
        throw InputError(
            fmt::format("{}:{}:{}: empty column name in the header", source, line_no, offsets[i]));
      for (size_t d = 0; d < i; ++d)
        if (fields[d] == fields[i])
          throw InputError(fmt::format("{}:{}:{}: column '{}' appears twice in the header", source,
                                       line_no, offsets[i], fields[i]));
    }
    c.header = fields;
    c.header_line = line_no;
    c.data_begin = pos;
    break;
  }
  if (c.header.empty()) throw InputError(fmt::format("{}:1:1: empty file, no header row", source));
  // read_csv's check: at least one data row. (Rows are checked in full later;
  // a malformed row is reported when it is reached.)
  bool any = !require_rows;
  for (size_t p = c.data_begin; p < text.size() && !any;) {
    p = next_line(text, p, line);
    const std::string_view content = trim(line);
    any = !content.empty() && content.front() != '#';
  }
  if (!any)
    throw InputError(fmt::format("{}:{}:1: header but no data rows", source, c.header_line));

  // The groups of read_samples (samples.cpp), in its order, with its rules and messages.
  const int nj = model.num_joints(), nu = model.num_upstream_joints();
  c.num_joints = nj;
  c.num_upstream = nu;
  c.motion = motion;
  const std::string where = fmt::format("{}:{}", source, c.header_line);
  // Joint positions (read_joint_columns): by name, or JOINT_deg in degrees.
  struct Bound {
    int column;
    double scale;
  };
  const auto positions = [&](const std::vector<Joint>& joints) {
    std::vector<Bound> out;
    for (const Joint& joint : joints) {
      int col = find(c.header, joint.name);
      double scale = 1.0;
      if (col < 0 && joint.type == JointType::Revolute) {
        col = find(c.header, joint.name + "_deg");
        scale = std::numbers::pi / 180.0;
      }
      if (col < 0)
        throw InputError(fmt::format(
            "{}: no column for joint '{}' (expected '{}'{})", where, joint.name, joint.name,
            joint.type == JointType::Revolute ? fmt::format(" or '{}_deg'", joint.name) : ""));
      out.push_back({col, scale});
    }
    return out;
  };
  // NAME + suffix for every joint, or none (optional_joint_columns).
  const auto suffixed = [&](const std::vector<Joint>& joints, const char* suffix) {
    std::vector<Bound> out;
    std::vector<std::string> missing;
    for (const Joint& j : joints) {
      const int col = find(c.header, j.name + suffix);
      if (col < 0) missing.push_back(j.name + suffix);
      out.push_back({col, 1.0});
    }
    if (missing.size() == joints.size()) return std::vector<Bound>{};
    if (!missing.empty())
      throw InputError(
          fmt::format("{}: column(s) {} missing (the header has {} columns for some "
                      "joints but not all)",
                      where, fmt::join(missing, ","), suffix));
    return out;
  };
  const std::vector<Bound> q = positions(model.joints);
  std::vector<Bound> qd = suffixed(model.joints, "_vel"), qdd = suffixed(model.joints, "_acc");
  if (qd.size() != qdd.size())
    throw InputError(
        fmt::format("{}: the header has joint {} columns but no {} columns: give "
                    "both, or neither (derived from t and the positions)",
                    where, qd.size() ? "_vel" : "_acc", qd.size() ? "_acc" : "_vel"));
  const std::vector<int> sm =
      column_group(c, {"wx", "wy", "wz", "dwx", "dwy", "dwz", "ax", "ay", "az"});
  // Joints above the sensor link: all or none (optional_positions), with their _vel/_acc.
  std::vector<Bound> qu, qdu, qddu;
  {
    size_t found = 0;
    for (const Joint& j : model.upstream_joints)
      if (find(c.header, j.name) >= 0 || find(c.header, j.name + "_deg") >= 0) ++found;
    if (found > 0) {
      qu = positions(model.upstream_joints);
      qdu = suffixed(model.upstream_joints, "_vel");
      qddu = suffixed(model.upstream_joints, "_acc");
      if (qdu.size() != qddu.size())
        throw InputError(
            fmt::format("{}: the upstream joints have _vel or _acc columns but not both", where));
    }
  }
  const std::vector<int> w = column_group(c, {"fx", "fy", "fz", "mx", "my", "mz"});
  if (w.empty())
    throw InputError(
        fmt::format("{}: no measured wrench: the columns fx,fy,fz,mx,my,mz are needed", where));
  const int t = find(c.header, "t"), block = find(c.header, "block");
  const std::vector<int> g = column_group(c, {"gx", "gy", "gz"});
  c.gravity_from_upstream = g.empty() && !qu.empty();
  c.gravity_from_force = g.empty() && qu.empty();

  // Values, in read_samples' order of groups.
  c.target.assign(c.header.size(), -1);
  c.scale.assign(c.header.size(), 1.0);
  int next = 0;
  std::vector<std::pair<int, double>> column_at;  // per value: column, scale
  const auto group = [&](const std::vector<Bound>& cols) {
    if (cols.empty()) return -1;
    const int first = next;
    for (const Bound& b : cols) {
      column_at.push_back({b.column, b.scale});
      ++next;
    }
    return first;
  };
  const auto plain = [](const std::vector<int>& cols) {
    std::vector<Bound> out;
    for (int col : cols) out.push_back({col, 1.0});
    return out;
  };
  group(q);
  if (motion) {
    c.qd = group(qd);
    c.qdd = group(qdd);
    c.sensor = group(plain(sm));
  }
  if (motion || c.gravity_from_upstream) c.q_up = group(qu);
  if (motion) {
    c.qd_up = group(qdu);
    c.qdd_up = group(qddu);
  }
  c.wrench = group(plain(w));
  if (motion) {
    c.time = group(t >= 0 ? std::vector<Bound>{{t, 1.0}} : std::vector<Bound>{});
    c.block = group(block >= 0 ? std::vector<Bound>{{block, 1.0}} : std::vector<Bound>{});
  }
  c.gravity = next;
  if (!g.empty()) {
    group(plain(g));
  } else {
    for (int k = 0; k < 3; ++k) column_at.push_back({-1, 1.0});  // computed
    next += 3;
  }
  c.num_values = next;
  c.column_of.assign(c.num_values, -1);
  for (int v = 0; v < c.num_values; ++v) {
    const auto [col, scale] = column_at[v];
    if (col < 0) continue;
    c.target[col] = v;
    c.scale[col] = scale;
    c.column_of[v] = col;
  }
  return c;
}

}  // namespace

SampleColumns bind_columns(const Model& model, std::string_view text, const std::string& source,
                           double g0, bool motion) {
  return bind(model, text, source, g0, motion, true);
}

SampleColumns bind_header(const Model& model, std::string_view text, const std::string& source,
                          double g0, bool motion) {
  return bind(model, text, source, g0, motion, false);
}

int bind_value(SampleColumns& c, int column, double scale) {
  c.target[column] = c.num_values;
  c.scale[column] = scale;
  c.column_of.push_back(column);
  return c.num_values++;
}

size_t num_blocks(std::string_view text, const SampleColumns& c, size_t block_bytes) {
  const size_t n = text.size() > c.data_begin ? text.size() - c.data_begin : 0;
  return (n + block_bytes - 1) / block_bytes;
}

std::pair<size_t, size_t> block_range(std::string_view text, const SampleColumns& c,
                                      size_t block_bytes, size_t k) {
  // First line start at or after x (x itself when the byte before is a '\n').
  auto line_start = [&](size_t x) -> size_t {
    if (x <= c.data_begin) return c.data_begin;
    if (x >= text.size()) return text.size();
    const size_t nl = text.find('\n', x - 1);
    return nl == std::string_view::npos ? text.size() : nl + 1;
  };
  return {line_start(c.data_begin + k * block_bytes),
          line_start(c.data_begin + (k + 1) * block_bytes)};
}

bool parse_line_slow(std::string_view text, size_t line_begin, size_t line_end,
                     const SampleColumns& c, double* vals) {
  const std::string_view line = text.substr(line_begin, line_end - line_begin);
  const std::string_view content = trim(line);
  if (content.empty() || content.front() == '#') return false;
  return parse_row_slow(line, line_number(text, line_begin), c, vals);
}

bool parse_row_slow(std::string_view line, int line_no, const SampleColumns& c, double* vals) {
  const std::string_view content = trim(line);
  if (content.empty() || content.front() == '#') return false;
  std::vector<std::string> fields;
  std::vector<int> offsets;
  split(line, c.source, line_no, fields, offsets);
  if (fields.size() != c.header.size())
    throw InputError(
        fmt::format("{}:{}:{}: row has {} fields, the header has {}", c.source, line_no,
                    fields.size() < c.header.size() ? line.size() + 1 : offsets[c.header.size()],
                    fields.size(), c.header.size()));
  // Values in read_samples' order: joints, wrench, gravity.
  for (int t = 0; t < c.num_values; ++t) {
    const int col = c.column_of[t];
    if (col < 0) continue;
    const double x = cell_number(fields[col], c.source, line_no, offsets[col], c.header[col]);
    vals[t] = c.scale[col] == 1.0 ? x : c.scale[col] * x;
  }
  return true;
}

void throw_not_integer(std::string_view text, size_t line_begin, const SampleColumns& c,
                       double value) {
  size_t end = text.find('\n', line_begin);
  if (end == std::string_view::npos) end = text.size();
  if (end > line_begin && text[end - 1] == '\r') --end;
  const int line_no = line_number(text, line_begin);
  std::vector<std::string> fields;
  std::vector<int> offsets;
  split(text.substr(line_begin, end - line_begin), c.source, line_no, fields, offsets);
  const int col = c.column_of[c.block];
  throw InputError(fmt::format("{}:{}:{}: column '{}': '{}' is not an integer", c.source, line_no,
                               offsets[col], c.header[col], format_number(value)));
}

void throw_zero_force(std::string_view text, size_t line_begin, const SampleColumns& c) {
  throw InputError(
      fmt::format("{}:{}: zero force: no gx,gy,gz columns and no force to take "
                  "the gravity direction from",
                  c.source, line_number(text, line_begin)));
}

}  // namespace massid::detail
