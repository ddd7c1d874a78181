#include <hemivem/app/report.hpp>

#include <hemivem/app/format.hpp>
#include <hemivem/uniqueness.hpp>

#include <algorithm>
#include <array>
#include <iomanip>
#include <map>
#include <cmath>
#include <sstream>

namespace hemivem::app {

namespace {

template <int dim>
std::string cell_counts(const MeshSize& size) {
  if constexpr (dim == 2) return std::to_string(size.cells) + " elements";
  return std::to_string(size.cells) + " cells, " + std::to_string(size.facets) + " faces";
}

template <int dim>
void engines_and_stages(std::ostream& out, const BasicSceneSolve<dim>& solved, const RunInfo& info) {
  const auto& built = *solved.built;
  const auto& sol = solved.solution;
  // the whole mesh's, where the results were made on this process's piece of it
  const MeshSize size = info.of_pieces ? info.of_pieces->size : mesh_size(built.mesh);
  out << "  mesh          " << info.mesh << ": " << size.vertices << " vertices, " << cell_counts<dim>(size)
      << ", h = " << size.h << ", " << info.dofs << " unknowns" << (dim == 3 ? " (three-dimensional)" : "") << "\n"
      << "  engines       linear " << info.linear
      << (info.processes > 1 ? " (" + std::to_string(info.processes) + " processes)" : std::string())
      << (built.has_contact ? ", minimizer " + info.minimizer : std::string(" (no contact: one linear solve)")) << "\n"
      << "  stages        ";
  for (std::size_t i = 0; i < sol.stages.size(); ++i) out << (i ? ", " : "") << sol.stages[i];
  out << "\n";
  // the coarser grids of a grid sequence, coarsest first (BasicSceneSolve::grid_sequence)
  for (std::size_t i = 0; i < solved.grid_sequence.size(); ++i)
    out << (i ? "                " : "  coarser grids ") << coarser_grid_text(solved.grid_sequence[i]) << "\n";
}

template <int dim>
void status(std::ostream& out, const BasicSceneSolve<dim>& solved, const RunInfo& info) {
  const auto& sol = solved.solution;
  out << "  status        " << to_string(sol.status) << " (certificate: " << certificate_text(sol.certificate)
      << "), " << sol.iterations() << " iterations\n";
  if (!sol.converged() && !sol.message.empty()) out << "  why           " << sol.message << "\n";
  for (std::size_t k = 0; k < sol.held_by_contact.size(); ++k)
    out << (k == 0 ? "  supports      free, held by the contact alone: " : "                and ")
        << sol.held_by_contact[k] << "\n";
  if (info.search.value("kind", "local") == "global")
    out << (sol.minimizer ? critical_points_text(*sol.minimizer, sol.energy - sol.minimizer->objective)
                          : "  search        " + sol.message + "\n");
}

template <int dim>
std::string uniqueness_text(const BasicContactSolution<dim>& sol) {
  std::ostringstream out;
  if (std::isnan(sol.uniqueness_margin) && !sol.may_be_nonunique)
    return "not measured (no S on the full-space route); unique: every contact law is convex";
  if (std::isnan(sol.uniqueness_margin)) {
    out << "lambda_min(S - alpha_j W) not measured: " << uniqueness_meaning(sol.uniqueness_margin);
    return out.str();
  }
  out << "lambda_min(S - alpha_j W) = " << sol.uniqueness_margin;
  if (sol.uniqueness_margin == 0.0) out << " (|computed| <= round-off bound " << sol.uniqueness_roundoff << ")";
  else if (sol.uniqueness_margin > 0) out << " > 0";
  else if (sol.uniqueness_margin < 0) out << " < 0";
  out << ": " << uniqueness_meaning(sol.uniqueness_margin);
  return out.str();
}

// The contact nodes by state (and by part, with several parts); in 3D the area in compression.
template <int dim>
void contact_zone(std::ostream& out, const BasicContactSolution<dim>& sol) {
  std::array<int, 6> count{};
  for (const auto& c : sol.contact) ++count[static_cast<std::size_t>(c.state)];
  out << "  uniqueness    " << uniqueness_text(sol) << "\n"
      << "  contact       " << sol.contact.size() << " nodes";
  if (sol.contact_parts.size() > 1) {  // several parts: how many nodes each has
    out << " in " << sol.contact_parts.size() << " parts (";
    for (std::size_t k = 0; k < sol.contact_parts.size(); ++k)
      out << (k == 0 ? "" : ", ") << sol.contact_parts[k] << " "
          << std::count_if(sol.contact.begin(), sol.contact.end(),
                           [k](const auto& c) { return c.part == static_cast<int>(k); });
    out << ")";
  }
  out << ": ";
  const std::size_t tied = static_cast<std::size_t>(count[static_cast<std::size_t>(ContactState::tied)]);
  if (tied > 0 && tied == sol.contact.size()) {
    out << "tied, u_nu = 0 (bilateral)\n";
    return;
  }
  // the states in words, those that occur: "19 at the gap, 40 in contact, 4 separated"
  const std::pair<ContactState, const char*> words[] = {
      {ContactState::at_gap, "at the gap"},         {ContactState::in_contact, "in contact"},
      {ContactState::in_tension, "in tension"},     {ContactState::separated, "separated"},
      {ContactState::at_minus_gap, "at minus the gap"}, {ContactState::tied, "tied (bilateral)"}};
  bool first = true;
  for (const auto& [state, text] : words)
    if (const int n = count[static_cast<std::size_t>(state)]; n > 0) {
      out << (first ? "" : ", ") << n << " " << text;
      first = false;
    }
  if constexpr (dim == 3) {
    double area = 0.0;
    for (const auto& c : sol.contact)
      if (c.force() > 0.0) area += c.weight;
    out << "; area in compression " << area;
  }
  out << "\n";
}

template <class Vector>
std::string vector_text(const Vector& v) {
  std::ostringstream o;
  o << std::setprecision(6) << "(";
  for (Eigen::Index c = 0; c < v.size(); ++c) o << (c ? ", " : "") << v(c);
  o << ")";
  return o.str();
}

// The balance of forces on the body: applied load, reactions by part, contact resultant.
template <int dim>
void balance(std::ostream& out, const BasicContactSolution<dim>& sol) {
  const auto& b = sol.forces;
  out << "  forces        applied " << vector_text(b.applied) << ", reactions";
  if (b.reactions.empty()) out << " none";
  for (std::size_t i = 0; i < b.reactions.size(); ++i)
    out << (i ? ", " : " ") << b.reactions[i].name << " " << vector_text(b.reactions[i].force);
  if (!sol.contact.empty()) out << ", contact " << vector_text(b.contact);
  out << "\n  balance       |applied + reactions" << (sol.contact.empty() ? "" : " + contact") << "| = "
      << std::setprecision(2) << b.residual() << std::setprecision(6)
      << " x the largest force\n";
}

// The contact nodes' forces: the sum of the normal forces zeta_i + lambda_i (not a resultant:
// the normals differ from node to node) and the friction states.
template <int dim>
void contact_forces(std::ostream& out, const BasicContactSolution<dim>& sol, const RunInfo& info) {
  double law = 0.0, reaction = 0.0, friction = 0.0;
  std::map<std::string, int> states;
  for (const auto& c : sol.contact) law += c.law_force, reaction += c.reaction, friction += c.friction_force;
  for (const auto& c : sol.contact)
    if (c.friction_state != FrictionState::none) ++states[to_string(c.friction_state)];
  out << "  normal forces " << law + reaction << " summed over the contact nodes (a sum, not a resultant): law "
      << law << ", constraint " << reaction << "\n";
  if (states.empty()) return;
  out << "  friction      " << (info.friction_summary.empty() ? std::string("none") : info.friction_summary) << ": ";
  bool first = true;
  for (const auto& [state, count] : states) out << (first ? "" : ", ") << count << " " << state, first = false;
  out << "; sum of the friction forces " << friction << "\n";
}

// The cell of the largest von Mises stress and its centroid.
void stress_line(std::ostream& out, const StressPeak& peak) {
  out << "  stress        max von Mises " << peak.von_mises << " in cell " << peak.cell << ", centroid (";
  for (std::size_t c = 0; c < peak.centroid.size(); ++c) out << (c ? ", " : "") << peak.centroid[c];
  out << ")\n";
}

template <int dim>
void energy_and_time(std::ostream& out, const BasicSceneSolve<dim>& solved) {
  const auto& sol = solved.solution;
  out << "  energy        potential " << sol.energy << "\n  time [s]      mesh " << solved.mesh_seconds;
  for (const char* k : {"grid_sequence", "assembly", "linear_solve", "condensation", "condition", "minimize", "back_substitution", "posing",
                        "full_space", "path", "frames",
                      "estimate"})
    if (sol.timings.count(k)) out << ", " << k << " " << sol.timings.at(k);
  out << ", total " << solved.total_seconds() << "\n";
}

}  // namespace

std::string coarser_grid_text(const nlohmann::json& g) {
  std::ostringstream out;
  out << "n = " << g.at("n").get<std::string>() << ": " << g.at("unknowns").get<int>() << " unknowns, "
      << g.at("newton_iterations").get<int>() << " Newton / " << g.at("krylov_iterations").get<int>()
      << " Krylov iterations, " << g.at("seconds").get<double>() << " s"
      << (g.at("converged").get<bool>() ? "" : ", not converged");
  return out.str();
}

std::string error_estimate_line(const ErrorEstimate& e) {
  std::ostringstream out;
  out << std::setprecision(6) << "  error         estimate " << e.energy << " = " << std::setprecision(3)
      << 100.0 * e.relative << " % of ||u_h||_E (energy norm; parts:" << std::setprecision(6);
  bool first = true;
  for (const auto& [name, value] : e.parts)
    if (value > 0.0) out << (first ? " " : ", ") << name << " " << value, first = false;
  if (first) out << " none";
  out << ")\n";
  return out.str();
}

template <int dim>
std::string brief_report(const BasicSceneSolve<dim>& solved) {
  const auto& sol = solved.solution;
  std::ostringstream out;
  out << std::setprecision(6) << to_string(sol.status) << " (certificate: " << certificate_text(sol.certificate)
      << "), " << sol.iterations() << " iterations, energy " << sol.energy << ", " << std::setprecision(3) << solved.total_seconds()
      << " s";
  return out.str();
}

template <int dim>
std::string full_report(const BasicSceneSolve<dim>& solved, const RunInfo& info) {
  std::ostringstream out;
  out << std::setprecision(6);
  engines_and_stages(out, solved, info);
  status(out, solved, info);
  if (!solved.solution.contact.empty()) {
    contact_zone(out, solved.solution);
    contact_forces(out, solved.solution, info);
  }
  if (solved.holds_results) balance(out, solved.solution);
  if (info.stress) stress_line(out, *info.stress);
  if (solved.estimate) out << error_estimate_line(*solved.estimate);
  energy_and_time(out, solved);
  return out.str();
}

template std::string brief_report(const BasicSceneSolve<2>&);
template std::string brief_report(const BasicSceneSolve<3>&);
template std::string full_report(const BasicSceneSolve<2>&, const RunInfo&);
template std::string full_report(const BasicSceneSolve<3>&, const RunInfo&);

template <int dim>
std::string adapt_report(const BasicAdaptiveSolve<dim>& adaptive) {
  std::ostringstream out;
  const AdaptStep& first = adaptive.steps.front();
  const AdaptStep& last = adaptive.steps.back();
  out << std::setprecision(3) << "  adapt         " << adaptive.steps.size() << " solves in " << adaptive.seconds
      << " s, " << first.unknowns << " -> " << last.unknowns << " unknowns, estimate " << 100.0 * first.estimate
      << " % -> " << 100.0 * last.estimate << " %\n"
      << "  stopped       " << to_string(adaptive.stopped) << ": " << adaptive.reason << "\n";
  return out.str();
}

template std::string adapt_report(const BasicAdaptiveSolve<2>&);
template std::string adapt_report(const BasicAdaptiveSolve<3>&);

}  // namespace hemivem::app
