// Exciting trajectories for identification in motion: a finite Fourier series
// per joint (Swevers, Ganseman, Tukel, De Schutter & Van Brussel 1997),
//
//   q_j(t)   = q0_j + sum_k ( a_jk sin(k w t) - b_jk cos(k w t) ) / (k w)
//   qd_j(t)  = sum_k a_jk cos(k w t) + b_jk sin(k w t)
//   qdd_j(t) = sum_k k w ( b_jk cos(k w t) - a_jk sin(k w t) )
//
// with w = 2 pi / period. Periodic, so the data of whole periods average the
// noise evenly; at rest at t = 0 (and every period) by the constraints
// sum_k a_jk = 0 and sum_k k b_jk = 0; scaled into the joints' position
// limits (a margin inside), velocity limits and acceleration limits.
#pragma once

#include <Eigen/Core>
#include <cstdint>
#include <vector>

#include "massid/base_parameters.hpp"
#include "massid/model.hpp"
#include "massid/samples.hpp"

namespace massid {

struct FourierTrajectory {
  double period = 10.0;  // s
  Eigen::VectorXd q0;    // [num_joints] centre position
  Eigen::MatrixXd a, b;  // [num_joints x harmonics] coefficients, rad/s (m/s)

  int num_joints() const { return static_cast<int>(q0.size()); }
  int harmonics() const { return static_cast<int>(a.cols()); }
  // Position, velocity and acceleration at time t, each [num_joints].
  void evaluate(double t, Eigen::Ref<Eigen::VectorXd> q, Eigen::Ref<Eigen::VectorXd> qd,
                Eigen::Ref<Eigen::VectorXd> qdd) const;
};

struct ExcitationLimits {
  double position_margin = 0.1;   // fraction of each limited joint's range kept free at each end
  double default_velocity = 1.0;  // rad/s or m/s when the URDF gives no velocity limit
  double acceleration = 4.0;      // rad/s^2 or m/s^2, every joint ...
  std::vector<double> joint_acceleration;  // ... or per joint [num_joints] where > 0
  double unlimited_amplitude = 1.5;        // rad (m) about q0 for joints without position limits
};

// Random coefficients (Gaussian, falling as 1/k), made to start at rest,
// scaled to the limits: the baseline exciting trajectory.
FourierTrajectory random_fourier_trajectory(const Model& model, int harmonics, double period,
                                            std::uint64_t seed,
                                            const ExcitationLimits& limits = {});

// The trajectory sampled at `rate` Hz over [0, duration]: t, q, qd, qdd, and
// the given gravity (sensor frame) in every row; lines numbered from 1.
Samples sample_trajectory(const FourierTrajectory& trajectory, double duration, double rate,
                          const Eigen::Vector3d& gravity);

// A baseline design: the best of `candidates` random trajectories by the
// condition number of the column-scaled, noise-weighted dynamic base
// regressor (the figure identify reports in motion), evaluated on the
// trajectory sampled at min(rate, 100 Hz). (An optimiser over the
// coefficients would do better; this one is deterministic per seed.)
struct ExcitationOptions {
  int harmonics = 5;
  double period = 10.0;    // s
  double duration = 30.0;  // s
  double rate = 1000.0;    // Hz of the written trajectory
  int candidates = 8;
  std::uint64_t seed = 1;
  Eigen::Vector3d gravity{0.0, 0.0, -kStandardGravity};  // sensor frame
  double noise_force = 0.1;                              // N, for the predicted std
  double noise_moment = 0.01;                            // N m
  ExcitationLimits limits;
};

struct ExcitationSummary {
  FourierTrajectory trajectory;
  double condition_number = 0.0;  // as identify reports it in motion
  Eigen::VectorXd predicted_std;  // [num_unknowns] at the noise and rate of the options
  bool identifiable = false;
  std::string identifiability_message;
};

ExcitationSummary design_excitation(const Model& model, const BaseParameters& base,
                                    const ExcitationOptions& options);

// Writes a trajectory CSV: t, the joint columns, JOINT_vel, JOINT_acc, gx,gy,gz.
void write_trajectory(const std::string& path, const Model& model, const Samples& trajectory);

}  // namespace massid
