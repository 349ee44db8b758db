#include "io/csv_stream.hpp"

#include <fcntl.h>
#include <fmt/format.h>
#include <sys/mman.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>

#include "io/column_map.hpp"
#include "io/csv_fields.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/samples.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"

namespace massid::detail {

MappedFile::MappedFile(const std::string& path) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  struct stat st {};
  bool ok = fd >= 0 && ::fstat(fd, &st) == 0 && S_ISREG(st.st_mode);
  size_ = ok ? static_cast<size_t>(st.st_size) : 0;
  if (ok && size_ > 0) {
    void* p = ::mmap(nullptr, size_, PROT_READ, MAP_PRIVATE, fd, 0);
    ok = p != MAP_FAILED;
    if (ok) data_ = static_cast<const char*>(p);
  }
  if (fd >= 0) ::close(fd);
  if (!ok) throw InputError(fmt::format("{}: cannot open file", path));
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

void read_header(std::string_view text, const std::string& source, SampleColumns& c) {
  c.source = source;
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
    check_header(fields, offsets, source, line_no);
    c.header = fields;
    c.header_line = line_no;
    c.data_begin = pos;
    break;
  }
  if (c.header.empty()) throw InputError(fmt::format("{}:1:1: empty file, no header row", source));
}

SampleColumns bind_columns(const Model& model, std::string_view text, const std::string& source,
                           const SampleOptions& options, bool motion) {
  SampleColumns c;
  read_header(text, source, c);
  // read_csv's check: at least one data row. (Rows are checked in full later;
  // a malformed row is reported when it is reached.)
  bool any = false;
  std::string_view line;
  for (size_t p = c.data_begin; p < text.size() && !any;) {
    p = next_line(text, p, line);
    const std::string_view content = trim(line);
    any = !content.empty() && content.front() != '#';
  }
  if (!any)
    throw InputError(fmt::format("{}:{}:1: header but no data rows", source, c.header_line));
  return bind_header(model, std::move(c), options, motion);
}

