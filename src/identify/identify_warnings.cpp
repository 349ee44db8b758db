#include <fmt/format.h>

#include <algorithm>
#include <cmath>

#include "massid/identify/identification.hpp"
#include "massid/identify/setup_checks.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {

namespace {

// "12, 57, 88 and 4 more" (file lines of the worst samples first).
std::string line_list(std::vector<Outlier> o, std::size_t shown = 10) {
  std::sort(o.begin(), o.end(),
            [](const Outlier& a, const Outlier& b) { return a.score > b.score; });
  std::string out;
  for (std::size_t i = 0; i < std::min(shown, o.size()); ++i)
    out += fmt::format("{}{} (d = {:.3g})", i ? ", " : "", o[i].line, o[i].score);
  if (o.size() > shown) out += fmt::format(" and {} more", o.size() - shown);
  return out;
}

// "lines 40-90 (51 rows) (d up to 12.3), ...": each episode and its largest score.
std::string episodes_text(const std::vector<ContactEpisode>& episodes) {
  std::string out;
  for (const ContactEpisode& e : episodes)
    out += fmt::format("{}{} (d up to {:.3g})", out.empty() ? "" : ", ", contact_place(e), e.score);
  return out;
}

}  // namespace

std::vector<Warning> identify_warnings(const IdentifySummary& s, const std::string& source) {
  using Setting = Hint::Setting;
  std::vector<Warning> out;
  if (s.condition_number > 1e6)
    out.push_back(
        {fmt::format(
             "{}: the plan hardly determines some parameters (condition number "
             "{:.3g}, eq. 36): their standard deviations are large and any error in the data is "
             "magnified; record more varied poses and tilts (massid design)",
             source, s.condition_number),
         {}});
  {
    // An estimated noise level with few residual degrees of freedom (many
    // unknowns against few samples) makes every std uncertain.
    std::string axes;
    double fewest = INFINITY;
    for (int k = 0; k < 6; ++k) {
      const bool given = k < 3 ? s.sigma_force_given : s.sigma_moment_given;
      if (!s.sigma_estimated || given || s.samples == 0 || s.residual_dof[k] >= kFewResidualDof)
        continue;
      axes += fmt::format("{}{} {:.3g}", axes.empty() ? "" : ", ", kWrenchColumns[k],
                          s.residual_dof[k]);
      fewest = std::min(fewest, s.residual_dof[k]);
    }
    if (!axes.empty()) {
      const long unknowns = static_cast<long>(s.value.size() + s.drift_value.size());
      const long more = static_cast<long>(std::ceil(kFewResidualDof - fewest));
      out.push_back(
          {fmt::format(
               "{}: {} samples for {} unknowns leave few degrees of freedom for the "
               "noise estimate ({} of {} per axis; fewer than {:.0f}): the estimated sigma, and "
               "with it every std, is uncertain by about {:.0f} % and errors beyond 2 std are "
               "more frequent than the std say; record at least {} samples, or give the sensor's "
               "noise",
               source, s.samples, unknowns, axes, s.samples, kFewResidualDof,
               100.0 / std::sqrt(2.0 * std::max(fewest, 0.5)), s.samples + more),
           {{Setting::SigmaForce, ""}, {Setting::SigmaMoment, ""}}});
    }
  }
  // Runs of consecutive outliers: an external wrench acting for a while
  // (setup_checks.hpp, find_contact_episodes), named apart from the others.
  const std::vector<ContactEpisode> contact =
      find_contact_episodes(s.outliers, s.outlier_threshold);
  // Rows an external wrench drives (contact) that the outlier test does not
  // flag (they inflate the fitted noise), found by predict's rule: named as
  // contact, with the robust fit as the fix.
  if (!s.robust && contact.empty()) {
    const std::vector<ContactEpisode> hidden =
        find_contact_episodes(s.beyond_noise, s.beyond_noise_threshold);
    if (!hidden.empty())
      out.push_back(
          {fmt::format("{}: {} carry an external wrench (contact?): consecutive samples whose "
                       "residuals lie beyond the noise by each axis' median and robust scale "
                       "(d above {:.3g}; the fitted noise includes them, so the outlier test "
                       "does not flag them); they bias the estimate: the robust fit rejects them",
                       source, episodes_text(hidden), s.beyond_noise_threshold),
           {{Setting::Robust, "on"}}});
  }
  // Only a streamed fit too long to read whole (no per-sample residuals)
  // judges each axis' largest residual: where the per-sample test ran, its
  // verdict stands (a clean log's 5.24 sigma on one axis against 5.23 is the
  // one-in-a-hundred of the per-axis bound, not a sample the per-sample test
  // missed; with gravity along the force the moments also carry the force's
  // direction noise, which only the per-sample test whitens).
  if (s.outliers.empty() && !s.robust && !s.per_sample_test && largest_residuals_implausible(s)) {
    // A long streamed log: no per-sample residuals, only the largest per axis
    // (with gravity along the force, a force axis against the three's norm).
    const double bound = largest_residual_bound(s.samples);
    for (int k = 0; k < 6; ++k) {
      const double scale = k < 3 && s.gravity_from_force ? s.sigma.head<3>().norm() : s.sigma[k];
      if (s.residual_max[k] > bound * scale)
        out.push_back({fmt::format("{}: the largest {} residual is {:.3g} sigma (above {:.3g}, "
                                   "expected with probability 1 %): some samples are implausible "
                                   "for the fitted noise; the robust fit finds them by line and "
                                   "rejects them",
                                   source, kWrenchColumns[k], s.residual_max[k] / scale, bound),
                       {{Setting::Robust, "on"}}});
    }
    return out;
  }
  if (s.outliers.empty()) return out;
  const double fraction = static_cast<double>(s.outliers.size()) / std::max(s.samples, 1);
  if (!contact.empty())
    out.push_back(
        {fmt::format("{}: {} carry an external wrench (contact?): consecutive samples with "
                     "residuals beyond the noise (standardised residual d above {:.3g}); {}",
                     source, episodes_text(contact), s.outlier_threshold,
                     s.robust ? "rejected, with any other outliers"
                              : "they bias the estimate: the robust fit rejects them"),
         s.robust ? std::vector<Hint>{} : std::vector<Hint>{{Setting::Robust, "on"}}});
  if (s.robust) {
    out.push_back({fmt::format("{}: rejected {} of {} samples ({:.2g} %) as outliers (standardised "
                               "residual d above {:.3g}), at lines {}",
                               source, s.outliers.size(), s.samples, 100 * fraction,
                               s.outlier_threshold, line_list(s.outliers)),
                   {}});
    if (fraction > 0.2)
      out.push_back({fmt::format("{}: more than 20 % of the samples rejected: the model or the "
                                 "set-up is likely wrong (sign, frame, units, sensor link, a "
                                 "drifting offset), not the samples",
                                 source),
                     {{Setting::Drift, "linear"}}});
  } else {
    out.push_back(
        {fmt::format("{}: {} sample(s) have residuals implausible for the fitted noise "
                     "(standardised residual d above {:.3g}, expected with probability "
                     "1 %): lines {}. They bias the estimate: check them (a bump, a "
                     "cable, a transient), or let the robust fit reject them",
                     source, s.outliers.size(), s.outlier_threshold, line_list(s.outliers)),
         {{Setting::Robust, "on"}}});
  }
  return out;
}

}  // namespace massid
