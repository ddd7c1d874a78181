// The Krylov factory: available_krylov_solvers() and make_krylov_solver() of
// hemivem/krylov_solver.hpp.
#include <hemivem/krylov_solver.hpp>

#include <hemivem/engine_names.hpp>
#include <hemivem/error.hpp>

#include <algorithm>

// The engines linked (hemivem_add_engine, cmake/HemivemEngines.cmake): their headers,
// HEMIVEM_ENGINES and HEMIVEM_ENGINE_<NAME>. The PETSc engines are not among them: they are
// loaded as a module because Debian's PETSc links the MPI build of MUMPS, whose symbols are
// those of the sequential MUMPS hemivem links (hemivem/petsc_krylov_plugin.hpp).
#include "krylov_registry.hpp"

#ifdef HEMIVEM_HAVE_PETSC_KRYLOV
#include <hemivem/petsc_krylov_plugin.hpp>

#include <mutex>

#include "engine_module.hpp"
#endif

namespace hemivem {

namespace {

std::string built_list() {
  const std::string list = join_engine_names(available_krylov_solvers());
  return list.empty() ? "none" : list;
}

#ifdef HEMIVEM_HAVE_PETSC_KRYLOV
// The module, looked for beside this library first (engine_module::candidates);
// HEMIVEM_PETSC_PLUGIN in the environment replaces the list.
engine_module::Location petsc_module() {
  return {"the PETSc Krylov module",
          "HEMIVEM_PETSC_PLUGIN",
          HEMIVEM_PETSC_PLUGIN_NAME,
          HEMIVEM_PETSC_PLUGIN_FROM_BINDIR,
          HEMIVEM_PETSC_PLUGIN,
          HEMIVEM_PETSC_PLUGIN_INSTALLED,
          reinterpret_cast<const void*>(&petsc_module)};
}

// The module is loaded once and never unloaded (engines it created may outlive any scope).
CreatePetscKrylovFunction petsc_entry() {
  static std::once_flag once;
  static CreatePetscKrylovFunction create = nullptr;
  static std::string error;
  std::call_once(once, [] {
    create = engine_module::open(petsc_module()).entry<CreatePetscKrylovFunction>(kCreatePetscKrylovSymbol, &error);
  });
  if (!create) throw InputError(error, "krylov engine");
  return create;
}
#endif

}  // namespace

std::vector<std::string> available_krylov_solvers() {
  std::vector<std::string> names;
#ifdef HEMIVEM_HAVE_PETSC_KRYLOV
  names.emplace_back("petsc-gamg");
  names.emplace_back("petsc-hypre");
#endif
#define HEMIVEM_NAME(name, Class) names.emplace_back(name);
  HEMIVEM_ENGINES(HEMIVEM_NAME)
#undef HEMIVEM_NAME
  // In the order of known_krylov_solvers(), the order of preference.
  const auto& known = known_krylov_solvers();
  std::stable_sort(names.begin(), names.end(), [&](const std::string& a, const std::string& b) {
    return std::find(known.begin(), known.end(), a) < std::find(known.begin(), known.end(), b);
  });
  return names;
}

std::unique_ptr<KrylovSolver> make_krylov_solver(const std::string& name) {
  const auto built = available_krylov_solvers();
  const std::string normalized = normalized_engine_name(name);
  if (normalized == "auto") {
    if (built.empty()) throw InputError("no Krylov engine was built", "krylov engine");
    return make_krylov_solver(built.front());
  }
  if (std::find(built.begin(), built.end(), normalized) == built.end()) {
    throw InputError(is_krylov_solver(normalized)
                         ? "Krylov engine '" + name + "' was not built; available: " + built_list()
                         : "unknown Krylov engine '" + name + "'; available: " + built_list(),
                     "krylov engine");
  }
#define HEMIVEM_MAKE(engine, Class) \
  if (normalized == engine) return std::make_unique<Class>();
  HEMIVEM_ENGINES(HEMIVEM_MAKE)
#undef HEMIVEM_MAKE
#ifdef HEMIVEM_HAVE_PETSC_KRYLOV
  if (KrylovSolver* solver = petsc_entry()(normalized.c_str())) return std::unique_ptr<KrylovSolver>(solver);
#endif
  throw InputError("Krylov engine '" + name + "' was not built; available: " + built_list(), "krylov engine");
}

}  // namespace hemivem