SampleColumns bind_header(const Model& model, SampleColumns c, const SampleOptions& options,
                          bool motion) {
  c.g0 = options.g0;
  c.root_gravity = options.root_gravity;
  // The one binding (column_map.hpp): every header error, read_samples' messages.
  const std::string where = fmt::format("{}:{}", c.source, c.header_line);
  const ColumnMap map =
      map_columns(model, c.header, where, WrenchColumns::Required, options.columns, motion);
  c.level_gravity = level_gravity_of(model, map.gravity_from, options, where);
  c.note = map.note;
  c.roles = map.roles;
  c.num_joints = model.num_joints();
  c.num_upstream = model.num_upstream_joints();
  c.motion = motion;
  c.gravity_from_upstream = map.gravity_from == GravityFrom::UpstreamJoints;
  c.gravity_from_force = map.gravity_from == GravityFrom::Force;
  c.pose = model.pose;

  // Values, in read_samples' order of groups.
  c.target.assign(c.header.size(), -1);
  c.scale.assign(c.header.size(), 1.0);
  int next = 0;
  std::vector<BoundColumn> column_at;  // per value: its column (-1: computed) and scale
  const auto group = [&](const ColumnGroup& cols) {
    if (cols.empty()) return -1;
    const int first = next;
    column_at.insert(column_at.end(), cols.begin(), cols.end());
    next += static_cast<int>(cols.size());
    return first;
  };
  const auto single = [](int column) {
    return column >= 0 ? ColumnGroup{{column, 1.0}} : ColumnGroup{};
  };
  group(map.q);
  if (motion) {
    c.qd = group(map.qd);
    c.qdd = group(map.qdd);
    c.sensor = group(map.sensor_motion);
  }
  if (motion || c.gravity_from_upstream) c.q_up = group(map.q_upstream);
  if (motion) {
    c.qd_up = group(map.qd_upstream);
    c.qdd_up = group(map.qdd_upstream);
  }
  c.wrench = group(map.wrench);
  if (motion) {
    c.time = group(single(map.time));
    c.block = group(single(map.block));
  }
  c.gravity = next;
  if (!map.gravity.empty()) {
    group(map.gravity);
  } else {
    group(ColumnGroup(3));  // computed
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
  if (map.gravity_from == GravityFrom::Tilt) {  // the two tilts, after every group
    c.gravity_from_tilt = true;
    c.tilt_value = bind_value(c, map.tilt[0].column, map.tilt[0].scale);
    bind_value(c, map.tilt[1].column, map.tilt[1].scale);
  }
  return c;
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
  check_row_width(line, offsets, c.header.size(), c.source, line_no);
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

Samples read_file_samples(const Model& model, const std::string& path, int max_rows,
                          const SampleOptions& read, std::vector<std::string>* header,
                          bool motion) {
  const MappedFile file(path);
  const std::string_view text = file.text();
  const SampleColumns cols = bind_columns(model, text, path, read, motion);
  if (header) *header = cols.roles;
  const int nj = model.num_joints(), nu = model.num_upstream_joints(), w = cols.wrench_value();
  const size_t limit = static_cast<size_t>(std::max(1, max_rows));
  std::vector<double> q, g, wrench, t;
  // Motion: the velocities and accelerations of the joints, then of the upstream joints.
  std::vector<double> qd, qdd, q_up, qd_up, qdd_up;
  std::vector<int> line;
  struct Enough {};  // max_rows read: the lines after are not parsed
  try {
    parse_block(text, cols, cols.data_begin, text.size(), [&](const double* v, size_t, int l) {
      q.insert(q.end(), v, v + nj);
      if (cols.qd >= 0) {
        qd.insert(qd.end(), v + cols.qd, v + cols.qd + nj);
        qdd.insert(qdd.end(), v + cols.qdd, v + cols.qdd + nj);
      }
      if (motion && cols.q_up >= 0) q_up.insert(q_up.end(), v + cols.q_up, v + cols.q_up + nu);
      if (cols.qd_up >= 0) {
        qd_up.insert(qd_up.end(), v + cols.qd_up, v + cols.qd_up + nu);
        qdd_up.insert(qdd_up.end(), v + cols.qdd_up, v + cols.qdd_up + nu);
      }
      if (cols.time >= 0) t.push_back(v[cols.time]);
      const size_t at = g.size();
      g.resize(at + 3);
      if (cols.gravity_from_upstream)
        upstream_sensor_frame(model, v + cols.q_up, nullptr, nullptr, cols.root_gravity,
                              g.data() + at, nullptr);
      else
        std::copy_n(v + cols.gravity_value(), 3, g.data() + at);
      wrench.insert(wrench.end(), v + w, v + w + 6);
      line.push_back(cols.header_line + 1 + l);
      if (line.size() == limit) throw Enough{};
    });
  } catch (const Enough&) {
  }
  using RowMajor = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;
  const Eigen::Index n = static_cast<Eigen::Index>(line.size());
  Samples s;
  s.source = path;
  s.gravity_from_force = cols.gravity_from_force;
  s.gravity_from_upstream = cols.gravity_from_upstream;
  s.root_gravity = read.root_gravity;
  s.q = Eigen::Map<const RowMajor>(q.data(), n, nj);
  s.gravity = Eigen::Map<const RowMajor>(g.data(), n, 3);
  s.wrench = Eigen::Map<const RowMajor>(wrench.data(), n, 6);
  if (cols.qd >= 0) {
    s.qd = Eigen::Map<const RowMajor>(qd.data(), n, nj);
    s.qdd = Eigen::Map<const RowMajor>(qdd.data(), n, nj);
  }
  if (motion && cols.q_up >= 0) s.q_upstream = Eigen::Map<const RowMajor>(q_up.data(), n, nu);
  if (cols.qd_up >= 0) {
    s.qd_upstream = Eigen::Map<const RowMajor>(qd_up.data(), n, nu);
    s.qdd_upstream = Eigen::Map<const RowMajor>(qdd_up.data(), n, nu);
  }
  if (cols.time >= 0) s.time = Eigen::Map<const Eigen::VectorXd>(t.data(), n);
  s.line = std::move(line);
  return s;
}

void check_pose_line(const SampleColumns& c, int line_no, double* vals) {
  const std::string why = normalise_pose(c.pose, c.num_upstream, vals + c.q_up);
  if (!why.empty()) throw InputError(fmt::format("{}:{}: {}", c.source, line_no, why));
}

void check_pose(std::string_view text, size_t line_begin, const SampleColumns& c, double* vals) {
  const std::string why = normalise_pose(c.pose, c.num_upstream, vals + c.q_up);
  if (!why.empty())  // the line's number counted only then
    throw InputError(fmt::format("{}:{}: {}", c.source, line_number(text, line_begin), why));
}

void throw_zero_force(const std::string& where) {
  throw InputError(
      fmt::format("{}: zero force: no gx,gy,gz columns and no force to take "
                  "the gravity direction from",
                  where));
}

void throw_zero_force(std::string_view text, size_t line_begin, const SampleColumns& c) {
  throw_zero_force(fmt::format("{}:{}", c.source, line_number(text, line_begin)));
}

}  // namespace massid::detail
