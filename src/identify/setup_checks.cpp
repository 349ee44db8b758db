// Set-up checks (setup_checks.hpp). Notation: N samples, f_i the measured
// force, g_i the gravity columns, M the URDF's total mass (nominal_total_mass),
// g0 = 9.80665 m/s^2. At rest the data obey f_i = M g_i + b + noise, with b
// the sensor offset, so
//   - the centred force f_i - mean(f) depends on the centred gravity
//     g_i - mean(g) alone: statistics built on centred data ignore b;
//   - the force does not depend on the joints: sign and frame checks need the
//     gravity columns only (they do not apply when gravity is taken from the
//     force, eq. 37: then f and g agree by construction).
#include "massid/identify/setup_checks.hpp"

#include <fmt/format.h>

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <Eigen/QR>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <functional>
#include <iterator>
#include <limits>
#include <numbers>
#include <numeric>
#include <stdexcept>

#include "core/median.hpp"
#include "identify/chi_square.hpp"
#include "io/column_map.hpp"
#include "io/csv_fields.hpp"
#include "io/csv_stream.hpp"
#include "massid/core/base_parameters.hpp"
#include "massid/core/errors.hpp"
#include "massid/core/kinematics.hpp"
#include "massid/core/simulate.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"

namespace massid {
namespace {

using detail::median;

using Severity = SetupFinding::Severity;
constexpr double kDeg = std::numbers::pi / 180.0;

// --- thresholds -------------------------------------------------------------

// |g| accepted as Earth's gravity: 9.78-9.83 m/s^2 at the surface, with room
// for an accelerometer's few-% scale error. Every unit mistake (g = 1, mm/s^2,
// ft/s^2 = 32.2, cm/s^2) is far outside.
constexpr double kGravityLow = 9.0, kGravityHigh = 10.5;
// A factor "near 1000": within 10^(3 +- 0.5). A URDF whose masses are off by
// 3x (or the as-built robot's extra 5 %) stays far below.
constexpr double kUnitLow = 316.0, kUnitHigh = 3162.0;
// Frame rotation: the angle must exceed this (warning; error above
// kRotationError) and 6 standard deviations of its noise. Realistic mounting
// and calibration errors stay below 1 deg; 2 deg already leaves force residuals
// of 3.5 % of the weight; 5 deg of 9 %, which biases every first moment.
constexpr double kRotationWarn = 2.0, kRotationError = 5.0, kRotationSigmas = 6.0;
// Gravity directions count as distinct when their RMS spread about the mean
// exceeds 2 % of |g| (1.2 deg of tilt).
constexpr double kMinSpread = 0.02;
// Rows the geometry and the nominal wrench are evaluated at (a strided subset).
constexpr int kNominalRows = 2000;
// Checks that compare columns over rows need this many rows.
constexpr int kMinRows = 3;
// Residuals correlated over rows (a sensor's low-pass filter, a logger faster
// than the sensor) carry fewer independent values than rows: at most one per
// this many rows is assumed for AR(1)-like noise with rho near 1.
constexpr double kMaxCorrelationRows = 200.0;

// --- formatting ---------------------------------------------------------------

// "line 4", "lines 4, 9, 12 and 3 more"; never empty: "no line" for no rows.
std::string lines_text(const Samples& s, const std::vector<int>& rows) {
  if (rows.empty()) return "no line";
  std::string t = rows.size() == 1 ? "line " : "lines ";
  const size_t shown = std::min<size_t>(rows.size(), 3);
  for (size_t k = 0; k < shown; ++k) t += fmt::format("{}{}", k ? ", " : "", s.line[rows[k]]);
  if (rows.size() > shown) t += fmt::format(" and {} more", rows.size() - shown);
  return t;
}

// The name of the column the reader reads for `joint` with `suffix` ("",
// "_vel", "_acc"; io's joint_column), else NAME + suffix.
std::string joint_column(const Joint& j, const std::vector<std::string>& header,
                         const std::string& suffix = "") {
  const int c = detail::joint_column(j, header, suffix).column;
  return c >= 0 ? header[c] : j.name + suffix;
}

bool constant(const Eigen::VectorXd& c) { return c.size() > 0 && c.maxCoeff() == c.minCoeff(); }

// Rows per independent value of a residual whose rows are in time order
// ([rows x k], any number of columns): (1 + rho) / (1 - rho) for the lag-1
// autocorrelation rho pooled over the columns, the factor by which an AR(1)
// noise's variance of a mean or a slope exceeds white noise's. 1 for white
// (or anti-correlated) residuals; at most kMaxCorrelationRows. Every verdict
// below judges its statistic against the noise's variance times this factor,
// so that a filtered sensor's 1,500 rows at one pose are not taken for 1,500
// independent measurements (issue 29: a 3 % difference between two
// hypotheses is no evidence).
double correlation_rows(const Eigen::MatrixXd& r) {
  if (r.rows() < 3) return 1.0;
  const double lag0 = r.squaredNorm();
  if (!(lag0 > 0)) return 1.0;
  const double lag1 = (r.topRows(r.rows() - 1).array() * r.bottomRows(r.rows() - 1).array()).sum();
  const double rho = std::clamp(lag1 / lag0, 0.0, 0.999);
  return std::min((1.0 + rho) / (1.0 - rho), kMaxCorrelationRows);
}

// The rotation R minimising sum |b_i - R a_i|^2 (Kabsch) from H = sum a_i b_i^T.
Eigen::Matrix3d kabsch(const Eigen::Matrix3d& H) {
  Eigen::JacobiSVD<Eigen::Matrix3d> svd(H, Eigen::ComputeFullU | Eigen::ComputeFullV);
  Eigen::Matrix3d D = Eigen::Matrix3d::Identity();
  D(2, 2) = (svd.matrixV() * svd.matrixU().transpose()).determinant() < 0 ? -1.0 : 1.0;
  return svd.matrixV() * D * svd.matrixU().transpose();
}

struct Context {
  Context(const Model& m, const Samples& samples, const std::vector<std::string>& h,
          std::vector<SetupFinding>& o)
      : model(m),
        s(samples),
        header(h),
        out(o),
        N(samples.size()),
        M(m.nominal_total_mass()),
        F(samples.has_wrench() ? Eigen::MatrixXd(samples.wrench.leftCols(3)) : Eigen::MatrixXd()),
        G(samples.gravity) {}
  const Model& model;
  const Samples& s;
  const std::vector<std::string>& header;
  std::vector<SetupFinding>& out;
  int N;
  double M;              // URDF total mass
  Eigen::MatrixXd F, G;  // [N x 3] force, gravity
  std::vector<int> sub;  // strided subset of rows
  Eigen::MatrixXd nom;   // [sub x 6] URDF wrench at the subset, gravity scaled to g0
  double reach = 0.0;    // largest distance of a link origin or com from the sensor origin

  // "lines 4-900": the rows the checks read.
  std::string lines() const { return fmt::format("lines {}-{}", s.line.front(), s.line.back()); }

