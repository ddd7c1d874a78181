#include <hemivem/engine_names.hpp>
#include <hemivem/error.hpp>
#include <hemivem/nonsmooth_backends.hpp>

// The minimizers built (hemivem_add_engine, cmake/HemivemEngines.cmake): their headers and
// HEMIVEM_ENGINES.
#include "nonsmooth_registry.hpp"

namespace hemivem {

std::vector<std::string> available_minimizers() {
  std::vector<std::string> names;
#define HEMIVEM_NAME(name, Class) names.emplace_back(name);
  HEMIVEM_ENGINES(HEMIVEM_NAME)
#undef HEMIVEM_NAME
  return names;
}

std::unique_ptr<NonsmoothMinimizer> make_minimizer(const std::string& name,
                                                   const std::map<std::string, double>& parameters) {
  const std::string n = normalized_engine_name(name);
#define HEMIVEM_MAKE(engine, Class) \
  if (n == engine) return std::make_unique<Class>(options_from_parameters<Class::Options>(parameters, engine));
  HEMIVEM_ENGINES(HEMIVEM_MAKE)
#undef HEMIVEM_MAKE
  const std::string list = join_engine_names(available_minimizers());
  const bool known = is_known_engine(known_minimizers(), n);
  throw InputError((known ? "minimizer '" + name + "' was not built" : "unknown minimizer '" + name + "'") +
                       "; available: " + (list.empty() ? "none" : list),
                   "minimizer");
}

}  // namespace hemivem
