#include "massid/identify/identifiability.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <Eigen/SVD>
#include <algorithm>
#include <random>

#include "identify/axis_least_squares.hpp"
#include "massid/core/base_regressor.hpp"

namespace massid {
namespace {

constexpr int kNoJoint = -1, kAllJoints = -2;

// Regressor rows for `count` samples (the data's, cycled; default max(3p, 30))
// with the gravity direction and/or joint positions (one joint, all or none)
// replaced by random ones.
Eigen::MatrixXd perturbed_rows(const Model& model, const BaseParameters& base,
                               const Samples& samples, bool random_gravity, int random_joint,
                               int count = 0) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  if (count <= 0) count = std::max(3 * base.num_unknowns(), 30);
  RegressorData data(model, base);
  Eigen::MatrixXd rows(6 * count, base.num_unknowns());
  for (int i = 0; i < count; ++i) {
    const int s = i % samples.size();
    Eigen::VectorXd q = samples.q.row(s).transpose();
    Eigen::Vector3d g = samples.gravity.row(s).transpose();
    for (int j = 0; j < model.num_joints(); ++j)
      if (random_joint == kAllJoints || j == random_joint)
        q[j] = model.joints[j].generic_position(uniform(rng));
    if (random_gravity)
      g = g.norm() * Eigen::Vector3d(normal(rng), normal(rng), normal(rng)).normalized();
    if (base.motion()) {
      // Moving a joint: at the sample's velocity and acceleration, or random ones.
      const Eigen::Index nj = q.size();
      const bool moving = nj > 0 && samples.qd.cols() == nj && samples.qdd.cols() == nj;
      Eigen::VectorXd qd =
          moving ? Eigen::VectorXd(samples.qd.row(s).transpose()) : Eigen::VectorXd::Zero(nj);
      Eigen::VectorXd qdd =
          moving ? Eigen::VectorXd(samples.qdd.row(s).transpose()) : Eigen::VectorXd::Zero(nj);
      for (int j = 0; j < model.num_joints(); ++j)
        if (random_joint == kAllJoints || j == random_joint) {
          qd[j] = 2.0 * normal(rng);
          qdd[j] = 5.0 * normal(rng);
        }
      base_regressor(model, base, data, q, qd, qdd, g, sensor_motion(samples, s));
    } else {
      base_regressor(model, base, data, q, g);
    }
    rows.middleRows(6 * i, 6) = data.base;
  }
  return rows;
}

// Would adding `rows` to the data determine every direction of `null` (an
// orthonormal basis of the data's null space, column-scaled coordinates)?
// Yes iff rows * S * null has full column rank.
bool completes(const Eigen::MatrixXd& rows, const Eigen::VectorXd& scale,
               const Eigen::MatrixXd& null) {
  const Eigen::MatrixXd rs = rows * scale.asDiagonal();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(rs * null);
  const double largest = Eigen::JacobiSVD<Eigen::MatrixXd>(rs).singularValues()(0);
  return svd.singularValues().minCoeff() > 1e-6 * largest;
}

// Numerical rank (singular values above tolerance * the largest), of rows
// with unit-norm columns.
int rank(const Eigen::VectorXd& sv, double tolerance) {
  return sv.size() ? static_cast<int>((sv.array() > tolerance * sv[0]).count()) : 0;
}

int scaled_rank(const Eigen::MatrixXd& rows, double tolerance) {
  return rank(detail::small_svd(rows * detail::column_scale(rows).asDiagonal()).singularValues(),
              tolerance);
}

// Independent equations that n samples can give at best: the rank of n
// samples with every joint and the gravity direction random (in motion also
// the velocities and accelerations). At rest a pose gives at most two
// independent moment equations (m = H x g is normal to g) and the force
// only M: 2n + 1 without offsets.
int best_rank(const Model& model, const BaseParameters& base, const Samples& samples, int n,
              double tolerance) {
  return scaled_rank(perturbed_rows(model, base, samples, true, kAllJoints, n), tolerance);
}

// The first `shown` items joined by `sep`, then "<more>N more" for the rest:
// "a; b; c and 4 more".
std::string cut_list(const std::vector<std::string>& items, std::size_t shown, const char* sep,
                     const char* more) {
  shown = std::min(shown, items.size());
  std::string out = fmt::format("{}", fmt::join(items.begin(), items.begin() + shown, sep));
  if (items.size() > shown) out += fmt::format("{}{} more", more, items.size() - shown);
  return out;
}

// "a or b or c or 5 more": joint names, at most six.
std::string joint_list(const std::vector<std::string>& names, const char* sep = " or ") {
  return cut_list(names, names.size() > 6 ? 5 : 6, sep, sep);
}

}  // namespace

