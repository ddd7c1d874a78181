#include <hemivem/error.hpp>
#include <hemivem/sparse_factorization.hpp>

#include <cctype>
#include <utility>

namespace hemivem {

std::string to_string(FactorizationStatus status) {
  switch (status) {
    case FactorizationStatus::success: return "success";
    case FactorizationStatus::not_positive_definite: return "not_positive_definite";
    case FactorizationStatus::numerical_failure: return "numerical_failure";
    case FactorizationStatus::out_of_memory: return "out_of_memory";
  }
  throw InternalError("a FactorizationStatus out of range: " + std::to_string(static_cast<int>(status)));
}

FactorizationStatus factorization_status_from_string(std::string_view name) {
  std::string s(name);
  for (auto& ch : s) ch = ch == '-' || ch == ' ' ? '_' : static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
  for (FactorizationStatus status :
       {FactorizationStatus::success, FactorizationStatus::not_positive_definite, FactorizationStatus::numerical_failure,
        FactorizationStatus::out_of_memory})
    if (s == to_string(status)) return status;
  throw InputError("unknown factorization status '" + std::string(name) +
                   "'; expected success, not_positive_definite, numerical_failure or out_of_memory");
}

bool FactorizationOptions::is_valid(std::string* error) const {
  auto fail = [error](std::string message) {
    if (error != nullptr) *error = std::move(message);
    return false;
  };
  if (!is_known_engine(known_linear_engines(), engine) && normalized_engine_name(engine) != "auto")
    return fail("engine: unknown linear engine '" + engine + "' (known: " + join_engine_names(known_linear_engines()) +
                ")");
  if (verbosity < 0) return fail("verbosity: must be >= 0, got " + std::to_string(verbosity));
  if (threads < 0) return fail("threads: must be >= 0 (0: engine default), got " + std::to_string(threads));
  return true;
}

}  // namespace hemivem
