#include "massid/identifiability.hpp"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <random>

#include "massid/base_regressor.hpp"

namespace massid {
namespace {

constexpr int kNoJoint = -1, kAllJoints = -2;

// Regressor rows for the samples (cycled) with the gravity direction and/or
// joint positions (one joint, all or none) replaced by random ones.
Eigen::MatrixXd perturbed_rows(const Model& model, const BaseParameters& base,
                               const Samples& samples, bool random_gravity, int random_joint) {
  std::mt19937_64 rng(7);
  std::normal_distribution<double> normal;
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const int count = std::max(3 * base.num_unknowns(), 30);
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

}  // namespace

IdentifiabilityReport check_identifiability(const Model& model, const BaseParameters& base,
                                            const Samples& samples, const Eigen::MatrixXd& A,
                                            double tolerance) {
  IdentifiabilityReport report;
  const int p = static_cast<int>(A.cols());
  report.unknowns = p;
  Eigen::VectorXd scale(p);
  for (int c = 0; c < p; ++c) {
    const double n = A.col(c).norm();
    scale[c] = n > 0 ? 1.0 / n : 1.0;
  }
  // Singular values of A S from the small triangular factor of its QR.
  Eigen::MatrixXd R;
  if (A.rows() >= p) {
    Eigen::HouseholderQR<Eigen::MatrixXd> qr(A * scale.asDiagonal());
    R = qr.matrixQR().topRows(p).triangularView<Eigen::Upper>();
  } else {
    R = A * scale.asDiagonal();
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(R, Eigen::ComputeFullV);
  const Eigen::VectorXd& sv = svd.singularValues();
  const double smax = sv.size() ? sv[0] : 0.0;
  report.rank = 0;
  for (int i = 0; i < sv.size(); ++i)
    if (sv[i] > tolerance * smax) ++report.rank;
  if (report.ok()) return report;

  const Eigen::MatrixXd null = svd.matrixV().rightCols(p - report.rank);
  for (int c = 0; c < p; ++c)  // involved: a noticeable share of the null space
    if (null.row(c).norm() > 0.05) report.undetermined.push_back(c);

  report.tilt_would_help =
      completes(perturbed_rows(model, base, samples, true, kNoJoint), scale, null);
  for (int j = 0; j < model.num_joints(); ++j)
    if (completes(perturbed_rows(model, base, samples, false, j), scale, null))
      report.joints_to_move.push_back(model.joints[j].name);
  const bool all_joints_help =
      model.num_joints() > 0 &&
      completes(perturbed_rows(model, base, samples, false, kAllJoints), scale, null);

  std::vector<std::string> names;
  for (int c : report.undetermined) {
    std::string n = base.unknown_name(c);
    if (c < base.num_mass()) n += " = " + base.params[c].expression;
    names.push_back(n);
  }
  std::string fix;
  if (!report.joints_to_move.empty()) {
    fix = fmt::format(
        fmt::runtime(base.motion() ? "move joint{} {} faster and over a wider range "
                                     "(higher velocities and accelerations, a longer log)"
                                   : "move joint{} {} over a wider range of positions"),
        report.joints_to_move.size() > 1 ? "s" : "", fmt::join(report.joints_to_move, " or "));
    // A joint that never moves may have been held on purpose (the paper held the wrist).
    for (const std::string& name : report.joints_to_move) {
      const auto col = samples.q.col(model.find_joint(name));
      if (samples.size() > 0 && col.maxCoeff() == col.minCoeff())
        fix += fmt::format(
            " ({} never moves in the data: if it was held still on purpose, pass "
            "--fixed {}={} to identify what such data can)",
            name, name, col[0]);
    }
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
      samples.source, samples.size(), report.rank, p, fmt::join(names, "; "), fix);
  return report;
}

}  // namespace massid
