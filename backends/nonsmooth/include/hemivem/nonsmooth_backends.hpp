// The factory of the nonsmooth minimizers that were built.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include <hemivem/nonsmooth_minimizer.hpp>

namespace hemivem {

/// Names of the minimizers that were built, in the order ssn, bundle-dca, nlopt-mma,
/// ceres-active-set.
std::vector<std::string> available_minimizers();

/// A minimizer by name (case-insensitive, '_' read as '-'); InputError listing the built
/// ones for a name that is unknown or was not built.
std::unique_ptr<NonsmoothMinimizer> make_minimizer(const std::string& name);

}  // namespace hemivem
