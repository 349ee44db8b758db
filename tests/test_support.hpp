// Shared helpers of the library tests: the example robots and their plans.
#pragma once

#include <Eigen/Core>
#include <Eigen/SVD>
#include <algorithm>
#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"
#include "massid/core/predictor.hpp"
#include "massid/core/regressor.hpp"
#include "massid/core/samples.hpp"
#include "massid/identify/estimation.hpp"
#include "massid/io/csv.hpp"
#include "massid/io/read_samples.hpp"

namespace massid::test {

// Radians per degree.
inline constexpr double kDeg = std::numbers::pi / 180.0;
// Gravity on a level sensor, in its frame.
inline const Eigen::Vector3d kLevel(0.0, 0.0, -kStandardGravity);

// An offset of the sensor's wrench (fx fy fz mx my mz) that the tests add.
inline const Wrench kOffset = (Wrench() << 0.5, -0.3, 1.0, 0.05, -0.02, 0.03).finished();

inline const std::string kUrLikeUrdf = MASSID_SOURCE_DIR "/examples/ur_like/ur_like.urdf";

// The values of the base parameters for the URDF's own inertials, then the
// offset where the basis has one.
inline Eigen::VectorXd true_values(const Model& model, const BaseParameters& base,
                                   const Wrench& offset) {
  Eigen::VectorXd t(base.num_unknowns());
  t.head(base.num_mass()) = base.K * nominal_standard_parameters(model);
  if (base.offset) t.tail(6) = offset;
  return t;
}

struct Example {
  std::string name;     // folder under examples/
  std::string urdf;     // path
  std::string plan;     // path
  int base_parameters;  // expected count without offsets
};

inline std::vector<Example> examples() {
  const std::string dir = MASSID_SOURCE_DIR "/examples/";
  return {
      {"puma260", dir + "puma260/puma260.urdf", dir + "puma260/plan.csv", 10},
      {"ur_like", dir + "ur_like/ur_like.urdf", dir + "ur_like/plan.csv", 16},
      {"branching", dir + "branching/branching.urdf", dir + "branching/plan.csv", 17},
      {"wrist_tool", dir + "wrist_tool/wrist_tool.urdf", dir + "wrist_tool/plan.csv", 4},
  };
}

// A plan of the example that determines the offsets too (three or more
// gravity directions).
inline std::string offset_plan(const Example& ex) {
  if (ex.name == "puma260") return MASSID_SOURCE_DIR "/examples/puma260/holdout.csv";
  return ex.plan;
}

inline Samples load_plan(const Model& model, const std::string& path) {
  return read_samples(model, read_csv(path), WrenchColumns::Optional);
}

// The paper's W (eq. 30, first column in the sign of eq. 23's T3; the printed
// s2 s3 + c2 c3 is a slip) for the PUMA 260's joint angles.
inline Eigen::Matrix<double, 3, 9> paper_W(double q1, double q2, double q3) {
  const double s1 = std::sin(q1), c1 = std::cos(q1), s2 = std::sin(q2), c2 = std::cos(q2),
               s3 = std::sin(q3), c3 = std::cos(q3);
  Eigen::Matrix<double, 3, 9> W;
  W << s1 * (s2 * s3 - c2 * c3), s1 * (c2 * s3 + s2 * c3), -s1 * c2, s1 * s2, c1, -s1, 1, 0, 0,
      c1 * (s2 * s3 - c2 * c3), c1 * (c2 * s3 + s2 * c3), -c1 * c2, c1 * s2, -s1, -c1, 0, 1, 0,
      -(s2 * c3 + c2 * s3), s2 * s3 - c2 * c3, -s2, -c2, 0, 0, 0, 0, 1;
  return W;
}

// The paper's eq. 36 figure for PUMA 260 samples: cond(F* W*) of eq. 33 with
// F of eq. 18 from the unit gravity direction, built from the paper alone.
inline double paper_condition_number(const Samples& s) {
  Eigen::MatrixXd FW(3 * s.size(), 9);
  for (int i = 0; i < s.size(); ++i) {
    const Eigen::Vector3d f = s.gravity.row(i).normalized();
    Eigen::Matrix3d F;
    F << 0, f.z(), -f.y(), -f.z(), 0, f.x(), f.y(), -f.x(), 0;
    FW.middleRows(3 * i, 3) = F * paper_W(s.q(i, 0), s.q(i, 1), s.q(i, 2));
  }
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(FW);
  return svd.singularValues()(0) / svd.singularValues()(8);
}

// Largest |estimate - truth| / std over the base parameters (offsets
// excluded), the truth K pi of the URDF's parameters in the base's layout.
inline double worst_normalised_error(const Model& model, const BaseParameters& base,
                                     const IdentifySummary& fit) {
  const Eigen::VectorXd truth = base.K * base.layout.nominal(model);
  double worst = 0.0;
  for (int i = 0; i < base.num_mass(); ++i)
    worst = std::max(worst, std::abs(fit.value[i] - truth[i]) / fit.stddev[i]);
  return worst;
}

}  // namespace massid::test