IdentifiabilityReport check_identifiability(const Model& model, const BaseParameters& base,
                                            const Samples& samples, const Eigen::MatrixXd& A,
                                            double tolerance) {
  IdentifiabilityReport report;
  const int p = static_cast<int>(A.cols());
  report.unknowns = p;
  const Eigen::VectorXd scale = detail::column_scale(A);
  const Eigen::JacobiSVD<Eigen::MatrixXd> svd =
      detail::small_svd(A * scale.asDiagonal(), Eigen::ComputeFullV);
  report.rank = rank(svd.singularValues(), tolerance);
  if (report.ok()) return report;

  const Eigen::MatrixXd null = svd.matrixV().rightCols(p - report.rank);
  for (int c = 0; c < p; ++c)  // involved: a noticeable share of the null space
    if (null.row(c).norm() > 0.05) report.undetermined.push_back(c);

  // Short names for the message, in the unknowns' order (stable between the
  // dense and the streamed fit, whose null-space bases differ by round-off):
  // at most eight, each expression cut (the full ones are in `massid model`).
  std::vector<std::string> names;
  for (int c : report.undetermined) {
    std::string n = base.unknown_name(c);
    if (c < base.num_mass()) {
      const std::string& e = base.params[c].expression;
      n += " = " + (e.size() > 60 ? e.substr(0, e.rfind(' ', 57)) + " ..." : e);
    }
    names.push_back(n);
  }
  const std::string undetermined = cut_list(names, 8, "; ", " and ");
  const int N = samples.size();
  const char* const poses = base.motion() ? "samples" : "poses";

  // Too few samples for the unknowns, however varied: say the count first.
  // (Random samples give at least one independent equation each: with 2p or
  // more the count is never the cause, and is not computed.)
  report.equations = N < 2 * p ? best_rank(model, base, samples, N, tolerance) : p;
  int lo = N, hi = std::max(N + 1, 2 * N);
  const int cap = 16 * p + 64;  // (random samples that never suffice: not a count problem)
  if (report.equations < p)
    while (hi <= cap && best_rank(model, base, samples, hi, tolerance) < p) lo = hi, hi *= 2;
  if (report.equations < p && hi <= cap) {
    // The fewest samples that can determine every unknown (random ones do).
    while (hi - lo > 1) {
      const int mid = lo + (hi - lo) / 2;
      (best_rank(model, base, samples, mid, tolerance) < p ? lo : hi) = mid;
    }
    report.samples_needed = hi;
    // Would that many with the data's gravity directions do, or do they need tilts?
    const bool tilts =
        scaled_rank(perturbed_rows(model, base, samples, false, kAllJoints, hi), tolerance) < p;
    report.tilt_would_help = tilts;
    report.message = fmt::format(
        "{}: {} {} give at most {} independent equations for {} unknowns: record at least {} "
        "{}{}{} (massid design plans them{}); these determine only {} of the {} unknowns "
        "(undetermined: {})",
        samples.source, N, poses, report.equations, p, hi, poses,
        base.motion() ? ", moving every joint" : " with every joint moved",
        tilts ? " and the platform tilted to several gravity directions" : "",
        base.motion() ? ", trajectories too" : "", report.rank, p, undetermined);
    return report;
  }

  report.tilt_would_help =
      completes(perturbed_rows(model, base, samples, true, kNoJoint), scale, null);
  for (int j = 0; j < model.num_joints(); ++j)
    if (completes(perturbed_rows(model, base, samples, false, j), scale, null))
      report.joints_to_move.push_back(model.joints[j].name);
  const bool all_joints_help =
      model.num_joints() > 0 &&
      completes(perturbed_rows(model, base, samples, false, kAllJoints), scale, null);

  std::string fix;
  if (!report.joints_to_move.empty()) {
    fix = fmt::format(
        fmt::runtime(base.motion() ? "move joint{} {} faster and over a wider range "
                                     "(higher velocities and accelerations, a longer log)"
                                   : "move joint{} {} over a wider range of positions"),
        report.joints_to_move.size() > 1 ? "s" : "", joint_list(report.joints_to_move));
    // A joint that never moves may have been held on purpose (the paper held the wrist).
    std::vector<std::string> still;
    std::string held;  // the hint's value: "JOINT=VALUE ..."
    for (const std::string& name : report.joints_to_move) {
      const auto col = samples.q.col(model.find_joint(name));
      if (samples.size() > 0 && col.maxCoeff() == col.minCoeff()) {
        still.push_back(name);
        held += fmt::format("{}{}={}", held.empty() ? "" : " ", name, col[0]);
      }
    }
    if (still.size() == 1)
      fix += fmt::format(
          " ({} never moves in the data: if it was held still on purpose, hold it at its "
          "value to identify what such data can)",
          still[0]);
    else if (!still.empty())
      fix += fmt::format(
          " ({} never move in the data: if they were held still on purpose, hold them at their "
          "values to identify what such data can)",
          joint_list(still, " and "));
    if (!still.empty()) report.hints.push_back({Hint::Setting::HoldJoints, held});
  } else if (all_joints_help) {
    fix = "move several joints together over wider ranges";
  }
  if (report.tilt_would_help) {
    std::string tilt =
        "tilt the platform: record poses with gravity in more directions of the sensor frame";
    if (base.offset) tilt += " (with the offsets estimated, at least three different directions)";
    fix = fix.empty() ? tilt : fix + ", or " + tilt;
  }
  if (fix.empty()) fix = "both move the joints and tilt the platform to more directions";
  report.message = fmt::format(
      "{}: the {} samples determine only {} of the {} unknowns; undetermined: {}. To fix: {}.",
      samples.source, samples.size(), report.rank, p, undetermined, fix);
  return report;
}

}  // namespace massid
