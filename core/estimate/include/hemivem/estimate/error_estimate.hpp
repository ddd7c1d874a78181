// An a posteriori estimate of the discretization error of a solve (docs/error-estimate.md): a
// residual estimator for the lowest-order virtual element method (Cangiani, Georgoulis, Pryer,
// Sutton 2017; Beirão da Veiga, Manzini 2015) with the contact tractions of the solution on
// Gamma_3, per element, in the energy norm ||v||_E^2 = 1/2 a(v, v).
#pragma once

#include <map>
#include <string>
#include <vector>

#include <hemivem/contact/problem.hpp>
#include <hemivem/contact/solver.hpp>

namespace hemivem {

/// The constant C that multiplies the residual part of the estimate (the volume, jump,
/// traction, contact and friction residuals, weighted by the compliance 1/(2 mu_E)); chosen
/// once, by calibration on Example 4.1 (docs/error-estimate.md), and never per problem.
inline constexpr double error_estimate_constant = 0.11;

/// An a posteriori estimate of the discretization error in the energy norm ||v||_E^2 = 1/2 a(v, v).
///
/// eta_E^2 = C / (2 mu_E) * (volume_E + jump_E + traction_E + contact_E + friction_E)
///         + 1/2 (u_E - Pi u_E)^T S_E (u_E - Pi u_E)
/// with C = error_estimate_constant and the residuals of docs/error-estimate.md.
struct ErrorEstimate {
  double energy = 0.0;    ///< eta = sqrt(sum_E eta_E^2): the estimate of ||u - u_h||_E
  double norm = 0.0;      ///< ||u_h||_E
  double relative = 0.0;  ///< energy / norm (0 when norm is 0 and energy is 0; +inf when only norm is 0)
  /// The contribution of each part, sqrt of the sum over elements of its squared share, by name:
  /// "volume", "jump", "traction", "contact", "friction", "stabilization" (every name present, 0 where absent).
  /// The squares of the parts sum to energy^2.
  std::map<std::string, double> parts;
  std::vector<double> indicators;  ///< eta_E per element (eta^2 = sum eta_E^2)
  double seconds = 0.0;            ///< wall time of the estimate
  double constant = error_estimate_constant;  ///< the C used
};

/// The names of ErrorEstimate::parts, in the order of the estimator's terms.
const std::vector<std::string>& error_estimate_part_names();

/// The estimate for a solution of `problem` (solution.u, and solution.contact for the contact and friction residuals).
///
/// Cost linear in the number of elements and edges; nothing is assembled or solved. Without
/// contact nodes (no contact boundary, or a solution of the elasticity problem alone) the Gamma_3
/// edges are compared with a zero traction. InputError when solution.u does not have 2 entries
/// per vertex of the problem's mesh, when the problem has no mesh, when a contact node names
/// a vertex outside the mesh, or when an edge id of a Dirichlet, traction or contact part is
/// out of range.
ErrorEstimate estimate_error(const ContactProblem& problem, const ContactSolution& solution);

}  // namespace hemivem
