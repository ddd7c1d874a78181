// The Python module's contact laws and reduced problems, shared by reduced.cpp and solve.cpp.
#pragma once

#include "bindings.hpp"

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <hemivem/contact.hpp>
#include <hemivem/contact_law.hpp>
#include <hemivem/nonsmooth_minimizer.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/scene.hpp>

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

}  // namespace hemivem::python
