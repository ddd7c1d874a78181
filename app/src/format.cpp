#include <hemivem/app/format.hpp>

#include <hemivem/error.hpp>
#include <hemivem/support/atomic_file.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>
#include <string>
#include <system_error>

namespace hemivem::app {

void write_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
  if (path.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
    if (ec) throw InputError("cannot create folder: " + ec.message(), path.parent_path().string());
  }
  write_file_atomically(path, write);
}

std::string sci(double v, int precision) {
  if (std::isnan(v)) return "-";
  std::ostringstream s;
  s << std::setprecision(precision) << std::scientific << v;
  return s.str();
}

std::string fixed(double v, int precision) {
  std::ostringstream s;
  s << std::setprecision(precision) << std::fixed << v;
  return s.str();
}

nlohmann::json number(double v) {
  if (!std::isfinite(v)) return nullptr;
  return v;
}

nlohmann::json certificate_json(const Certificate& c) {
  return {{"primal", number(c.primal)},
          {"dual", number(c.dual)},
          {"length_scale", number(c.length_scale)},
          {"force_scale", number(c.force_scale)},
          {"tolerance", number(c.tolerance)}};
}

std::string certificate_text(const Certificate& c) {
  return "primal " + sci(c.primal, 3) + ", dual " + sci(c.dual, 3) + " (tolerance " + sci(c.tolerance, 1) + ")";
}

nlohmann::json critical_points_json(const MinimizerResult& r, double shift) {
  nlohmann::json points = nlohmann::json::array();
  for (const auto& p : r.critical_points)
    points.push_back({{"reduced_objective", number(p.objective)},
                      {"potential_energy", number(p.objective + shift)},
                      {"certificate", certificate_json(p.certificate)},
                      {"starts", p.starts},
                      {"engines", p.engines}});
  return points;
}

std::string critical_points_text(const MinimizerResult& r, double shift) {
  std::ostringstream s;
  s << std::setprecision(10);
  s << "  search        " << r.message << "\n";
  const std::size_t shown = std::min<std::size_t>(r.critical_points.size(), 8);
  for (std::size_t k = 0; k < shown; ++k) {
    const auto& p = r.critical_points[k];
    s << "  critical pt " << k + 1 << "  energy " << p.objective + shift << ", reached " << p.starts << " time(s) by ";
    for (std::size_t e = 0; e < p.engines.size(); ++e) s << (e ? ", " : "") << p.engines[e];
    s << (k == 0 ? " (lowest: the solution reported)" : "") << "\n";
  }
  if (shown < r.critical_points.size())
    s << "  ...           " << r.critical_points.size() - shown << " more in result.json\n";
  return s.str();
}

std::string progress_line(const GlobalSearchProgress& p) {
  std::ostringstream s;
  s << std::setprecision(10) << "hemivem: global search run " << p.run << "/" << p.max_runs << ": " << p.engine
    << " from " << p.start << ": F = " << p.objective << (p.certified ? ", certified" : ", not certified") << "; "
    << p.critical_points << " critical point(s)";
  if (p.critical_points > 0) s << ", lowest F = " << p.lowest;
  s << " (" << fixed(p.seconds, 2) << " s)";
  return s.str();
}

}  // namespace hemivem::app
