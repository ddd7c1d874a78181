// The a posteriori estimate of the discretization error of a three-dimensional solve
// (docs/error-estimate.md, "Three dimensions"): the residual estimator of the plane problem
// with faces in the place of edges.
#pragma once

#include <hemivem/contact/contact3d.hpp>
#include <hemivem/estimate/error_estimate.hpp>

namespace hemivem {

/// The estimate for a solution of a 3D `problem` (solution.u, and solution.contact for the
/// contact residual), in the energy norm ||v||_E^2 = 1/2 a(v, v):
///
/// eta_E^2 = C / (2 mu_E) * (h_E^2 ||f0||^2_E + 1/2 sum_{interior f of E} h_f ||[sigma n]||^2_f
///           + sum_{f of E on Gamma_2} h_f ||f2 - sigma n||^2_f + sum_{f of E on Gamma_3} h_f ||t_c - sigma n||^2_f)
///         + 1/2 (u_E - Pi u_E)^T S_E (u_E - Pi u_E),
///
/// sigma the stress of Pi u_h (constant on a cell), h_E the cell's diameter and h_f = |f|^(1/2)
/// the face's size (as an edge's length |e| in the plane: the measure of the face to the power
/// 1/(d - 1)),
/// t_c = -(p_i nu_i) at the contact nodes, linear on the fan of triangles (face centroid, z_i,
/// z_{i+1}) with the mean of the face's nodes at the centroid, and C = error_estimate_constant,
/// the plane problem's. The "friction" part is 0 (a 3D contact is frictionless). Cost linear in
/// the cells and faces; nothing is assembled or solved. InputError when solution.u does not have
/// 3 entries per vertex, the problem has no mesh, a contact node names a vertex outside the
/// mesh, or a face id of a Dirichlet, traction or contact part is out of range.
ErrorEstimate estimate_error(const ContactProblem3D& problem, const ContactSolution3D& solution);

}  // namespace hemivem
