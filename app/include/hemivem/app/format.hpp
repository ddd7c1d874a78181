// Numbers, certificates and a global search's findings as the command and result.json show
// them, and files written atomically.
#pragma once

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>

#include <hemivem/certificate.hpp>
#include <hemivem/global_search.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

namespace hemivem::app {

/// Writes a file through `write` into a temporary name in the same folder and renames it
/// into place on success, so a failure never leaves a half-written output behind.
void write_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

/// v in scientific notation with `precision` digits after the point; "-" for NaN.
std::string sci(double v, int precision = 2);
/// v in fixed notation with `precision` digits after the point.
std::string fixed(double v, int precision = 4);
/// v as a JSON number, null when it is not finite (JSON has no NaN or Inf).
nlohmann::json number(double v);
/// A point or vector as a JSON array of its components (number(): non-finite ones null).
template <class Vector>
nlohmann::json vector_json(const Vector& v) {
  nlohmann::json out = nlohmann::json::array();
  for (Eigen::Index c = 0; c < v.size(); ++c) out.push_back(number(v(c)));
  return out;
}

/// The certificate as JSON: {primal, dual, length_scale, force_scale, tolerance}.
nlohmann::json certificate_json(const Certificate& c);
/// "primal 1.2e-16, dual 3.4e-15 (tolerance 1.0e-10)".
std::string certificate_text(const Certificate& c);

/// A global search's critical points as JSON, lowest first: reduced_objective, potential_energy
/// (reduced_objective + `shift`, the constant between the two energies of the problem; 0 for a
/// reduced problem alone), certificate, starts, engines.
nlohmann::json critical_points_json(const MinimizerResult& r, double shift);
/// The same as lines of the command's summary ("  search  ..." and one line per point, at most 8).
std::string critical_points_text(const MinimizerResult& r, double shift);
/// One line of a global search's progress (stderr).
std::string progress_line(const GlobalSearchProgress& p);

}  // namespace hemivem::app
