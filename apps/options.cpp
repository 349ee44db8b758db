#include "options.hpp"

#include <fmt/format.h>

#include <cmath>
#include <iostream>

#include "hints.hpp"
#include "massid/core/errors.hpp"

namespace massid::cli {

namespace {
bool to_number(const std::string& text, double& value) {
  size_t used = 0;
  try {
    value = std::stod(text, &used);
  } catch (const std::exception&) {
    return false;
  }
  return used > 0 && used == text.size() && std::isfinite(value);
}
}  // namespace

double parse_number(const std::string& text, const std::string& option) {
  double v = 0.0;
  if (!to_number(text, v)) throw InputError(fmt::format("{}: '{}' is not a number", option, text));
  return v;
}

std::vector<double> parse_list(const std::string& text, size_t count, const std::string& option,
                               const std::string& names) {
  std::vector<double> out;
  size_t start = 0;
  while (true) {
    const size_t comma = text.find(',', start);
    const std::string cell = text.substr(start, comma == std::string::npos ? comma : comma - start);
    double v = 0.0;
    if (!to_number(cell, v))
      throw InputError(fmt::format("{}: '{}' is not a number (expected {})", option, cell, names));
    out.push_back(v);
    if (comma == std::string::npos) break;
    start = comma + 1;
  }
  if (out.size() != count)
    throw InputError(fmt::format("{}: expected {} comma-separated numbers {}, got {}", option,
                                 count, names, out.size()));
  return out;
}

std::pair<std::string, std::string> parse_assignment(const std::string& text,
                                                     const std::string& option) {
  const size_t eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size())
    throw InputError(fmt::format("{}: '{}' should read JOINT=VALUE", option, text));
  return {text.substr(0, eq), text.substr(eq + 1)};
}

std::vector<std::pair<std::string, double>> parse_held(const std::vector<std::string>& items) {
  std::vector<std::pair<std::string, double>> held;
  for (const std::string& item : items) {
    const auto [joint, value] = parse_assignment(item, "--fixed");
    held.emplace_back(joint, parse_number(value, "--fixed " + joint));
  }
  return held;
}

void add_level_gravity_option(CLI::App* sub, std::string& value) {
  sub->add_option("--gravity", value,
                  "Gravity in the sensor frame with the platform level, gx,gy,gz, turned by the "
                  "tilt_x_deg,tilt_y_deg columns of a log without gx,gy,gz (default: "
                  "--root-gravity through the fixed joints above the sensor link)");
}

std::optional<Eigen::Vector3d> parse_level_gravity(const std::string& value) {
  if (value.empty()) return std::nullopt;
  return parse_numbers<3>(value, "--gravity", "gx,gy,gz");
}

void add_columns_option(CLI::App* sub, std::vector<std::string>& items) {
  sub->add_option(
         "--columns", items,
         "Read columns of other names as roles: ROLE=NAME,... (e.g. mx=tx,my=ty,mz=tz; "
         "roles fx..mz, gx..gz, t, block, wx..az, dwx..dwz, tilt_x_deg, tilt_y_deg, "
         "JOINT, JOINT_deg, JOINT_vel, JOINT_acc, JOINT_deg_vel, JOINT_deg_acc); repeatable")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
}

ColumnNames parse_columns(const std::vector<std::string>& items) {
  ColumnNames names;
  for (const std::string& item : items) {
    size_t start = 0;
    while (start <= item.size()) {
      const size_t comma = item.find(',', start);
      const std::string pair =
          item.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      const size_t eq = pair.find('=');
      if (eq == std::string::npos || eq == 0 || eq + 1 == pair.size())
        throw InputError(fmt::format(
            "--columns: '{}' should read ROLE=NAME (e.g. --columns mx=tx,my=ty,mz=tz)", pair));
      names.bind.emplace_back(pair.substr(0, eq), pair.substr(eq + 1));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  return names;
}

void print_column_note(const std::string& note) {
  if (!note.empty()) std::cerr << "massid: note: " << note << "\n";
}

CLI::Validator sign_check(bool positive) {
  return CLI::Validator(
      [positive](std::string& text) -> std::string {
        double v = 0.0;
        if (to_number(text, v) && (positive ? v > 0 : v >= 0)) return "";
        return fmt::format("'{}' is not a {} number", text, positive ? "positive" : "non-negative");
      },
      positive ? "POSITIVE" : "NONNEGATIVE");
}

bool report_setup(const std::vector<SetupFinding>& findings) {
  const bool error = has_error(findings);
  for (const SetupFinding& f : findings)
    if (error == (f.severity == SetupFinding::Severity::Error))
      std::cerr << (error ? "massid: error: " : "massid: warning: ")
                << cli::with_hints(f.message, f.hints) << "\n";
  return !error;
}

bool check_input(const Model& model, const Samples& samples, const std::vector<std::string>& header,
                 bool motion) {
  return report_setup(check_input_setup(model, samples, header, motion).findings);
}

}  // namespace massid::cli
