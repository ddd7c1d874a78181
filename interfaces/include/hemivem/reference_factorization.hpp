// One analysis and one numeric factorization of a matrix by an engine's library alone, timed:
// the yardstick of `hemivem bench --limit` (measure_reference_factorization of
// hemivem/linear_backends.hpp, which asks the cholmod engine).
#pragma once

#include <string>

namespace hemivem {

struct ReferenceFactorization {
  bool ok = false;               ///< false: the analysis or factorization failed (message says why)
  std::string message;
  std::string ordering;          ///< "amd" or "metis"
  double analysis_seconds = 0.0;
  double factorization_seconds = 0.0;
  double factor_bytes = 0.0;     ///< the numeric values and row indices of the factor
};

}  // namespace hemivem
