// What the model, simulate and predict commands share: --dynamic and its
// motion options, and a table written back with new columns.
#pragma once

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <string>
#include <utility>
#include <vector>

#include "massid/identify/motion_data.hpp"
#include "massid/io/csv.hpp"
#include "options.hpp"

namespace massid::cli {

// Appends (or overwrites) named numeric columns of a table, for writing.
struct OutputTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;

  explicit OutputTable(const CsvTable& in) : header(in.header), rows(in.rows) {}
  void set_column(const std::string& name, const Eigen::VectorXd& values) {
    int c = -1;
    for (size_t i = 0; i < header.size(); ++i)
      if (header[i] == name) c = static_cast<int>(i);
    if (c < 0) {
      header.push_back(name);
      for (auto& r : rows) r.emplace_back();
      c = static_cast<int>(header.size()) - 1;
    }
    for (size_t r = 0; r < rows.size(); ++r) rows[r][c] = format_number(values[r]);
  }
};

// --dynamic and its motion options (model, simulate, identify, predict).
struct MotionFlags {
  bool dynamic = false;
  double cutoff = 0.0;                    // --cutoff HZ (0: the default for the log's rate)
  std::string root_gravity;               // --root-gravity gx,gy,gz
  std::string level_gravity;              // predict, simulate: --gravity gx,gy,gz
  std::string gravity_model = "varying";  // model --dynamic: --gravity-model level|varying
  bool sensor_moving = false;             // model --dynamic --moving-sensor
  bool sensor_at_rest = false;            // model --dynamic --sensor-at-rest
  // The same options for `python -m massid.report predict`.
  std::vector<std::string> report_args() const {
    std::vector<std::string> a;
    if (cutoff > 0) a.insert(a.end(), {"--cutoff", format_number(cutoff)});
    if (!root_gravity.empty()) a.insert(a.end(), {"--root-gravity", root_gravity});
    if (!level_gravity.empty()) a.insert(a.end(), {"--gravity", level_gravity});
    return a;
  }
  MotionDataOptions data() const {
    MotionDataOptions o;
    o.filter.cutoff = cutoff;
    if (!root_gravity.empty())
      o.samples.root_gravity = parse_numbers<3>(root_gravity, "--root-gravity", "gx,gy,gz");
    o.samples.level_gravity = parse_level_gravity(level_gravity);
    return o;
  }
};

// --dynamic, --root-gravity and (with `filter`) --cutoff on a subcommand.
inline void add_motion_options(CLI::App* sub, MotionFlags& motion, bool filter) {
  sub->add_flag("--dynamic", motion.dynamic,
                "Motion: the full wrench (weight and motion) over ten parameters per link");
  sub->add_option("--root-gravity", motion.root_gravity,
                  "Gravity in the URDF root frame, gx,gy,gz (default 0,0,-9.80665): with "
                  "--sensor below movable joints whose columns the file has");
  if (filter)
    sub->add_option("--cutoff", motion.cutoff,
                    "Motion log without JOINT_vel/_acc: zero-phase low-pass cutoff, Hz, for the "
                    "derivatives and the wrench alike (default: min(10, rate/20))")
        ->check(CLI::PositiveNumber);
}

}  // namespace massid::cli
