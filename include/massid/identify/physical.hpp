// Physically consistent standard parameters from identified base parameters.
//
// Identification gives base parameters pi_b = K pi (base_parameters.hpp) with
// their covariance. Unconstrained, they may be those of no real body (a
// negative mass, an inertia breaking the triangle inequalities), and they say
// nothing about the directions K does not see. fit_physical finds, for every
// measured link, ten standard parameters (m, h = m c, inertia about the link
// origin: parameters.hpp) that
//   - are physically consistent: m > 0 and the pseudo-inertia
//       J = [[ Sigma, h ], [ h^T, m ]],  Sigma = 1/2 tr(I) 1 - I  (I about the origin)
//     is positive definite (Wensing, Kim & Slotine 2017: J >= 0 is equivalent to
//     a density on the link, and implies the triangle inequalities of the
//     principal moments about the centre of mass);
//   - reproduce the identified base parameters within their std;
//   - keep the URDF's inertials where the data cannot see (a weak prior).
//
// Parameterisation (Rucker & Wensing 2022, log-Cholesky): per link ten free
// numbers theta = (alpha, d1, d2, d3, s12, s23, s13, t1, t2, t3),
//       U = e^alpha [[ e^d1  s12   s13   t1 ]
//                    [ 0     e^d2  s23   t2 ]
//                    [ 0     0     e^d3  t3 ]
//                    [ 0     0     0     1  ]],    J = U U^T,
// so every theta is a consistent body (m = e^{2 alpha} > 0, J > 0) and every
// body with J > 0 has exactly one theta. The cost, minimised by Ceres' Levenberg-
// Marquardt over theta (the samples never enter: only pi_b and its covariance),
//   sum |L^-1 (K pi(theta) - pi_b)|^2                     data: Sigma_b = L L^T
// + prior                                                 (below)
// where Sigma_b is the marginal covariance of the mass base parameters (the
// offsets left out), q_l = (m, h, I_C) the link's mass, first moment and
// rotational inertia about its centre of mass (the URDF's own convention: a
// link whose mass or centre of mass the data moves keeps the URDF's shape),
// s_k = M, M L, M L^2 (total mass, reach: parameter_scales) and w small, so that
// the prior only decides what the data does not.
//
// The prior in motion is each link's log-det (Bregman) divergence from the
// URDF's body (Lee, Wensing & Park 2020), weighted by divergence_weight^2:
//   d(J || J0) = -log det(J0^-1 J) + tr(J0^-1 J) - 4,
// relative to each link's own size and infinite for a degenerate body. A
// weight of 1 counts the URDF as one observation of each link: a product of
// inertia the data sees only to within the link's own inertia stays near the
// URDF's instead of turning the link into a needle (which the weak
// quadratic prior, on the global scales, let happen). At rest the prior is
// the quadratic one on (m, h, I_C) with prior_weight, so that each link keeps
// the URDF's inertia about its centre of mass.
//
// Static identification (first-moment layout, 4 per link): the same solve;
// the data sees only m and h, and the prior keeps each link's inertia about
// its centre of mass at the URDF's, so the ten parameters stay consistent.
//
// The search is bounded (PhysicalOptions::min_mass_fraction,
// min_extent_fraction): masses cannot collapse to zero nor extents to a point.
//
// A link without <inertial>, or with zero mass, has the prior of a tiny body
// (a log parameterisation cannot reach m = 0): PhysicalOptions::tiny_mass_fraction
// of the total mass, at the link origin, a solid sphere of radius
// tiny_radius_fraction of the reach. A URDF inertia that is itself
// inconsistent is kept as the prior's target, but the solve starts from the
// nearest consistent body.
//
// Options -> fit_physical() -> PhysicalSummary, in the style of Ceres' Solve().
#pragma once

#include <Eigen/Core>
#include <string>
#include <vector>

#include "massid/core/base_parameters.hpp"
#include "massid/core/model.hpp"
#include "massid/core/standard_parameters.hpp"

namespace massid {

struct IdentifySummary;

struct PhysicalOptions {
  // w above: the prior's weight against data whitened to unit std (at rest).
  double prior_weight = 1e-3;
  // In motion the prior is the log-det divergence of each link's pseudo-inertia
  // from the prior body's, with this weight (its square multiplies d).
  double divergence_weight = 1.0;
  // The prior body of a link without a mass (see above).
  double tiny_mass_fraction = 1e-4;
  double tiny_radius_fraction = 0.02;
  // Bounds of the search: every mass within [min_mass_fraction,
  // 1 / min_mass_fraction] times the total mass, every spread of a body's
  // mass e^d_i (the diagonal of U / e^alpha: lengths with
  // sum_i e^{2 d_i} <= tr(Sigma_C) / m) within [min_extent_fraction,
  // 1 / min_extent_fraction] times the reach, and the centre of mass t and
  // shears s within 1 / min_extent_fraction reaches. They keep the solve finite
  // where the data pull a mass towards zero or below (an estimate no body
  // can match), and are far from any real body.
  double min_mass_fraction = 1e-9;
  double min_extent_fraction = 1e-6;
  int max_iterations = 500;
  double function_tolerance = 1e-12;
  double gradient_tolerance = 1e-14;
  double parameter_tolerance = 1e-12;
};

struct PhysicalSummary {
  // [10 num_links] full layout (parameters.hpp): m, mx, my, mz, ixx .. izz per
  // link, inertia about the link origin. What a URDF writer consumes.
  Eigen::VectorXd standard;
  std::vector<PhysicalLink> links;  // in Model::links order
  // Per mass base parameter: (K pi_phys - pi_b) / std; the worst by magnitude.
  Eigen::VectorXd mismatch;
  int worst = -1;  // index in base.params, -1 when there are none
  double worst_mismatch = 0.0;
  bool static_layout = false;             // identified at rest: inertias from the URDF
  double initial_cost = 0.0, cost = 0.0;  // Ceres' 1/2 |r|^2 at the start and the end
  int iterations = 0;
  double solve_seconds = 0.0;
  // Ceres' convergence, or its iteration limit with the cost falling by less
  // than 1e-8 (squared std: nothing a fit can tell) over the last tenth of
  // the iterations (at least 10).
  bool converged = false;
  std::string message;  // Ceres' termination message

  // Every link (inline: writing a params file asks, and must not bring in
  // the fit's solver).
  bool consistent() const {
    for (const PhysicalLink& l : links)
      if (!l.consistent) return false;
    return true;
  }
};

// Throws InputError when the summary does not belong to `base`.
PhysicalSummary fit_physical(const Model& model, const BaseParameters& base,
                             const IdentifySummary& identified,
                             const PhysicalOptions& options = {});

}  // namespace massid
