// The factory of the nonsmooth minimizers that were built.
#pragma once

#include <map>
#include <memory>
#include <string>
#include <vector>

#include <hemivem/nonsmooth_minimizer.hpp>

namespace hemivem {

/// Names of the minimizers that were built, in the order ssn, bundle-dca, nlopt-mma,
/// ceres-active-set.
std::vector<std::string> available_minimizers();

/// A minimizer by name (case-insensitive, '_' read as '-'); InputError listing the built
/// ones for a name that is unknown or was not built. `parameters` set the engine's typed
/// options by name (options_from_parameters: an unknown name, a value of the wrong kind or
/// out of range is an InputError naming the engine and the field).
std::unique_ptr<NonsmoothMinimizer> make_minimizer(const std::string& name,
                                                   const std::map<std::string, double>& parameters = {});

}  // namespace hemivem
