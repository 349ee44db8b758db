// Parsing of option values that CLI11 leaves as text: number lists, tilts,
// JOINT=VALUE pairs. Errors are InputError naming the option.
#pragma once

#include <CLI/CLI.hpp>
#include <Eigen/Core>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "massid/identify/estimation.hpp"
#include "massid/identify/setup_checks.hpp"
#include "massid/io/read_samples.hpp"

namespace massid::cli {

// A finite number, or InputError "OPTION: 'TEXT' is not a number".
double parse_number(const std::string& text, const std::string& option);

// "a,b,c" -> N numbers; `names` describes them in the message ("gx,gy,gz").
std::vector<double> parse_list(const std::string& text, size_t count, const std::string& option,
                               const std::string& names);
template <int N>
Eigen::Matrix<double, N, 1> parse_numbers(const std::string& text, const std::string& option,
                                          const std::string& names) {
  const std::vector<double> v = parse_list(text, N, option, names);
  return Eigen::Map<const Eigen::Matrix<double, N, 1>>(v.data());
}

// "NAME=VALUE" -> (NAME, VALUE text).
std::pair<std::string, std::string> parse_assignment(const std::string& text,
                                                     const std::string& option);

// --fixed JOINT=VALUE items -> (joint, position) pairs for hold_joints().
std::vector<std::pair<std::string, double>> parse_held(const std::vector<std::string>& items);

// --gravity gx,gy,gz on a command that reads a log (identify, predict,
// simulate, compensate): the level gravity in the sensor frame that tilt
// columns turn (SampleOptions::level_gravity). Its value: unset when empty.
void add_level_gravity_option(CLI::App* sub, std::string& value);
std::optional<Eigen::Vector3d> parse_level_gravity(const std::string& value);

// --columns ROLE=NAME[,ROLE=NAME...] (repeatable) on a command that reads a log.
void add_columns_option(CLI::App* sub, std::vector<std::string>& items);
// Its items -> the bindings (read_samples.hpp's ColumnNames); InputError for an
// item that is not ROLE=NAME.
ColumnNames parse_columns(const std::vector<std::string>& items);
// A column note (column_note, read_samples.hpp) on stderr, when there is one.
void print_column_note(const std::string& note);

// A number option validator with a readable message (CLI11's ranges print DBL_MAX in full).
CLI::Validator sign_check(bool positive);

// The set-up checks' findings (setup_checks.hpp) on stderr: with an error,
// every error on its own line and false (exit 2); else the warnings, true.
bool report_setup(const std::vector<SetupFinding>& findings);

// A file a command reads (simulate's plan, design --evaluate's plan): the
// library's verdict (check_input_setup, setup_checks.hpp) printed by
// report_setup. False after an error (exit 2).
bool check_input(const Model& model, const Samples& samples, const std::vector<std::string>& header,
                 bool motion);

}  // namespace massid::cli