  void add(Severity sev, const char* code, std::string message, std::vector<Hint> hints = {}) {
    if (sev == Severity::Error) hints.push_back({Hint::Setting::Checks, "off"});
    out.push_back({sev, code, std::move(message), std::move(hints)});
  }
};

// The subset of samples at `rows` (the columns the checks read).
Samples sample_rows(const Samples& s, const std::vector<int>& rows) {
  Samples out;
  out.source = s.source;
  out.gravity_from_force = s.gravity_from_force;
  out.gravity_from_upstream = s.gravity_from_upstream;
  out.root_gravity = s.root_gravity;
  for (auto [from, to] :
       {std::pair{&s.q, &out.q}, {&s.gravity, &out.gravity}, {&s.wrench, &out.wrench}})
    *to = from->rows() > 0 ? Eigen::MatrixXd((*from)(rows, Eigen::all))
                           : Eigen::MatrixXd(static_cast<Eigen::Index>(rows.size()), from->cols());
  if (!s.line.empty())
    for (const int r : rows) out.line.push_back(s.line[r]);
  return out;
}

// Gravity from the tilt columns (no gx,gy,gz, no joints above the sensor):
// the level gravity (--gravity, or --root-gravity through the fixed joints)
// turned by tilt_x_deg,tilt_y_deg, not columns of the file.
bool gravity_from_tilt(const Context& c) {
  const auto has = [&](const char* n) {
    return std::find(c.header.begin(), c.header.end(), n) != c.header.end();
  };
  return has("tilt_x_deg") && !has("gx") && !c.s.gravity_from_upstream;
}

// The URDF's wrench and reach at a strided subset of the rows, gravity scaled
// to g0 (so that a unit mistake in gx,gy,gz does not hide one in the wrench).
void nominal(Context& c) {
  const int stride = std::max(1, (c.N + kNominalRows - 1) / kNominalRows);
  for (int i = 0; i < c.N; i += stride) c.sub.push_back(i);
  Samples p = sample_rows(c.s, c.sub);
  KinematicsData kin(c.model);
  for (int k = 0; k < p.size(); ++k) {
    const double n = p.gravity.row(k).norm();
    if (n > 0)
      p.gravity.row(k) *= kStandardGravity / n;
    else
      p.gravity.row(k).setZero();
    forward_kinematics(c.model, kin, p.q.row(k).transpose());
    for (int l = 0; l < c.model.num_links(); ++l) {
      c.reach = std::max(c.reach, kin.position[l].norm());
      if (c.model.links[l].mass > 0)
        c.reach =
            std::max(c.reach, (kin.position[l] + kin.rotation[l] * c.model.links[l].com).norm());
    }
  }
  c.nom = simulate_wrenches(c.model, p);
}

// gravity-magnitude. Statistic: the median of |g_i| over the rows, and the rows
// outside [9.0, 10.5] m/s^2. Error when the median is outside: every
// identified parameter scales with 1/|g|. Warning for single rows outside
// while the median is right (a few corrupted rows bias the fit).
void check_gravity_magnitude(Context& c) {
  std::vector<double> norms(c.N);
  std::vector<int> bad;
  for (int i = 0; i < c.N; ++i) {
    norms[i] = c.G.row(i).norm();
    if (!(norms[i] >= kGravityLow && norms[i] <= kGravityHigh)) bad.push_back(i);
  }
  const double med = median(norms);
  if (med >= kGravityLow && med <= kGravityHigh) {
    if (!bad.empty())
      c.add(Severity::Warning, "gravity-magnitude",
            fmt::format("{}: gx,gy,gz have |g| = {:.4g} m/s^2 at {} ({} of {} rows), outside "
                        "[{}, {}]: fix or remove those rows (gravity in m/s^2, sensor frame)",
                        c.s.source, norms[bad[0]], lines_text(c.s, bad), bad.size(), c.N,
                        kGravityLow, kGravityHigh));
    return;
  }
  std::string fix = "give gravity in m/s^2 (level, sensor z up: 0,0,-9.80665)";
  if (med > 0.9 && med < 1.1)
    fix = "they look like unit vectors or g units: multiply gx,gy,gz by 9.80665";
  else if (med > 9000 && med < 10500)
    fix = "they look like mm/s^2: divide gx,gy,gz by 1000";
  else if (med > 900 && med < 1050)
    fix = "they look like cm/s^2: divide gx,gy,gz by 100";
  else if (med > 29.5 && med < 34.5)
    fix = "they look like ft/s^2: multiply gx,gy,gz by 0.3048";
  c.add(Severity::Error, "gravity-magnitude",
        fmt::format("{}: gx,gy,gz have a median magnitude of {:.6g} m/s^2 ({}), not Earth's 9.81: "
                    "every identified parameter would be off by the same factor; {}",
                    c.s.source, med, c.lines(), fix));
}

// Centred gravity and force, and the eigen-decomposition of the gravity scatter
// C = sum (g_i - mean g)(g_i - mean g)^T (eigenvalues ascending).
struct Centred {
  Eigen::MatrixXd Gc, Fc;
  Eigen::Vector3d lambda;  // ascending
  Eigen::Matrix3d axes;    // columns: eigenvectors
  double g = 0.0;          // mean |g_i|
  bool spread_ok = false;
};

Centred centre(const Context& c) {
  Centred r;
  r.Gc = c.G.rowwise() - c.G.colwise().mean();
  r.Fc = c.F.rowwise() - c.F.colwise().mean();
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(r.Gc.transpose() * r.Gc);
  r.lambda = eig.eigenvalues().cwiseMax(0.0);
  r.axes = eig.eigenvectors();
  r.g = c.G.rowwise().norm().mean();
  r.spread_ok = c.N >= kMinRows && std::sqrt(r.lambda.sum() / c.N) > kMinSpread * r.g;
  return r;
}

// wrench-sign. Statistic: the slope s of the centred force on the centred
// gravity, s = sum (f_i - mean f).(g_i - mean g) / sum |g_i - mean g|^2 (the
// total mass, offset-free), when the gravity directions vary enough to
// determine it to 10 standard deviations; else (one gravity direction) the
// median over rows of cos(f_i, g_i), flagged below -0.5 (an offset would have
// to exceed the weight to get there). Error: a negated wrench identifies
// negated parameters.
bool check_sign(Context& c, const Centred& k) {
  bool negative = false;
  std::string how;
  const double Sgg = k.lambda.sum();
  bool decided = false;
  if (k.spread_ok) {
    const double s = (k.Fc.array() * k.Gc.array()).sum() / Sgg;
    const double dof = std::max(1, 3 * c.N - 4);
    const Eigen::MatrixXd r = k.Fc - s * k.Gc;
    const double sigma = std::sqrt(r.squaredNorm() / dof * correlation_rows(r));
    if (std::abs(s) > 10.0 * sigma / std::sqrt(Sgg)) {
      decided = true;
      negative = s < 0;
      how = fmt::format("the force changes by {:.4g} kg times the change of gravity", s);
    }
  }
  std::vector<int> against;
  std::vector<double> cosines;
  for (int i = 0; i < c.N; ++i) {
    const double n = c.F.row(i).norm() * c.G.row(i).norm();
    if (!(n > 0)) continue;
    const double cs = c.F.row(i).dot(c.G.row(i)) / n;
    cosines.push_back(cs);
    if (cs < 0) against.push_back(i);
  }
  if (!decided) {
    const double med = median(cosines);
    negative = !cosines.empty() && med < -0.5;
    how = fmt::format("the median angle between force and gravity is {:.0f} deg",
                      std::acos(std::clamp(med, -1.0, 1.0)) / kDeg);
  }
  if (!negative) return false;
  const double fitted = (c.F.array() * c.G.array()).sum() / c.G.squaredNorm();
  // Gravity from the tilt columns: the level gravity they turn may be the one
  // upside down.
  const bool tilt = gravity_from_tilt(c);
  c.add(Severity::Error, "wrench-sign",
        fmt::format("{}: the measured force points against gravity ({}) at {} of {} rows "
                    "({}; {}; total mass along gravity {:.4g} kg, the URDF's {:.4g} kg): massid "
                    "wants the wrench the bodies exert on the sensor, f = M g at rest. If the "
                    "sensor reports the reaction (MuJoCo, force plates), negate fx,fy,fz,mx,my,mz; "
                    "{}",
                    c.s.source,
                    tilt ? "the level gravity turned by tilt_x_deg,tilt_y_deg" : "gx,gy,gz",
                    against.size(), c.N, lines_text(c.s, against), how, fitted, c.M,
                    tilt ? "if the level gravity points up in the sensor frame, give it along "
                           "gravity (sensor frame, platform level)"
                         : "if gx,gy,gz point up instead of along gravity, negate gx,gy,gz"),
        tilt ? std::vector<Hint>{{Hint::Setting::LevelGravity, ""}} : std::vector<Hint>{});
  return true;
}

// frame-rotation. Statistic: the angle of the best rotation R with
// f_i - mean f = s R (g_i - mean g) (Kabsch on centred data: offset-free) when
// the gravity directions span two dimensions; with two directions only (one
// tilt axis) the rotation about their difference is invisible, and the
// statistic is the angle between the force's and gravity's principal
// direction of change. Its noise: for a rotation error w the residuals are
// s w x g_i, so std(w) <= sigma / (|s| sqrt(l2 + l3)) (l: eigenvalues of the
// gravity scatter, descending; l1 alone for the 1-D statistic), sigma the
// per-axis force residual. Flagged above max(2 deg, 6 std): a warning to
// 5 deg, an error above (the fit's moments would be meaningless).
void check_rotation(Context& c, const Centred& k) {
  if (!k.spread_ok) return;  // one gravity direction: a rotation is undetermined
  const double l1 = k.lambda(2), l23 = k.lambda(0) + k.lambda(1);
  const bool two_d = l23 > 0.01 * l1 && std::sqrt(k.lambda(1) / c.N) > kMinSpread * k.g;
  double angle = 0.0, sigma_angle = 0.0;
  Eigen::Matrix3d R;
  std::string basis;
  if (two_d) {
    R = kabsch(k.Gc.transpose() * k.Fc);
    const double s = (k.Fc.array() * (k.Gc * R.transpose()).array()).sum() / k.lambda.sum();
    const double dof = std::max(1, 3 * c.N - 7);
    const Eigen::MatrixXd r = k.Fc - s * k.Gc * R.transpose();
    const double sigma = std::sqrt(r.squaredNorm() / dof * correlation_rows(r));
    angle = Eigen::AngleAxisd(R).angle();
    sigma_angle = sigma / (std::abs(s) * std::sqrt(l23));
    basis = "from the centred data, so a sensor offset does not matter";
  } else {
    const Eigen::Vector3d dg = k.axes.col(2);
    const Eigen::VectorXd t = k.Gc * dg;
    const Eigen::Vector3d v = k.Fc.transpose() * t / l1;
    const double dof = std::max(1, 3 * c.N - 6);
    const Eigen::MatrixXd r = k.Fc - t * v.transpose();
    const double sigma = std::sqrt(r.squaredNorm() / dof * correlation_rows(r));
    angle = std::acos(std::clamp(v.normalized().dot(dg), -1.0, 1.0));
    sigma_angle = sigma / (v.norm() * std::sqrt(l1));
    // The full rotation from the raw vectors (assuming no offset): two
    // distinct directions determine it.
    R = kabsch(c.G.transpose() * c.F);
    basis = fmt::format(
        "the force's direction of change is {:.2f} deg from gravity's (the plan tilts about one "
        "axis, so that is a lower bound); the rotation assumes no sensor offset",
        angle / kDeg);
  }
  const double deg = angle / kDeg;
  if (!(deg > kRotationWarn && angle > kRotationSigmas * sigma_angle)) return;
  const Eigen::AngleAxisd aa(R);
  // What gravity came from (the tilt columns, the joints above the sensor,
  // gx,gy,gz), and so what may be the rotated one: {gravity, against, or_gravity}.
  const bool tilt = gravity_from_tilt(c);
  static const char* const kFrom[3][3] = {
      {"the level gravity turned by tilt_x_deg,tilt_y_deg", "that gravity",
       "or, if the level gravity is the rotated one, give it as R times it (--gravity, sensor "
       "frame, platform level)"},
      {"gravity from the joints above the sensor link", "the URDF's sensor link",
       "or check the joints above it and --root-gravity"},
      {"gx,gy,gz", "the gravity columns", "or gx,gy,gz by R if they are the rotated ones"}};
  const auto [gravity, against, or_gravity] = kFrom[tilt ? 0 : c.s.gravity_from_upstream ? 1 : 2];
  c.add(deg > kRotationError ? Severity::Error : Severity::Warning, "frame-rotation",
        fmt::format(
            "{}: the force direction disagrees with {} by {:.2f} deg (noise explains {:.2g} deg) "
            "over {}: the wrench frame is rotated against {}; best fit f = M R g with R = "
            "[[{:.4f}], [{:.4f}], [{:.4f}]] ({:.2f} deg about ({:.3f}); {}). Rotate fx,fy,fz and "
            "mx,my,mz by R^T into the frame of that gravity ({}), or make the URDF's sensor link "
            "the sensor's frame",
            c.s.source, gravity, deg, kRotationSigmas * sigma_angle / kDeg, c.lines(), against,
            fmt::join(R.row(0), ", "), fmt::join(R.row(1), ", "), fmt::join(R.row(2), ", "),
            aa.angle() / kDeg, fmt::join(aa.axis(), ", "), basis, or_gravity),
        tilt ? std::vector<Hint>{{Hint::Setting::LevelGravity, ""}} : std::vector<Hint>{});
}

// --- channel signs and swaps ------------------------------------------------

// The 48 signed permutation matrices P, P(k, perm[k]) = +-1; the identity first.
const std::vector<Eigen::Matrix3d>& signed_permutations() {
  static const std::vector<Eigen::Matrix3d> all = [] {
    std::vector<Eigen::Matrix3d> v;
    int perm[3] = {0, 1, 2};
    do {
      for (int signs = 0; signs < 8; ++signs) {
        Eigen::Matrix3d P = Eigen::Matrix3d::Zero();
        for (int k = 0; k < 3; ++k) P(k, perm[k]) = (signs >> k) & 1 ? -1.0 : 1.0;
        v.push_back(P);
      }
    } while (std::next_permutation(perm, perm + 3));
    return v;
  }();
  return all;
}

int changed_channels(const Eigen::Matrix3d& P) {
  int n = 0;
  for (int k = 0; k < 3; ++k) n += P(k, k) != 1.0;
  return n;
}

// One test of the channels of one kind (force or moment): for each signed
// permutation P the residual sum of squares `ssr` of the fit that assumes
// the recorded channels are P times the true ones, and `dof`. Noise is judged
// from the best fit: the P's within 25 of its variances tie with it.
// The identity is excluded when it is worse than the best by more than 100
// variances (10 sigma) and by a factor 4 (model errors such as a 1 deg
// misalignment or an as-built mass inflate every fit alike; a flipped channel
// that varies is far worse). The variance is the best fit's residual variance
// times its correlation_rows (`residual` gives the residual of the i-th P): a
// difference of SSR between two hypotheses grows with the noise's correlation
// as the variance of a mean does.
struct ChannelFit {
  std::vector<double> ssr;
  std::vector<bool> tie;
  bool identity_out = false;
  double rows = 0.0;
};

ChannelFit channel_fit(std::vector<double> ssr, double dof, double rows, double total,
                       const std::vector<bool>* among,
                       const std::function<Eigen::MatrixXd(size_t)>& residual) {
  const size_t n = ssr.size();
  ChannelFit f;
  f.rows = rows;
  f.tie.assign(n, true);
  f.ssr = ssr;
  if (!(dof >= 1)) return f;
  double best = INFINITY;
  size_t at = 0;
  for (size_t i = 0; i < n; ++i)
    if ((!among || (*among)[i]) && ssr[i] < best) {
      best = ssr[i];
      at = i;
    }
  const double var =
      std::max(best / dof * correlation_rows(residual(at)), 1e-24 * total / rows + 1e-300);
  for (size_t i = 0; i < n; ++i) f.tie[i] = (!among || (*among)[i]) && ssr[i] <= best + 25 * var;
  f.identity_out = !f.tie[0] && ssr[0] - best > 100 * var && ssr[0] > 4 * best;
  return f;
}

// The answer of a test: P (the identity unless decisive) and the residual RMS
// per row as recorded and with P.
struct ChannelTest {
  bool tested = false;
  Eigen::Matrix3d P = Eigen::Matrix3d::Identity();
  double rms_recorded = 0.0, rms_best = 0.0;
  std::vector<bool> tie;  // the P's the data cannot tell from the best
  bool decisive() const { return tested && !P.isIdentity(); }
};

// Among the ties, the P with the fewest changed channels, or one tied in
// `other` too (the force and the moment channels agree).
ChannelTest pick_channels(const ChannelFit& f, const std::vector<bool>* other = nullptr) {
  const auto& all = signed_permutations();
  ChannelTest t;
  t.tested = true;
  t.tie = f.tie;
  int pick = -1;
  for (int pass = 0; pass < 2 && pick < 0; ++pass)
    for (size_t i = 0; i < all.size(); ++i)
      if (f.tie[i] && (pass == 1 || !other || (*other)[i]) &&
          (pick < 0 || changed_channels(all[i]) < changed_channels(all[pick])))
        pick = static_cast<int>(i);
  if (pick > 0 && f.identity_out) t.P = all[pick];
  t.rms_recorded = std::sqrt(std::max(f.ssr[0], 0.0) / f.rows);
  t.rms_best = std::sqrt(std::max(f.ssr[t.P.isIdentity() ? 0 : pick], 0.0) / f.rows);
  return t;
}

// Force channels. Statistics: for every signed permutation P, the residual of
// the centred fit f_i - mean f = M P (g_i - mean g) with M >= 0 (offset-free),
// SSR(P) = S_ff - max(0, tr(P H))^2 / S_gg with H = sum (g_i - mean g)(f_i -
// mean f)^T; where that leaves several P's tied (one gravity direction, or
// gz the same in every row as in a plan at one tilt), the same fit without
// centring decides among them (an offset as large as the weight would be
// needed to fake a flipped channel there).
ChannelFit force_channels(const Context& c, const Centred& k) {
  const auto fit = [&](const Eigen::MatrixXd& G, const Eigen::MatrixXd& F, double dof,
                       const std::vector<bool>* among) {
    const Eigen::Matrix3d H = G.transpose() * F;
    const double Sff = F.squaredNorm(), Sgg = G.squaredNorm();
    std::vector<double> ssr;
    for (const Eigen::Matrix3d& P : signed_permutations()) {
      const double t = Sgg > 0 ? std::max(0.0, (P * H).trace()) : 0.0;
      ssr.push_back(std::max(0.0, Sff - (Sgg > 0 ? t * t / Sgg : 0.0)));
    }
    // The residual F - M G P^T of P's fit, M = tr(P H) / S_gg.
    const auto residual = [&](size_t i) -> Eigen::MatrixXd {
      const Eigen::Matrix3d& P = signed_permutations()[i];
      const double t = Sgg > 0 ? std::max(0.0, (P * H).trace()) : 0.0;
      return F - (Sgg > 0 ? t / Sgg : 0.0) * G * P.transpose();
    };
    return channel_fit(ssr, dof, c.N, Sff, among, residual);
  };
  if (c.N < kMinRows) return {};
  ChannelFit centred;
  if (k.spread_ok) {
    centred = fit(k.Gc, k.Fc, 3.0 * c.N - 4, nullptr);
    if (centred.identity_out) return centred;
  }
  return fit(c.G, c.F, 3.0 * c.N - 1, k.spread_ok ? &centred.tie : nullptr);
}

// Moment channels. Statistic: for every P, the residual of the least-squares
// fit of P^T m_i = Y_m(q_i, g_i) pi + b over the URDF's structure (its base
// parameters and the three moment offsets; no inertial value is used), at the
// strided subset of rows: SSR(P) = |y_P|^2 - |Q^T y_P|^2, with Q an
// orthonormal basis of the regressor's moment rows. The fit cannot tell P
// from -P (negated first moments): when the URDF has masses, the sign whose
// moments correlate positively with the URDF's is kept.
ChannelFit moment_channels(const Context& c) {
  const int n = static_cast<int>(c.sub.size());
  if (n < kMinRows) return {};
  const Samples s = sample_rows(c.s, c.sub);
  BaseParameterOptions bo;
  bo.offset = true;
  const BaseParameters base = find_base_parameters(c.model, bo);
  const Eigen::MatrixXd A = stacked_regressor(c.model, base, s);
  Eigen::MatrixXd Am(3 * n, A.cols());
  for (int k = 0; k < n; ++k) Am.middleRows(3 * k, 3) = A.middleRows(6 * k + 3, 3);
  const Eigen::MatrixXd Y = s.wrench.rightCols(3).transpose();
  const Eigen::RowVectorXd norm = Am.colwise().norm();  // unit columns (a zero one stays)
  Am.array().rowwise() /= (norm.array() > 0).select(norm.array(), 1.0);
  Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(Am);
  qr.setThreshold(1e-10);
  const Eigen::Index r = qr.rank();
  if (3 * n - r < 6) return {};
  const Eigen::MatrixXd Q = qr.householderQ() * Eigen::MatrixXd::Identity(3 * n, r);
  // The URDF's moments, centred, for the sign.
  Eigen::MatrixXd nom = c.nom.rightCols(3).transpose();
  nom = nom.colwise() - nom.rowwise().mean();
  const Eigen::MatrixXd Yc = Y.colwise() - Y.rowwise().mean();
  std::vector<double> ssr, agreement;
  for (const Eigen::Matrix3d& P : signed_permutations()) {
    const Eigen::MatrixXd YP = P.transpose() * Y;  // the true moments if P is right
    const Eigen::Map<const Eigen::VectorXd> y(YP.data(), 3 * n);
    ssr.push_back(std::max(0.0, y.squaredNorm() - (Q.transpose() * y).squaredNorm()));
    agreement.push_back(((P.transpose() * Yc).array() * nom.array()).sum());
  }
  // P's fit residual, [n x 3] in row order.
  const auto residual = [&](size_t i) -> Eigen::MatrixXd {
    const Eigen::MatrixXd YP = signed_permutations()[i].transpose() * Y;
    const Eigen::Map<const Eigen::VectorXd> y(YP.data(), 3 * n);
    const Eigen::VectorXd e = y - Q * (Q.transpose() * y);
    return Eigen::Map<const Eigen::MatrixXd>(e.data(), 3, n).transpose();
  };
  const double dof = static_cast<double>(3 * n - r);
  ChannelFit f = channel_fit(ssr, dof, n, Y.squaredNorm(), nullptr, residual);
  // The URDF signs the fit only where the agreement of the recorded moments'
  // changes with the URDF's, sum (P^T m_i - mean).(m_URDF,i - mean), exceeds
  // 10 times its noise, sigma |m_URDF - mean| (with the residual's
  // correlation): at one pose, or poses a few degrees apart, the changes are
  // noise and their sign no evidence.
  const size_t best = static_cast<size_t>(std::min_element(ssr.begin(), ssr.end()) - ssr.begin());
  const double noise =
      std::sqrt(ssr[best] / std::max(dof, 1.0) * correlation_rows(residual(best))) * nom.norm();
  const bool signed_by_urdf = c.M > 0 && nom.norm() > 0 && std::abs(agreement[best]) > 10 * noise;
  std::vector<bool> sign_ok;
  for (double a : agreement) sign_ok.push_back(!signed_by_urdf || a >= 0);
  if (signed_by_urdf) {
    bool any = false;
    for (size_t i = 0; i < ssr.size(); ++i) any |= f.tie[i] && sign_ok[i];
    if (any)
      for (size_t i = 0; i < ssr.size(); ++i) f.tie[i] = f.tie[i] && sign_ok[i];
    f.identity_out = !f.tie[0] && (f.identity_out || !sign_ok[0]);
  }
  return f;
}

// "'fz' is negated", "'fx' holds fy and 'fy' holds fx": what P says about the
// columns (recorded k = P(k, j) true j), and the fix ("negate fz", ...).
std::string channels_text(const Eigen::Matrix3d& P, char kind, std::string* fix) {
  const char axis[3] = {'x', 'y', 'z'};
  std::vector<std::string> what, how;
  for (int k = 0; k < 3; ++k) {
    int j = 0;
    while (P(k, j) == 0.0) ++j;
    const bool neg = P(k, j) < 0;
    if (j == k && !neg) continue;
    if (j == k) {
      what.push_back(fmt::format("'{}{}' is negated", kind, axis[k]));
      how.push_back(fmt::format("negate {}{}", kind, axis[k]));
    } else {
      what.push_back(
          fmt::format("'{}{}' holds {}{}{}", kind, axis[k], neg ? "-" : "", kind, axis[j]));
      how.push_back(fmt::format("take {}{} from column {}{}{}", kind, axis[j], neg ? "minus " : "",
                                kind, axis[k]));
    }
  }
  // "a", "a and b", "a, b and c".
  auto join = [](const std::vector<std::string>& v) {
    return v.size() < 2
               ? fmt::format("{}", fmt::join(v, ""))
               : fmt::format("{} and {}", fmt::join(v.begin(), v.end() - 1, ", "), v.back());
  };
  if (fix) *fix = join(how);
  return join(what);
}

// force-channels / moment-channels: a channel negated or two channels swapped
// (a reflection: no frame rotation explains it), found by the tests above.
void report_channels(Context& c, const ChannelTest& t, char kind, const ChannelTest* also) {
  std::string fix, fix_also;
  const std::string what = channels_text(t.P, kind, &fix);
  std::string extra;
  if (also) {
    extra = fmt::format(
        "; the moments too: {} (moment residual RMS {:.3g} N m as recorded, {:.3g} "
        "N m so)",
        channels_text(also->P, 'm', &fix_also), also->rms_recorded, also->rms_best);
    fix += " and " + fix_also;
  }
  const bool force = kind == 'f';
  c.add(Severity::Error, force ? "force-channels" : "moment-channels",
        fmt::format("{}: the {} channels do not fit the URDF with gx,gy,gz as recorded ({}), but "
                    "do if {} ({} residual RMS {:.3g} {} as recorded, {:.3g} {} so){}: a sign or "
                    "the column mapping is wrong in the sensor's configuration or the logger; {} "
                    "(massid wants the sensor's own right-handed axes)",
                    c.s.source, force ? "force" : "moment", c.lines(), what,
                    force ? "force" : "moment", t.rms_recorded, force ? "N" : "N m", t.rms_best,
                    force ? "N" : "N m", extra, fix));
}

// The median of |f_i| over the rows (robust to an offset and a few bad rows).
double median_force(const Context& c) {
  const Eigen::VectorXd n = c.F.rowwise().norm();
  return median({n.data(), n.data() + n.size()});
}

// force-units. Statistic: r = median |f_i| / (M g0), the total mass the force
// implies over the URDF's (offset-robust: the median of magnitudes). Error for
// r in [316, 3162]: forces in mN.
void check_force_units(Context& c) {
  if (!(c.M > 0)) return;
  const double f = median_force(c);
  const double r = f / (c.M * kStandardGravity);
  if (r >= kUnitLow && r <= kUnitHigh)
    c.add(Severity::Error, "force-units",
          fmt::format("{}: fx,fy,fz imply a total mass of {:.4g} kg, {:.0f} times the URDF's "
                      "{:.4g} kg (median |f| {:.4g} over {}): the forces look like mN; divide "
                      "fx,fy,fz by 1000 (massid wants N)",
                      c.s.source, r * c.M, r, c.M, f, c.lines()));
}

// moment-units. Statistics: r = RMS |m_i| / RMS |m_URDF,i| (the measured
// moments over the URDF's, at a subset of rows), and the lever arm they imply,
// L = RMS |m_i| / (M g0), against the robot's reach (the farthest link origin
// or centre of mass from the sensor origin). Error when r is in [316, 3162]
// and L exceeds 3 times the reach plus 1 cm: no offset or inertial error
// explains a lever arm longer than the robot.
void check_moment_units(Context& c) {
  if (!(c.M > 0) || c.sub.empty()) return;
  const double n = static_cast<double>(c.sub.size());
  const double rms_meas = std::sqrt(c.s.wrench(c.sub, Eigen::seqN(3, 3)).squaredNorm() / n);
  const double rms_nom = std::sqrt(c.nom.rightCols(3).squaredNorm() / n);
  if (!(rms_nom > 0)) return;
  const double r = rms_meas / rms_nom, lever = rms_meas / (c.M * kStandardGravity);
  if (r >= kUnitLow && r <= kUnitHigh && lever > 3.0 * c.reach + 0.01)
    c.add(Severity::Error, "moment-units",
          fmt::format("{}: mx,my,mz are {:.0f} times what the URDF predicts (RMS {:.4g}, lever arm "
                      "{:.3g} m for a robot that reaches {:.3g} m, {}): the moments look like N "
                      "mm; divide mx,my,mz by 1000 (massid wants N m)",
                      c.s.source, r, rms_meas, lever, c.reach, c.lines()));
}

// force-units / moment-units when the URDF has no mass (no <inertial> on any
// measured link): nothing to compare the wrench with but the robot's size.
// Statistic: the lever arm L = RMS |m_i| / RMS |f_i| (the distance of the
// centre of mass from the sensor origin across gravity, RMS over the poses)
// against the reach (the farthest link origin from the sensor origin, over
// the poses). Moments in N mm make L ~1000 x too long: error when L > 30 x
// reach + 1 cm (no centre of mass lies that far outside the links). Forces in
// mN make L ~1000 x too short and the implied mass huge: error when L <
// reach / 300 and the implied mass median |f| / g0 exceeds 1000 kg per cubic
// metre of reach^3 (a robot denser than a block of water its own size; the
// UR5, 21 kg at 0.9 m, is 29 kg/m^3). Needs a reach of at least 5 cm.
void check_units_without_mass(Context& c) {
  if (c.M > 0 || c.N < 1 || !(c.reach >= 0.05)) return;
  const double rms_f = std::sqrt(c.F.squaredNorm() / c.N);
  const double rms_m = std::sqrt(c.s.wrench.rightCols(3).squaredNorm() / c.N);
  if (!(rms_f > 0)) return;
  const double lever = rms_m / rms_f;
  const double mass = median_force(c) / kStandardGravity;
  const std::string why = fmt::format(
      "the URDF has no mass (no <inertial> on a measured link), so the wrench is judged by the "
      "robot's size: RMS |m| / RMS |f| puts the centre of mass {:.3g} m from the sensor origin, "
      "for a robot that reaches {:.3g} m, {}",
      lever, c.reach, c.lines());
  if (lever > 30.0 * c.reach + 0.01)
    c.add(Severity::Error, "moment-units",
          fmt::format("{}: {}: the moments look like N mm; divide mx,my,mz by 1000 (massid wants "
                      "N m)",
                      c.s.source, why));
  else if (lever < c.reach / 300.0 && mass > 1000.0 * std::pow(c.reach, 3))
    c.add(Severity::Error, "force-units",
          fmt::format("{}: {}, and fx,fy,fz imply a total mass of {:.4g} kg: the forces look like "
                      "mN; divide fx,fy,fz by 1000 (massid wants N)",
                      c.s.source, why, mass));
}

// The degrees message's words on the derivatives: "(and its velocity and
// acceleration in deg/s, deg/s^2 'J_deg_vel', 'J_deg_acc')".
std::string degree_derivatives(const std::string& joint) {
  return fmt::format(
      " (and its velocity and acceleration in deg/s, deg/s^2, if any, '{0}_deg_vel' and "
      "'{0}_deg_acc')",
      joint);
}

// joint-degrees / joint-millimetres. Statistic per joint column named as the
// joint (not JOINT_deg): the largest excursion beyond the URDF limits, and
// whether every value divided by 57.2958 (revolute) or 1000 (prismatic) lies
// within them. Tolerance: 0.05 rad or m plus 5 % of the range. Error for a
// limited joint more than 0.5 rad (0.05 m plus 10 % of the range) outside
// while the converted values fit: a joint in the wrong unit makes the
// kinematics, hence every parameter, wrong. A continuous joint has no limits:
// more than one turn each way (|q| > 2 pi + 0.5) with |q| / 57.3 within a turn
// is a warning (a static experiment rarely winds a joint up), more than two
// turns an error.
void check_joint_units(Context& c) {
  for (int j = 0; j < c.model.num_joints(); ++j) {
    const Joint& joint = c.model.joints[j];
    if (std::find(c.header.begin(), c.header.end(), joint.name) == c.header.end() &&
        !c.header.empty())
      continue;  // a JOINT_deg column
    const Eigen::VectorXd q = c.s.q.col(j);
    const double qmax = q.cwiseAbs().maxCoeff();
    auto rows_where = [&](auto pred) {
      std::vector<int> r;
      for (int i = 0; i < c.N; ++i)
        if (pred(q[i])) r.push_back(i);
      return r;
    };
    if (joint.type == JointType::Revolute) {
      const double to_rad = kDeg;
      if (joint.limited) {
        const double tol = 0.05 + 0.05 * (joint.upper - joint.lower);
        const double excess =
            std::max({0.0, q.maxCoeff() - joint.upper, joint.lower - q.minCoeff()});
        const bool fits = to_rad * q.maxCoeff() <= joint.upper + tol &&
                          to_rad * q.minCoeff() >= joint.lower - tol;
        if (excess > 0.5 && excess > tol && fits) {
          const auto out =
              rows_where([&](double v) { return v > joint.upper + tol || v < joint.lower - tol; });
          c.add(Severity::Error, "joint-degrees",
                fmt::format(
                    "{}: column '{}' reaches {:.4g} at {}, beyond the URDF limits [{:.4g}, "
                    "{:.4g}] rad, and every value fits them read as degrees: rename the "
                    "column '{}_deg'{} or convert it to radians",
                    c.s.source, joint.name,
                    std::abs(q.maxCoeff()) > std::abs(q.minCoeff()) ? q.maxCoeff() : q.minCoeff(),
                    lines_text(c.s, out), joint.lower, joint.upper, joint.name,
                    degree_derivatives(joint.name)));
        }
      } else if (qmax > 2 * std::numbers::pi + 0.5 &&
                 to_rad * qmax <= 2 * std::numbers::pi + 0.05) {
        const auto out = rows_where([&](double v) { return std::abs(v) > 2 * std::numbers::pi; });
        const bool two_turns = qmax > 4 * std::numbers::pi;
        c.add(two_turns ? Severity::Error : Severity::Warning, "joint-degrees",
              fmt::format("{}: continuous joint column '{}' reaches |q| = {:.4g} rad ({:.1f} "
                          "turns) at {}; read as degrees it stays within one turn: if it is in "
                          "degrees, rename the column '{}_deg'{} or convert it to radians",
                          c.s.source, joint.name, qmax, qmax / (2 * std::numbers::pi),
                          lines_text(c.s, out), joint.name, degree_derivatives(joint.name)));
      }
    } else if (joint.type == JointType::Prismatic && joint.limited) {
      const double range = joint.upper - joint.lower;
      const double tol = 0.05 * range + 0.005;
      const double excess = std::max({0.0, q.maxCoeff() - joint.upper, joint.lower - q.minCoeff()});
      const bool fits =
          q.maxCoeff() / 1000 <= joint.upper + tol && q.minCoeff() / 1000 >= joint.lower - tol;
      if (excess > 0.05 + 0.1 * range && fits) {
        const auto out =
            rows_where([&](double v) { return v > joint.upper + tol || v < joint.lower - tol; });
        c.add(Severity::Error, "joint-millimetres",
              fmt::format("{}: prismatic joint column '{}' reaches {:.4g} at {}, beyond the URDF "
                          "limits [{:.4g}, {:.4g}] m, and every value fits them read as mm: "
                          "divide the column by 1000 (massid wants m)",
                          c.s.source, joint.name, q[out.front()], lines_text(c.s, out), joint.lower,
                          joint.upper));
      }
    }
  }
}

// joint-derivatives. Statistic per joint with a _vel column (and per joint
// with an _acc column): the least-squares scale s of the column y on the
// central difference d_i = (x_{i+1} - x_{i-1}) / (t_{i+1} - t_{i-1}) of the
// column it is the derivative of (position for _vel, _vel for _acc), s = sum
// y_i d_i / sum d_i^2, over the rows where |y_i| is at least a quarter of its
// 90th percentile (motion well above the noise) and the three rows lie in
// one block with t increasing; needs t and 20 such rows. Error when s <= 0 or
// max(s, 1/s) > 1.5: a column in another unit (deg/s read as rad/s: 57.3) or
// scaled by a driver (2, 0.5) makes every dynamic parameter wrong while the
// fit's chi^2 (sigma estimated from its own residuals) looks normal. A coarse
// sampling of fast motion lowers |d| by sin(w dt) / (w dt): 0.84 at one
// radian per sample, far inside the bound.
constexpr double kDerivativeScale = 1.5;
constexpr int kDerivativeRows = 20;

// The scale s of y on the derivative of x (above); NaN when the rows do not tell.
double derivative_scale(const Samples& s, const Eigen::VectorXd& x, const Eigen::VectorXd& y) {
  const int N = static_cast<int>(x.size());
  std::vector<int> rows;
  std::vector<double> d(N, 0.0), mag;
  for (int i = 1; i + 1 < N; ++i) {
    if (!s.block.empty() && (s.block[i - 1] != s.block[i] || s.block[i + 1] != s.block[i]))
      continue;
    const double dt = s.time[i + 1] - s.time[i - 1];
    if (!(dt > 0) || !std::isfinite(dt)) continue;
    d[i] = (x[i + 1] - x[i - 1]) / dt;
    rows.push_back(i);
    mag.push_back(std::abs(y[i]));
  }
  if (static_cast<int>(rows.size()) < kDerivativeRows) return std::nan("");
  std::nth_element(mag.begin(), mag.begin() + mag.size() * 9 / 10, mag.end());
  const double floor = 0.25 * mag[mag.size() * 9 / 10];
  if (!(floor > 0)) return std::nan("");  // the joint does not move
  double yd = 0.0, dd = 0.0;
  int used = 0;
  for (const int i : rows)
    if (std::abs(y[i]) >= floor) {
      yd += y[i] * d[i];
      dd += d[i] * d[i];
      ++used;
    }
  if (used < kDerivativeRows) return std::nan("");
  return dd > 0 ? yd / dd : std::nan("");
}

void check_joint_derivatives(Context& c) {
  const Samples& s = c.s;
  if (s.time.size() != c.N) return;
  struct Group {
    const std::vector<Joint>* joints;
    const Eigen::MatrixXd *q, *qd, *qdd;
  };
  for (const Group& g :
       {Group{&c.model.joints, &s.q, &s.qd, &s.qdd},
        Group{&c.model.upstream_joints, &s.q_upstream, &s.qd_upstream, &s.qdd_upstream}}) {
    const int n = static_cast<int>(g.joints->size());
    for (int j = 0; j < n; ++j) {
      const Joint& joint = (*g.joints)[j];
      // (x, y, the column of y, the column of x, suffix of y)
      for (int order = 1; order <= 2; ++order) {
        const Eigen::MatrixXd& X = order == 1 ? *g.q : *g.qd;
        const Eigen::MatrixXd& Y = order == 1 ? *g.qd : *g.qdd;
        if (X.cols() != n || Y.cols() != n || X.rows() != c.N || Y.rows() != c.N) continue;
        const double k = derivative_scale(s, X.col(j), Y.col(j));
        if (!std::isfinite(k) || (k > 0 && std::max(k, 1 / k) <= kDerivativeScale)) continue;
        const std::string suffix = order == 1 ? "_vel" : "_acc";
        const std::string ycol = joint_column(joint, c.header, suffix);
        const std::string xcol = joint_column(joint, c.header, order == 1 ? "" : "_vel");
        const bool degrees = joint.type == JointType::Revolute;
        std::string fix;
        if (degrees && std::abs(k * kDeg - 1) < 0.05 && ycol == joint.name + suffix)
          fix = fmt::format("it holds {}: declare it as '{}_deg{}' (read in {})",
                            order == 1 ? "deg/s" : "deg/s^2", joint.name, suffix,
                            order == 1 ? "rad/s" : "rad/s^2");
        else if (degrees && std::abs(k / kDeg - 1) < 0.05 && ycol != joint.name + suffix)
          fix = fmt::format("it holds {}: name it '{}{}'", order == 1 ? "rad/s" : "rad/s^2",
                            joint.name, suffix);
        else if (k < 0)
          fix = "negate it";
        else
          fix = fmt::format("divide it by {:.3g} or correct its unit (t in s, {} per s{})", k,
                            order == 1 ? "position" : "velocity", order == 1 ? "" : "^2");
        c.add(Severity::Error, "joint-derivatives",
              fmt::format("{}: column '{}' is {:.3g} times the derivative of column '{}' over t "
                          "(least squares over the rows in motion; 1 expected): {}",
                          s.source, ycol, k, xcol, fix));
        break;  // one finding per joint
      }
    }
  }
}

// duplicate-columns, constant-wrench, constant-joint. Statistics: exact
// equality of two columns over every row, exact constancy of one (both
// impossible for a live sensor channel with noise), over at least 3 rows.
// Wrench columns are judged against the URDF's wrench at the subset of rows,
// so noise-free data that physics makes constant or equal (fy = 0 when the
// plan tilts about y only) are not flagged: a constant channel must vary in
// the URDF's wrench by 5 % of the largest range of its kind (forces, moments),
// two equal channels must differ there by 1 %.
// Severity: a dead or duplicated wrench channel feeds wrong numbers into every
// fit (error); joints that are equal or constant only limit what the data can
// determine, which identify diagnoses itself (warning).
// Returns whether a force column is dead or duplicated (then the sign and
// frame checks, which would only echo it, are skipped).
bool check_columns(Context& c, const SetupCheckOptions& options) {
  if (c.N < kMinRows) return false;
  bool force_broken = false;
  const Eigen::MatrixXd& W = c.s.wrench;
  // Ranges of the URDF's wrench per axis, and of its kind.
  Eigen::Matrix<double, 6, 1> range = Eigen::Matrix<double, 6, 1>::Zero();
  if (c.nom.rows() > 0) range = c.nom.colwise().maxCoeff() - c.nom.colwise().minCoeff();
  const double kind_range[2] = {std::max(range.head<3>().maxCoeff(), 0.0),
                                range.tail<3>().maxCoeff()};
  const bool wrench = c.s.has_wrench();  // a plan has none
  bool wrench_constant[6];
  for (int a = 0; a < 6; ++a) {
    wrench_constant[a] = wrench && constant(W.col(a));
    const double scale = kind_range[a / 3];
    if (wrench_constant[a] && scale > 0 && range[a] > 0.05 * scale) {
      force_broken |= a < 3;
      c.add(
          Severity::Error, "constant-wrench",
          fmt::format(
              "{}: column '{}' is {} in all {} rows ({}), yet the URDF's {} varies by {:.4g} {} "
              "over them: the channel looks dead (cable, logger, wrong column); fix the recording",
              c.s.source, kWrenchColumns[a], W(0, a), c.N, c.lines(), kWrenchColumns[a], range[a],
              a < 3 ? "N" : "N m"));
    }
  }
  for (int a = 0; a < 6; ++a)
    for (int b = a + 1; b < 6; ++b) {
      if (!wrench || wrench_constant[a] || wrench_constant[b] || W.col(a) != W.col(b)) continue;
      const double scale = std::max(kind_range[a / 3], kind_range[b / 3]);
      const double differ =
          c.nom.rows() > 0 ? (c.nom.col(a) - c.nom.col(b)).cwiseAbs().maxCoeff() : 0.0;
      if (!(differ > 0.01 * scale)) continue;
      force_broken |= a < 3 || b < 3;
      c.add(Severity::Error, "duplicate-columns",
            fmt::format("{}: columns '{}' and '{}' are identical in all {} rows ({}): one channel "
                        "was recorded twice; fix the logger's column mapping",
                        c.s.source, kWrenchColumns[a], kWrenchColumns[b], c.N, c.lines()));
    }
  const int nj = c.model.num_joints();
  std::vector<bool> joint_constant(nj);
  for (int j = 0; j < nj; ++j) {
    joint_constant[j] = constant(c.s.q.col(j));
    const std::string col = joint_column(c.model.joints[j], c.header);
    if (joint_constant[j] && options.constant_joints)
      c.add(
          Severity::Warning, "constant-joint",
          fmt::format("{}: column '{}' is {} in all {} rows ({}): joint '{}' never moves, so the "
                      "parameters only its motion separates cannot be identified; move it in the "
                      "plan, or if it was held still, hold it at its value",
                      c.s.source, col, format_number(c.s.q(0, j)), c.N, c.lines(),
                      c.model.joints[j].name),
          {{Hint::Setting::HoldJoints, c.model.joints[j].name + "=" + format_number(c.s.q(0, j))}});
  }
  for (int a = 0; a < nj; ++a)
    for (int b = a + 1; b < nj; ++b) {
      if (joint_constant[a] || joint_constant[b] || c.s.q.col(a) != c.s.q.col(b)) continue;
      c.add(Severity::Warning, "duplicate-columns",
            fmt::format(
                "{}: joint columns '{}' and '{}' are identical in all {} rows ({}): if the logger "
                "wrote one joint into both, fix its column mapping; if the joints really moved "
                "together, the data cannot separate what each moves (move them independently)",
                c.s.source, joint_column(c.model.joints[a], c.header),
                joint_column(c.model.joints[b], c.header), c.N, c.lines()));
    }
  return force_broken;
}

}  // namespace

// --- rows against gravity ------------------------------------------------------

// rows_against_gravity. At rest f_i = A g_i + b for every mechanism and every
// consistent wiring (A = M R for a rotated frame, M P for swapped or negated
// channels, -M for the reaction), so a file that is consistent fits that map
// at every row to its noise. The fit is a least trimmed squares one (the
// majority h = N/2 + 1 of rows with the smallest residuals, concentration
// steps from the fit on every row and on each eighth of the file: contact
// comes in runs of consecutive rows, so one eighth is clean), then the noise
// sigma per axis from the median residual (chi_3 median 2.366) and, refitted
// on the rows within it, from their residual sum of squares. A row is against
// gravity when |r_i| / sigma exceeds chi_3 at 1 % / N: a clean file has none
// with probability 99 %. sigma has a floor of 1e-9 of the RMS force, so
// noise-free data are judged by round-off, not by nothing.
std::vector<int> rows_against_gravity(const Samples& s) {
  const int N = s.size();
  if (!s.has_wrench() || s.gravity_from_force || s.gravity.rows() != N || N < 8) return {};
  const Eigen::MatrixXd F = s.wrench.leftCols(3);
  Eigen::MatrixXd X(N, 4);
  X.leftCols(3) = s.gravity;
  const double scale = s.gravity.cwiseAbs().maxCoeff();
  if (!(scale > 0) || !std::isfinite(scale) || !F.allFinite()) return {};
  X.leftCols(3) /= scale;
  X.col(3).setOnes();
  using Map = Eigen::Matrix<double, 4, 3>;
  const auto fit = [&](const std::vector<int>& rows) -> Map {
    return Eigen::MatrixXd(X(rows, Eigen::all))
        .completeOrthogonalDecomposition()
        .solve(Eigen::MatrixXd(F(rows, Eigen::all)));
  };
  const auto squared = [&](const Map& B) -> Eigen::VectorXd {
    return (F - X * B).rowwise().squaredNorm();
  };
  const int h = N / 2 + 1;
  const auto smallest = [&](const Eigen::VectorXd& r2) {
    std::vector<int> idx(static_cast<size_t>(N));
    std::iota(idx.begin(), idx.end(), 0);
    std::nth_element(idx.begin(), idx.begin() + (h - 1), idx.end(),
                     [&](int a, int b) { return r2[a] < r2[b]; });
    idx.resize(static_cast<size_t>(h));
    std::sort(idx.begin(), idx.end());
    return idx;
  };
  std::vector<std::vector<int>> starts;
  starts.emplace_back(static_cast<size_t>(N));
  std::iota(starts.back().begin(), starts.back().end(), 0);
  for (int b = 0; b < 8; ++b) {
    std::vector<int> block;
    for (int i = b * N / 8; i < (b + 1) * N / 8; ++i) block.push_back(i);
    if (block.size() >= 4) starts.push_back(std::move(block));
  }
  Map best = Map::Zero();
  double best_objective = std::numeric_limits<double>::infinity();
  for (const std::vector<int>& start : starts) {
    Map B = fit(start);
    std::vector<int> kept;
    for (int step = 0; step < 30; ++step) {
      std::vector<int> next = smallest(squared(B));
      if (next == kept) break;
      kept = std::move(next);
      B = fit(kept);
    }
    const double objective = squared(B)(kept).sum();
    if (objective < best_objective) {
      best_objective = objective;
      best = B;
    }
  }
  const double floor2 = std::pow(1e-9 * std::sqrt(F.squaredNorm() / N), 2) + 1e-300;
  const double cut2 = std::pow(detail::chi_quantile(0.01 / N, 3), 2);
  Eigen::VectorXd r2 = squared(best);
  std::vector<double> all(r2.data(), r2.data() + N);
  double sigma2 = std::max(median(all) / 2.366, floor2);
  std::vector<int> kept;
  for (int pass = 0; pass < 2; ++pass) {
    kept.clear();
    for (int i = 0; i < N; ++i)
      if (r2[i] <= cut2 * sigma2) kept.push_back(i);
    if (static_cast<int>(kept.size()) < h) return {};  // not a minority against the map
    const Map B = fit(kept);
    r2 = squared(B);
    sigma2 = std::max(r2(kept).sum() / std::max(1.0, 3.0 * static_cast<double>(kept.size()) - 12.0),
                      floor2);
  }
  std::vector<int> away;
  for (int i = 0; i < N; ++i)
    if (r2[i] > cut2 * sigma2) away.push_back(i);
  if (2 * static_cast<int>(away.size()) >= N) return {};
  return away;
}

namespace {

// The wiring checks (channels, sign, rotation) on the rows consistent with
// gravity: a verdict holds over the file, never from a minority of rows.
void check_wiring(Context& c) {
  const Centred k = centre(c);
  // Which signed permutation of the channels the data fit (a negated or
  // swapped channel), before the sign and rotation checks: a reflection
  // is no rotation, and a rotation (180 deg about z: fx, fy negated) no
  // sign error.
  const ChannelFit mf = moment_channels(c), ff = force_channels(c, k);
  const ChannelTest mt = mf.tie.empty() ? ChannelTest{} : pick_channels(mf, &ff.tie);
  const ChannelTest ft = ff.tie.empty() ? ChannelTest{} : pick_channels(ff, &mf.tie);
  const bool rotation = ft.decisive() && ft.P.determinant() > 0;
  const bool negated = ft.decisive() && ft.P == -Eigen::Matrix3d::Identity();
  const bool same = mt.decisive() && mt.P == ft.P;
  if (ft.decisive() && !rotation && !negated)
    report_channels(c, ft, 'f', same ? &mt : nullptr);
  else if (rotation)
    check_rotation(c, k);
  else if (!check_sign(c, k))
    check_rotation(c, k);
  if (mt.decisive() && !same) report_channels(c, mt, 'm', nullptr);
}

}  // namespace

std::vector<SetupFinding> check_setup(const Model& model, const Samples& samples,
                                      const std::vector<std::string>& header,
                                      const SetupCheckOptions& options) {
  std::vector<SetupFinding> out;
  if (samples.size() == 0) return out;
  Context c(model, samples, header, out);
  nominal(c);
  const bool wrench = samples.has_wrench();  // a plan has none: its joints and gravity only
  const bool force_broken = check_columns(c, options);
  if (!samples.gravity_from_force) {
    check_gravity_magnitude(c);
    if (wrench && !force_broken && !options.motion) {
      // The rows an external wrench drives (contact) set aside, when a
      // minority (rows_against_gravity).
      const std::vector<int> away = rows_against_gravity(samples);
      if (away.empty()) {
        check_wiring(c);
      } else {
        std::vector<int> all(static_cast<size_t>(c.N)), rows;
        std::iota(all.begin(), all.end(), 0);
        std::set_difference(all.begin(), all.end(), away.begin(), away.end(),
                            std::back_inserter(rows));
        const Samples consistent = sample_rows(samples, rows);
        Context cc(model, consistent, header, out);
        nominal(cc);
        check_wiring(cc);
      }
    }
  }
  if (wrench) {
    check_force_units(c);
    check_moment_units(c);
    check_units_without_mass(c);
  }
  check_joint_units(c);
  check_joint_derivatives(c);
  // Errors first: they decide the outcome.
  std::stable_partition(out.begin(), out.end(),
                        [](const SetupFinding& f) { return f.severity == Severity::Error; });
  return out;
}

Samples read_samples_head(const Model& model, const std::string& path, int max_rows,
                          std::vector<std::string>* header, const SampleOptions& read,
                          bool motion) {
  return detail::read_file_samples(model, path, max_rows, read, header, motion);
}

std::vector<SetupFinding> check_setup_file(const Model& model, const std::string& path,
                                           const SetupCheckOptions& options) {
  std::vector<std::string> header;
  const Samples s =
      read_samples_head(model, path, options.max_rows, &header, options.read, options.motion);
  return check_setup(model, s, header, options);
}

bool has_error(const std::vector<SetupFinding>& findings) {
  return std::any_of(findings.begin(), findings.end(),
                     [](const SetupFinding& f) { return f.severity == Severity::Error; });
}

std::vector<SetupFinding> SetupVerdict::shown() const {
  const bool error = refused();
  std::vector<SetupFinding> out;
  for (const SetupFinding& f : findings)
    if (error == (f.severity == Severity::Error)) out.push_back(f);
  return out;
}

std::vector<Warning> SetupVerdict::warnings() const {
  std::vector<Warning> out;
  if (refused()) return out;
  for (const SetupFinding& f : findings) out.push_back({f.message, f.hints});
  return out;
}

SetupVerdict check_input_setup(const Model& model, const Samples& samples,
                               const std::vector<std::string>& header, bool motion) {
  SetupCheckOptions o;
  o.constant_joints = false;  // a plan may hold a joint still on purpose
  o.motion = motion;
  return {check_setup(model, samples, header, o)};
}

namespace {

std::string refusal_message(const std::vector<SetupFinding>& errors) {
  std::string out;
  for (const SetupFinding& f : errors) out += (out.empty() ? "" : "\n") + f.message;
  return out;
}

std::vector<Hint> refusal_hints(const std::vector<SetupFinding>& errors) {
  std::vector<Hint> out;
  for (const SetupFinding& f : errors)
    for (const Hint& h : f.hints)
      if (std::find(out.begin(), out.end(), h) == out.end()) out.push_back(h);
  return out;
}

}  // namespace

std::optional<SetupFinding> check_fitted_weight(const Model& model, const BaseParameters& base,
                                                const IdentifySummary& summary,
                                                const std::string& source) {
  const int m = base.total_mass;
  if (m < 0 || m >= summary.value.size() || m >= summary.stddev.size()) return std::nullopt;
  const double M = summary.value[m], sd = summary.stddev[m];
  if (!(M + 5.0 * sd < 0.0)) return std::nullopt;
  return SetupFinding{
      SetupFinding::Severity::Error,
      "wrench-sign",
      fmt::format("{}: the fit gives a total mass of {:.4g} +- {:.2g} kg (the URDF's {:.4g} kg): "
                  "the measured force points against gravity. massid wants the wrench the "
                  "bodies exert on the sensor (at rest f = M g; in motion their weight minus "
                  "the rate of change of their momentum). If the sensor reports the reaction "
                  "(MuJoCo, force plates, some drivers), negate fx,fy,fz,mx,my,mz; if gravity "
                  "points up (gx,gy,gz, or the root gravity), negate it",
                  source, M, sd, model.nominal_total_mass()),
      {{Hint::Setting::Checks, "off"}}};
}

SetupRefused::SetupRefused(std::vector<SetupFinding> errors)
    : InputError(refusal_message(errors), refusal_hints(errors)), errors_(std::move(errors)) {}

// --- contact episodes ---------------------------------------------------------

std::vector<ContactEpisode> find_contact_episodes(const std::vector<Outlier>& flagged,
                                                  double threshold, const ContactOptions& options) {
  std::vector<Outlier> rows = flagged;
  std::sort(rows.begin(), rows.end(),
            [](const Outlier& a, const Outlier& b) { return a.sample < b.sample; });
  std::vector<ContactEpisode> out;
  const double nan = std::numeric_limits<double>::quiet_NaN();
  const int min_rows = std::max(1, options.min_rows);
  size_t k = 0;
  while (k < rows.size()) {
    ContactEpisode e;
    e.first = e.last = rows[k].sample;
    e.first_line = e.last_line = rows[k].line;
    e.threshold = threshold;
    e.force = e.moment = nan;
    for (; k < rows.size() && rows[k].sample - e.last <= options.max_gap + 1; ++k) {
      e.last = rows[k].sample;
      e.last_line = rows[k].line;
      ++e.rows;
      e.score = std::max(e.score, rows[k].score);
    }
    if (e.rows >= min_rows) out.push_back(e);
  }
  return out;
}

namespace {

// The measured wrench's RMS of force and moment over the rows with a finite
// residual (the residual's own without a measured wrench); NaN with fewer
// than two such rows (or a residual not [N x 6], which beyond_noise refuses).
Eigen::Vector2d measured_rms(const Samples& samples, const Eigen::MatrixXd& residual) {
  const int N = static_cast<int>(residual.rows());
  Eigen::Vector2d sum = Eigen::Vector2d::Zero();  // of |force|^2, |moment|^2
  int finite = 0;
  const bool measured = samples.wrench.rows() == N && samples.wrench.cols() == 6;
  for (int i = 0; i < N && residual.cols() == 6; ++i)
    if (residual.row(i).allFinite()) {
      const auto w = measured && samples.wrench.row(i).allFinite()
                         ? Eigen::Matrix<double, 1, 6>(samples.wrench.row(i))
                         : Eigen::Matrix<double, 1, 6>(residual.row(i));
      sum += Eigen::Vector2d(w.head<3>().squaredNorm(), w.tail<3>().squaredNorm());
      ++finite;
    }
  if (finite < 2) return Eigen::Vector2d::Constant(std::numeric_limits<double>::quiet_NaN());
  return (sum / finite).cwiseSqrt();
}

// The rows beyond the noise (d above the threshold), the threshold and each
// axis' centre (median).
struct Beyond {
  std::vector<Outlier> rows;
  double threshold = 0.0;
  Eigen::Matrix<double, 6, 1> centre = Eigen::Matrix<double, 6, 1>::Zero();
};

Beyond beyond_noise(const std::vector<int>& line, const Eigen::MatrixXd& residual,
                    const Eigen::Vector2d& measured_rms, const ContactOptions& options) {
  const int N = static_cast<int>(residual.rows());
  if (N < 2 || residual.cols() != 6 || static_cast<int>(line.size()) != N)
    throw std::invalid_argument(
        "find_contact_episodes: residual must be [N x 6] with one file line per row");
  Beyond out;
  const auto finite = residual.array().isFinite().rowwise().all().count();
  if (finite < 2 || !measured_rms.allFinite()) return out;
  // Per axis: median and robust scale of the finite residuals; a floor of
  // 1e-9 of the measured wrench's RMS of its kind (noise-free data: round-off
  // is no contact).
  Eigen::Matrix<double, 6, 1> scale;
  for (int a = 0; a < 6; ++a) {
    std::vector<double> v;
    for (int i = 0; i < N; ++i)
      if (residual.row(i).allFinite()) v.push_back(residual(i, a));
    out.centre[a] = median(v);
    for (double& x : v) x = std::abs(x - out.centre[a]);
    scale[a] = std::max(1.4826 * median(v), 1e-9 * measured_rms[a / 3] + 1e-300);
  }
  out.threshold = detail::chi_quantile(options.probability / finite, 6);
  for (int i = 0; i < N; ++i) {
    if (!residual.row(i).allFinite()) continue;
    const double d =
        ((residual.row(i).transpose() - out.centre).array() / scale.array()).matrix().norm();
    if (d > out.threshold) out.rows.push_back({i, line[i], d});
  }
  return out;
}

}  // namespace

std::vector<Outlier> rows_beyond_noise(const Samples& samples, const Eigen::MatrixXd& residual,
                                       double* threshold, const ContactOptions& options) {
  // Samples without file lines (built in memory): the row indices.
  std::vector<int> index;
  if (samples.line.empty()) {
    index.resize(static_cast<size_t>(residual.rows()));
    std::iota(index.begin(), index.end(), 0);
  }
  Beyond b = beyond_noise(samples.line.empty() ? index : samples.line, residual,
                          measured_rms(samples, residual), options);
  if (threshold) *threshold = b.threshold;
  return std::move(b.rows);
}

std::vector<ContactEpisode> find_contact_episodes(const std::vector<int>& line,
                                                  const Eigen::MatrixXd& residual,
                                                  const Eigen::Vector2d& measured_rms,
                                                  const ContactOptions& options) {
  const Beyond b = beyond_noise(line, residual, measured_rms, options);
  if (b.threshold == 0.0) return {};
  std::vector<ContactEpisode> out = find_contact_episodes(b.rows, b.threshold, options);
  for (ContactEpisode& e : out) {
    e.force = e.moment = 0.0;
    for (int i = e.first; i <= e.last; ++i) {
      if (!residual.row(i).allFinite()) continue;
      const Wrench w = residual.row(i).transpose() - b.centre;
      e.force = std::max(e.force, w.head<3>().norm());
      e.moment = std::max(e.moment, w.tail<3>().norm());
    }
  }
  return out;
}

std::vector<ContactEpisode> find_contact_episodes(const Samples& samples,
                                                  const Eigen::MatrixXd& residual,
                                                  const ContactOptions& options) {
  return find_contact_episodes(samples.line, residual, measured_rms(samples, residual), options);
}

std::string contact_place(const ContactEpisode& e) {
  return fmt::format("lines {}-{} ({} rows)", e.first_line, e.last_line, e.last - e.first + 1);
}

std::string contact_note(const std::string& source, const ContactEpisode& e) {
  return fmt::format(
      "{}: {} carry an external wrench of up to {:.3g} N, {:.3g} N m (contact; residual up to "
      "{:.3g} times the noise, threshold {:.3g}): fx_comp..mz_comp hold it",
      source, contact_place(e), e.force, e.moment, e.score, e.threshold);
}

}  // namespace massid
