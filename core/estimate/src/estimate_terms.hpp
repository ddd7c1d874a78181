// The parts of the residual estimator per element and their sum into an ErrorEstimate, shared
// by the plane and the three-dimensional estimate.
#pragma once

#include <array>
#include <chrono>
#include <vector>

#include <hemivem/estimate/error_estimate.hpp>
#include <hemivem/estimate/error_estimate3d.hpp>

namespace hemivem::detail {

enum EstimatePart { volume, jump, traction, contact, friction, stabilization, part_count };

/// The residuals of one element, before weighting.
struct ElementTerms {
  std::array<double, part_count> raw{};  ///< volume .. friction: squared residuals; stabilization: S_E(u - Pi u, u - Pi u)
  double weight = 0.0;                   ///< C / (2 mu_E)
  double consistency_energy = 0.0;       ///< |E| sigma : eps of Pi u_h
};

/// The terms of every element of the problem's mesh, in its order: estimate_error before
/// sum_estimate, with its InputErrors.
std::vector<ElementTerms> estimate_terms(const ContactProblem& problem, const ContactSolution& solution);
std::vector<ElementTerms> estimate_terms(const ContactProblem3D& problem, const ContactSolution3D& solution);

/// eta_E^2 = weight * (volume + jump + traction + contact + friction) + 1/2 stabilization per
/// element, ||u_h||_E^2 = 1/2 sum (consistency_energy + stabilization), the parts and the
/// indicators; `seconds` since `start`.
ErrorEstimate sum_estimate(const std::vector<ElementTerms>& terms, std::chrono::steady_clock::time_point start);

}  // namespace hemivem::detail
