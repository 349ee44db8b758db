// Measurements that the URDF's own inertials would produce: w = Y pi_URDF
// + offset + Gaussian noise (regressor.hpp: at rest Y(q, g) over the first
// moments; with `dynamic`, Y(q, qd, qdd, g, sensor motion) over the ten
// parameters per link, the inertias about the link origins). The reference
// for tests and for planning.
#pragma once

#include <Eigen/Core>
#include <cstdint>

#include "massid/core/model.hpp"
#include "massid/core/predictor.hpp"
#include "massid/core/samples.hpp"

namespace massid {

struct SimulateOptions {
  double noise_force = 0.0;   // N, standard deviation per axis
  double noise_moment = 0.0;  // N m
  Wrench offset = Wrench::Zero();
  std::uint64_t seed = 1;
  int repeat = 1;        // samples per plan row (a logger recording while the pose is held)
  bool dynamic = false;  // the wrench in motion: needs the plan's velocities and accelerations
};

// [N repeat x 6] wrenches at the plan's joint positions and gravity vectors:
// row i * repeat + r is the r-th sample of plan row i.
Eigen::MatrixXd simulate_wrenches(const Model& model, const Samples& plan,
                                  const SimulateOptions& options = {});

}  // namespace massid
