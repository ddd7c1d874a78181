// The Krylov factory: available_krylov_solvers(), make_krylov_solver(), krylov_world() and
// make_distributed_rows() of hemivem/krylov_solver.hpp. With the PETSc engines built, the
// engines, the processes and the distributed rows come from the PETSc module's entry points
// (hemivem/petsc_krylov_plugin.hpp), whose failures are rethrown here as the exceptions they
// describe; without them there is one process.
#include <hemivem/krylov_solver.hpp>

#include <hemivem/engine_names.hpp>
#include <hemivem/error.hpp>

#include <algorithm>
#include <cstdint>
#include <string>
#include <vector>

// The engines linked (hemivem_add_engine, cmake/HemivemEngines.cmake): their headers,
// HEMIVEM_ENGINES and HEMIVEM_ENGINE_<NAME>. The PETSc engines are not among them: they are
// loaded as a module because Debian's PETSc links the MPI build of MUMPS, whose symbols are
// those of the sequential MUMPS hemivem links (hemivem/petsc_krylov_plugin.hpp).
#include "krylov_registry.hpp"

#ifdef HEMIVEM_HAVE_PETSC_KRYLOV
#include <hemivem/petsc_krylov_plugin.hpp>

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

// The module is loaded once and never unloaded (engines and rows it created may outlive any
// scope).
const engine_module::Module& petsc_loaded() {
  static const engine_module::Module module = engine_module::open(petsc_module());
  return module;
}

/// The module's entry point `symbol`; InputError when the module cannot be loaded or lacks it.
template <class Function>
Function petsc_entry(const char* symbol) {
  std::string error;
  const Function function = petsc_loaded().entry<Function>(symbol, &error);
  if (!function) throw InputError(error, "krylov engine");
  return function;
}
#endif

/// In one process, the rows of `layout` if they are all of them (OneProcessRows); null otherwise.
std::unique_ptr<RowDistribution> one_process_rows(const RowLayout& layout) {
  if (layout.first == 0 && layout.owned >= 0 && layout.owned == layout.global && layout.ghosts.empty())
    return std::make_unique<OneProcessRows>(layout.global);
  return nullptr;
}

std::string describe(const RowLayout& layout) {
  return "rows " + std::to_string(layout.first) + ".." + std::to_string(layout.first + layout.owned - 1) + " of " +
         std::to_string(layout.global) + " with " + std::to_string(layout.ghosts.size()) + " ghosts";
}

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
  if (KrylovSolver* solver = petsc_entry<CreatePetscKrylovFunction>(kCreatePetscKrylovSymbol)(normalized.c_str()))
    return std::unique_ptr<KrylovSolver>(solver);
#endif
  throw InputError("Krylov engine '" + name + "' was not built; available: " + built_list(), "krylov engine");
}

ProcessWorld krylov_world() {
  ProcessWorld world;
#ifdef HEMIVEM_HAVE_PETSC_KRYLOV
  PetscModuleError error;
  if (petsc_entry<PetscWorldFunction>(kPetscWorldSymbol)(&world.rank, &world.size, &error) != 0) rethrow(error);
#endif
  return world;
}

std::unique_ptr<RowDistribution> process_rows() {
  const ProcessWorld world = krylov_world();
  RowLayout one;
  one.first = world.rank;
  one.owned = 1;
  one.global = world.size;
  return make_distributed_rows(one);
}

std::unique_ptr<RowDistribution> make_distributed_rows(RowLayout layout) {
#ifdef HEMIVEM_HAVE_PETSC_KRYLOV
  const ProcessWorld world = krylov_world();
  if (world.size == 1) {
    if (auto rows = one_process_rows(layout)) return rows;
    throw InternalError("inconsistent row layout in one process: " + describe(layout) +
                        " (one process owns rows 0..global-1 and has no ghosts)");
  }
  const std::vector<std::int64_t> ghosts(layout.ghosts.begin(), layout.ghosts.end());
  PetscModuleError error;
  RowDistribution* rows = petsc_entry<CreatePetscRowsFunction>(kCreatePetscRowsSymbol)(
      static_cast<std::int64_t>(layout.first), static_cast<std::int64_t>(layout.owned),
      static_cast<std::int64_t>(layout.global), ghosts.data(), static_cast<std::int64_t>(ghosts.size()), &error);
  if (!rows) rethrow(error);
  if (!rows) throw InternalError("the PETSc Krylov module made no distributed rows");
  return std::unique_ptr<RowDistribution>(rows);
#else
  if (auto rows = one_process_rows(layout)) return rows;
  throw InputError("distributed rows (" + describe(layout) +
                       ") need the PETSc engines petsc-gamg and petsc-hypre, which were not built",
                   "krylov engine");
#endif
}

}  // namespace hemivem
