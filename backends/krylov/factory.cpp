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

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <system_error>
#endif

namespace hemivem {

namespace {

std::string built_list() {
  const std::string list = join_engine_names(available_krylov_solvers());
  return list.empty() ? "none" : list;
}

#ifdef HEMIVEM_HAVE_PETSC_KRYLOV
// Where the module may be, in this order:
//   1. the folder hemivem/ beside the file holding this code (found with dladdr): for a
//      shared libhemivem_krylov, the installed layout, which the build tree reproduces;
//   2. <libdir>/hemivem relative to that file's folder taken as <bindir>: an installed
//      program holding a static libhemivem_krylov;
//   3. the path of the module in the build tree;
//   4. the path of the module in the install prefix chosen at configure time.
// HEMIVEM_PETSC_PLUGIN in the environment replaces the list.
std::vector<std::string> petsc_candidates() {
  const char* env = std::getenv("HEMIVEM_PETSC_PLUGIN");
  if (env && *env) return {env};
  std::vector<std::string> paths;
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&petsc_candidates), &info) != 0 && info.dli_fname && *info.dli_fname) {
    std::error_code ec;
    std::filesystem::path self = std::filesystem::weakly_canonical(info.dli_fname, ec);
    if (ec) self = std::filesystem::path(info.dli_fname).lexically_normal();
    paths.push_back((self.parent_path() / "hemivem" / HEMIVEM_PETSC_PLUGIN_NAME).string());
    const std::filesystem::path from_bindir = self.parent_path() / HEMIVEM_PETSC_PLUGIN_FROM_BINDIR;
    paths.push_back((from_bindir / HEMIVEM_PETSC_PLUGIN_NAME).lexically_normal().string());
  }
  paths.emplace_back(HEMIVEM_PETSC_PLUGIN);
  paths.emplace_back(HEMIVEM_PETSC_PLUGIN_INSTALLED);
  return paths;
}

// The module is loaded once and never unloaded (engines it created may outlive any scope).
CreatePetscKrylovFunction petsc_entry() {
  static std::once_flag once;
  static CreatePetscKrylovFunction create = nullptr;
  static std::string error;
  std::call_once(once, [] {
    const std::vector<std::string> candidates = petsc_candidates();
    std::string path;
    for (const std::string& candidate : candidates) {
      std::error_code ec;
      if (std::filesystem::is_regular_file(candidate, ec)) {
        path = candidate;
        break;
      }
    }
    if (path.empty()) {
      std::string tried;
      for (const std::string& candidate : candidates) tried += (tried.empty() ? "" : ", ") + candidate;
      error = "cannot find the PETSc Krylov module (looked for " + tried +
              "; the environment variable HEMIVEM_PETSC_PLUGIN sets its path)";
      return;
    }
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND);
    if (!handle) {
      const char* why = dlerror();
      error = "cannot load the PETSc Krylov module " + path + ": " + (why ? why : "unknown error");
      return;
    }
    create = reinterpret_cast<CreatePetscKrylovFunction>(dlsym(handle, kCreatePetscKrylovSymbol));
    if (!create) error = "the PETSc Krylov module " + path + " has no entry point " + kCreatePetscKrylovSymbol;
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
