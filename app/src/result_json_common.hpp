// The keys of result.json that a plane and a three-dimensional solve fill alike: the run
// (schema, version, scene, engines, files, warnings, options), the outcome (status,
// certificate, uniqueness, search, critical points, energy, iterations, evaluations) and the
// stages with their times.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include <hemivem/app/format.hpp>
#include <hemivem/app/outputs.hpp>
#include <hemivem/uniqueness.hpp>

namespace hemivem::app::detail {

/// The solution's time of `stage`, 0 when it has none.
template <class Solution>
double timing(const Solution& s, const std::string& stage) {
  const auto it = s.timings.find(stage);
  return it == s.timings.end() ? 0.0 : it->second;
}

/// The full-space route's counts as result.json's full_space writes them (and each grid of its
/// grid_sequence): newton_iterations, krylov_iterations, preconditioner_setups.
inline nlohmann::json full_space_counts_json(const FullSpaceStatistics& f) {
  return {{"newton_iterations", f.newton_iterations},
          {"krylov_iterations", f.krylov_iterations},
          {"preconditioner_setups", f.preconditioner_setups}};
}

/// result.json's common keys of a solution `s` (ContactSolution or ContactSolution3D).
template <class Solution>
nlohmann::json result_json_common(const Solution& s, const RunInfo& info, int dimension) {
  using nlohmann::json;
  json j;
  j["schema"] = "hemivem-result/26";
  j["version"] = info.version;
  j["dimension"] = dimension;
  j["scene"] = {{"name", info.scene_name}, {"toml", info.scene_toml}};
  j["backends"] = {{"linear", info.linear}, {"minimizer", info.minimizer}};
  j["processes"] = info.processes;
  j["files"] = info.files;
  j["warnings"] = info.warnings;
  j["options"] = info.options;
  j["status"] = to_string(s.status);
  j["converged"] = s.converged();
  j["message"] = s.message;
  j["certificate"] = certificate_json(s.certificate);
  j["uniqueness_margin"] = number(s.uniqueness_margin);
  j["uniqueness_roundoff"] = number(s.uniqueness_roundoff);
  j["uniqueness"] = uniqueness_verdict(s.uniqueness_margin);
  j["may_be_nonunique"] = s.may_be_nonunique;
  j["search"] = info.search;
  j["critical_points"] =
      s.minimizer ? critical_points_json(*s.minimizer, s.energy - s.minimizer->objective) : json::array();
  j["potential_energy"] = number(s.energy);
  j["iterations"] = s.iterations();
  j["evaluations"] = {{"function", s.minimizer ? s.minimizer->function_evaluations : 0},
                      {"subgradient", s.minimizer ? s.minimizer->subgradient_evaluations : 0}};
  if (s.full_space) {
    j["full_space"] = full_space_counts_json(*s.full_space);
    j["full_space"]["grid_sequence"] = info.grid_sequence;
  } else {
    j["full_space"] = nullptr;
  }
  j["stages"] = s.stages;
  json t = json::object();
  for (const auto& [k, v] : s.timings) t[k] = number(v);
  t["mesh"] = number(info.mesh_seconds);
  for (const char* stage : {"assembly", "condensation", "minimize", "back_substitution"}) t[stage] = timing(s, stage);
  t["total"] = number(info.mesh_seconds + timing(s, "total"));
  j["timings"] = t;
  j["error_estimate"] = info.error_estimate ? error_estimate_json(*info.error_estimate) : json(nullptr);
  j["stress"] = info.stress ? json{{"max_von_mises", number(info.stress->von_mises)},
                                   {"cell", info.stress->cell},
                                   {"centroid", info.stress->centroid}}
                            : json(nullptr);
  return j;
}

}  // namespace hemivem::app::detail
