#include "massid/identify/predict_log.hpp"

#include <fmt/format.h>

#include <utility>

#include "massid/identify/delay.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {

namespace {

// The rows of `table` at the given file lines (in order).
CsvTable keep_lines(CsvTable table, const std::vector<int>& lines) {
  size_t k = 0;
  for (int r = 0; r < table.num_rows() && k < lines.size(); ++r)
    if (table.line[r] == lines[k]) {
      std::swap(table.rows[k], table.rows[r]);  // (k <= r)
      table.line[k++] = table.line[r];
    }
  table.rows.resize(k);
  table.line.resize(k);
  table.column_offset.clear();
  return table;
}

}  // namespace

LogPrediction predict_log(const IdentifiedModel& identified, CsvTable table,
                          const std::string& source, const PredictLogOptions& options) {
  LogPrediction out;
  out.source = source;
  const bool motion = identified.dynamic();
  SampleOptions read = options.motion.samples;
  // The sensor's pose from columns, when the header has them.
  const Model model =
      with_pose_columns(identified.model(), table.header,
                        fmt::format("{}:{}", table.source, table.header_line), read);
  read.sensor_motion = motion;  // a static prediction ignores a partial wx..az (an IMU's ax..az)
  out.column_note =
      column_note(model, table.header, fmt::format("{}:{}", table.source, table.header_line),
                  WrenchColumns::Optional, read);
  Samples samples = read_samples(model, table, WrenchColumns::Optional, read);
  if (options.checks) {
    out.setup = check_input_setup(model, samples, column_roles(model, table.header, read), motion);
    if (options.on_verdict) options.on_verdict(out.setup);
    if (out.setup.refused()) throw SetupRefused(out.setup.shown());
  }
  // The clock delay, before the filter, as identify applied it.
  std::string delay_note;
  samples =
      delay_joint_stream(std::move(samples), identified.delay(), identified.source(), &delay_note);
  if (!delay_note.empty()) out.notes.push_back(delay_note);
  if (motion) {
    // The full wrench, weight and motion, from the dynamic base parameters.
    MotionDataOptions mopts = options.motion;
    mopts.samples = read;
    mopts.filter.decimation = 1;  // a prediction for every row the filter keeps
    samples = prepare_motion_samples(model, std::move(samples), mopts, &out.motion);
    if (out.motion.derived) table = keep_lines(std::move(table), samples.line);
  }
  // The mechanism's wrench alone (_pred); what the sensor reads adds the offset.
  IdentifiedModelData data(identified);
  out.predicted = identified.predict_samples(data, samples);
  if (samples.has_wrench()) {
    out.compensated = identified.compensate_rows(samples.wrench, out.predicted);
    // Rows that carry an external wrench (contact), against what the sensor reads.
    const Eigen::MatrixXd reading = identified.sensor_reading_rows(out.predicted);
    if (samples.size() >= 2)
      out.contact = find_contact_episodes(samples, samples.wrench - reading, options.contact);
    for (const ContactEpisode& e : out.contact) out.notes.push_back(contact_note(source, e));
  }
  out.samples = std::move(samples);
  out.table = std::move(table);
  return out;
}

}  // namespace massid
