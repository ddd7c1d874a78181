// A solve in words, after Ceres' Solver::Summary: a one-line brief report and a full report
// of every stage (the lines `hemivem solve` prints between its title and the files it wrote).
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include <hemivem/app/adapt.hpp>
#include <hemivem/app/outputs.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::app {

/// One line: the status, the certificate, the iterations, the potential energy and the total
/// time, e.g. "converged (certificate: primal 0.000e+00, dual 3.4e-15 (tolerance 1.0e-10)),
/// 4 iterations, energy -0.216339, 0.0557 s".
template <int dim>
std::string brief_report(const BasicSceneSolve<dim>& solved);

/// Every line of a solve: mesh, engines, stages, status and certificate, the global search's
/// critical points, uniqueness, the contact zone, forces, friction, the largest von Mises
/// stress (info.stress), the error estimate, energy and the time of
/// each stage, one "  name          value" line each, ending in a newline. `info` is the
/// run_info() of the solve. A plane's or a solid's solve (the mesh's cells and faces, the area
/// in compression, forces of three components).
template <int dim>
std::string full_report(const BasicSceneSolve<dim>& solved, const RunInfo& info);

/// full_report's line of an error estimate: eta, eta / ||u_h||_E in per cent and the parts
/// that are not zero, ending in a newline.
std::string error_estimate_line(const ErrorEstimate& estimate);

/// A coarser grid of a grid sequence (an entry of BasicSceneSolve::grid_sequence) in words:
/// "n = 16: 13005 unknowns, 5 Newton / 80 Krylov iterations, 0.97 s", with ", not converged"
/// where it did not.
std::string coarser_grid_text(const nlohmann::json& grid);

/// The lines of an adaptive solve after full_report of its last solve: how many solves, the
/// unknowns and the estimate from first to last, and why it stopped.
template <int dim>
std::string adapt_report(const BasicAdaptiveSolve<dim>& adaptive);

}  // namespace hemivem::app
