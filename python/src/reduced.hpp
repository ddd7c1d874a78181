// The Python module's contact laws and reduced problems, shared by reduced.cpp and solve.cpp.
#pragma once

#include "bindings.hpp"

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact_law.hpp>
#include <hemivem/global_search.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem::python {

struct PyLaw {
  std::shared_ptr<const ContactLaw> law;
};

/// A reduced problem and what it came from: a condensation (built problem, boundary and the
/// factorization kept for back-substitution) or its own arrays (files, arrays, a result).
struct ReducedHolder {
  std::weak_ptr<ReducedHolder> self;          ///< for views of the built mesh
  std::unique_ptr<BuiltProblem> built;         ///< condense() only
  ContactBoundary boundary;                    ///< condense() only
  std::unique_ptr<Condensation> condensation;  ///< condense() only: owns the factorization
  ReducedProblem own;                          ///< otherwise
  std::string linear;
  std::map<std::string, double> timings;
  const ReducedProblem& problem() const;
};

/// The per-iteration history as a dict of arrays.
py::dict history_dict(const std::vector<IterationRecord>& history);

/// A critical point of a global search, sharing the memory of the result that holds it.
struct PyCriticalPoint {
  std::shared_ptr<const CriticalPoint> point;  ///< aliases the owning result
  std::optional<double> shift;                 ///< potential energy - F (a solve only)
};

/// The critical points of `result`, lowest F first, each keeping `owner` (which holds
/// `result`) alive; `shift` as in result.json (critical_points_json), none for a reduced
/// problem alone.
py::list critical_points_list(const std::shared_ptr<const void>& owner, const MinimizerResult& result,
                              std::optional<double> shift);

/// The names of the searches ("local", "global"); true for "global", InputError naming
/// `where` for any other name.
bool is_global_search(const std::string& search, const std::string& where);

/// GlobalSearchOptions::progress for a call running without the GIL: polls Ctrl-C and calls
/// `progress` (a Python callable or None) with the GIL held; throws Interrupted (the error
/// kept by `watch`) when either raised.
std::function<void(const GlobalSearchProgress&)> search_progress(SignalWatch& watch, const py::object& progress);

}  // namespace hemivem::python
