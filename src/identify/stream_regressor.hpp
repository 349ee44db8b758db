// Private: the moment rows of the base regressor for streaming identification
// (streaming.hpp), for a batch of samples at once, computed directly rather
// than as the full standard regressor reduced to the base.
//
// The mass unknowns other than M (the only nonzero entries of the base
// regressor besides M's force rows g, see base_regressor.cpp) each stand for
// one standard column: Y'(m_l) = [0; p_l x g], Y'(h_l)_k = [0; (R_l e_k) x g].
// Forward kinematics in the sensor frame, vectorised across the samples of the
// batch (every quantity is an array over the samples, so each loop runs over
// the batch in SIMD lanes): rotations about coordinate axes turn two columns,
// sines and cosines come two lanes at a time (sincos.hpp, within 1 ulp of
// libm), links fixed to the sensor are computed once. Every sample gets the
// same operations whatever its position in the batch, so results do not
// depend on how samples are batched. Equal to base_regressor to round-off
// (tests compare the identification results with the dense solve).
#pragma once

#include <Eigen/Core>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"

namespace massid::detail {

class StreamRegressor {
 public:
  // Batches of up to `capacity` samples.
  StreamRegressor(const Model& model, const BaseParameters& base, int capacity);

  int size() const { return static_cast<int>(cols_.size()); }  // K
  // Unknown index of moment mass unknown i < K.
  const std::vector<int>& unknown() const { return unknown_; }

  // m <= capacity samples: joint j of sample r at q[j * ld_in + r], gravity
  // component k at g[k * ld_in + r]. Writes moment row a (mx, my, mz) of
  // unknown i for sample r to out[a][i * ld_out + r].
  void compute(int m, const double* q, const double* g, int ld_in, double* const out[3],
               int ld_out);

  struct Step {
    int parent = 0;
    Eigen::Matrix3d Ro;  // joint origin in the parent frame
    Eigen::Vector3d to;
    bool Ro_identity = false, to_zero = false;
    bool constant = false;  // fixed to the sensor: pose computed once
    JointType type = JointType::Fixed;
    Eigen::Vector3d axis;
    int joint = -1;
    double joint_scale = 1.0, joint_offset = 0.0;  // a mimic joint: scale q + offset
    int axis_kind = 0;                             // 0 general, 1 + i: +-unit axis i
    double axis_sign = 1.0;
  };
  struct Col {
    int link = 0;
    int kind = 0;  // 0: mass (p_l x g); 1..3: first moment (R_l e_{kind-1} x g)
  };

 private:
  std::vector<Step> steps_;  // links 1.. in order (parents first)
  std::vector<Col> cols_;    // [K] the moment mass unknowns in unknown order
  std::vector<int> unknown_;
  int capacity_ = 0;  // rounded up to even (two sincos lanes)
  // Per link 12 arrays of `capacity_` samples: R(r, c) at 3 c + r, p(r) at 9 + r.
  std::vector<double> pose_;
  std::vector<double> angle_, sin_, cos_;  // [capacity_]
};

}  // namespace massid::detail
