#include "identify/identify_file.hpp"

#include <climits>
#include <filesystem>
#include <stdexcept>

#include "io/csv_stream.hpp"
#include "massid/identify/rest_windows.hpp"
#include "massid/identify/setup_checks.hpp"
#include "massid/identify/streaming.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {

namespace {

// A streamed log whose largest residuals are implausible is re-read whole to
// name its samples when it is at most 64 MB (about 250 000 rows; the dense fit
// then needs a few hundred MB, and only then).
bool small_enough_to_name_samples(const std::string& path, std::uintmax_t limit = 64u << 20) {
  std::error_code ec;
  const auto size = std::filesystem::file_size(path, ec);
  return !ec && size <= limit;
}

// A plain streamed fit looks for contact (rows an external wrench drives)
// in logs up to 8 MB (about 30 000 rows): reading one whole costs about as
// much again as the streamed fit there, and far more above (use --robust).
constexpr std::uintmax_t kContactScanBytes = 8u << 20;

// A log recorded while the robot moved from pose to pose: its head (the
// first kContinuousHeadRows rows) has moving rows (rest_windows.hpp).
constexpr int kContinuousHeadRows = 20000;
bool continuous_log(const Model& model, const std::string& path, const RestWindowOptions& o,
                    const SampleOptions& read) {
  if (o.detection == RestDetection::Off) return false;
  return find_rest_windows(detail::read_file_samples(model, path, kContinuousHeadRows, read), o)
      .continuous;
}

}  // namespace

IdentifySummary identify_at_rest(const Model& model, const BaseParameters& base, Samples all,
                                 const IdentifyOptions& options, Samples* samples) {
  const RestWindows windows = find_rest_windows(model, all, options.rest);
  Samples s = windows.continuous ? rest_samples(all, windows) : std::move(all);
  IdentifySummary summary = identify(model, base, s, options);
  summary.rest = windows;
  if (samples) *samples = std::move(s);
  return summary;
}

IdentifySummary identify_file(const Model& model, const BaseParameters& base,
                              const std::string& path, const IdentifyOptions& options,
                              Samples* samples, const SampleOptions& read) {
  const auto in_memory = [&] {
    return identify_at_rest(model, base,
                            read_samples(model, read_csv(path), WrenchColumns::Required, read),
                            options, samples);
  };
  if (options.robust || options.drift != Drift::None) return in_memory();   // iterated fits
  if (continuous_log(model, path, options.rest, read)) return in_memory();  // rest windows
  // Streamed from the memory-mapped file in constant memory: the same results
  // as identify() on read_samples of the whole file.
  const StreamOptions stream;
  const IdentifyAccumulator acc = accumulate_csv(model, base, path, stream, read);
  IdentifySummary summary = acc.finish(options);
  if (summary.residual_max.hasNaN())  // not proven in the first pass: a second one
    summary.residual_max = residual_max_csv(model, base, path, summary.value, stream, read);
  // Implausible residuals: the in-memory fit (the same estimate) names the samples.
  if (largest_residuals_implausible(summary) && small_enough_to_name_samples(path))
    return in_memory();
  const bool contact_scan = small_enough_to_name_samples(path, kContactScanBytes);
  if (contact_scan || samples) {
    Samples all = detail::read_file_samples(model, path, INT_MAX, read);
    // The rows an external wrench drives hide from the outlier test when they
    // inflate the fitted noise: judged as predict judges them, from the
    // residuals of the samples read whole (as the in-memory fit).
    if (contact_scan && all.size() >= 2 && !all.gravity_from_force)
      summary.beyond_noise =
          rows_beyond_noise(all, all.wrench - fitted_wrenches(model, base, all, summary),
                            &summary.beyond_noise_threshold);
    if (samples) *samples = std::move(all);
  }
  return summary;
}

IdentifySummary identify_motion_file(const Model& model, const std::string& path, bool offset,
                                     const IdentifyOptions& options, const MotionDataOptions& data,
                                     BaseParameters* base, MotionDataReport* report,
                                     Samples* head) {
  if (!base) throw std::invalid_argument("identify_motion_file: base is required");
  const auto in_memory = [&] {
    MotionDataReport r;
    Samples s = read_motion_samples(model, path, WrenchColumns::Required, data, &r);
    *base = find_base_parameters(model, motion_base_options(s, offset));
    IdentifySummary summary = identify(model, *base, s, options);
    if (report) *report = r;
    if (head) *head = std::move(s);
    return summary;
  };
  if (options.robust || options.drift != Drift::None) return in_memory();  // iterated fits
  MotionIdentification m = identify_motion_csv(model, path, offset, options, data);
  // Implausible residuals: the in-memory fit (the same estimate) names the samples.
  if (largest_residuals_implausible(m.summary) && small_enough_to_name_samples(path))
    return in_memory();
  *base = std::move(m.base);
  if (report) *report = m.report;
  if (head) *head = std::move(m.head);
  return m.summary;
}

}  // namespace massid
