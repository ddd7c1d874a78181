#include <hemivem/linear_backends.hpp>

#include <hemivem/engine_names.hpp>
#include <hemivem/error.hpp>

#include <algorithm>
#include <array>

// The engines linked (hemivem_add_engine, cmake/HemivemEngines.cmake): their headers,
// HEMIVEM_ENGINES and HEMIVEM_ENGINE_<NAME>. The MPI engine is not among them: it is loaded as
// a module because the sequential and the MPI MUMPS builds export the same symbols
// (hemivem/mumps_mpi_plugin.hpp).
#include "linear_registry.hpp"

#ifdef HEMIVEM_HAVE_MUMPS_MPI
#include <hemivem/mumps_mpi_plugin.hpp>

#include <dlfcn.h>

#include <atomic>
#include <cstdlib>
#include <filesystem>
#include <mutex>
#include <system_error>
#include <vector>
#endif

namespace hemivem {

namespace {

std::string built_list() {
  const std::string list = join_engine_names(available_factorizations());
  return list.empty() ? "none" : list;
}

#ifdef HEMIVEM_HAVE_MUMPS_MPI
// Where the module may be, in this order:
//   1. the folder hemivem/ beside the file holding this code (found with dladdr): for a
//      shared libhemivem_linear, the installed layout, which the build tree reproduces;
//   2. <libdir>/hemivem relative to that file's folder taken as <bindir>: an installed
//      program holding a static libhemivem_linear;
//   3. the path of the module in the build tree;
//   4. the path of the module in the install prefix chosen at configure time.
// HEMIVEM_MUMPS_MPI_PLUGIN in the environment replaces the list.
std::vector<std::string> mumps_mpi_candidates() {
  const char* env = std::getenv("HEMIVEM_MUMPS_MPI_PLUGIN");
  if (env && *env) return {env};
  std::vector<std::string> paths;
  Dl_info info{};
  if (dladdr(reinterpret_cast<void*>(&mumps_mpi_candidates), &info) != 0 && info.dli_fname && *info.dli_fname) {
    std::error_code ec;
    std::filesystem::path self = std::filesystem::weakly_canonical(info.dli_fname, ec);
    if (ec) self = std::filesystem::path(info.dli_fname).lexically_normal();
    paths.push_back((self.parent_path() / "hemivem" / HEMIVEM_MUMPS_MPI_PLUGIN_NAME).string());
    paths.push_back(
        (self.parent_path() / HEMIVEM_MUMPS_MPI_PLUGIN_FROM_BINDIR / HEMIVEM_MUMPS_MPI_PLUGIN_NAME).lexically_normal().string());
  }
  paths.emplace_back(HEMIVEM_MUMPS_MPI_PLUGIN);
  paths.emplace_back(HEMIVEM_MUMPS_MPI_PLUGIN_INSTALLED);
  return paths;
}

// The module is loaded once and never unloaded (engines it created may outlive any scope).
std::atomic<MumpsMpiRankFunction> loaded_rank{nullptr};

CreateMumpsMpiFunction mumps_mpi_entry() {
  static std::once_flag once;
  static CreateMumpsMpiFunction create = nullptr;
  static std::string error;
  std::call_once(once, [] {
    const std::vector<std::string> candidates = mumps_mpi_candidates();
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
      error = "cannot find the mumps-mpi module (looked for " + tried +
              "; the environment variable HEMIVEM_MUMPS_MPI_PLUGIN sets its path)";
      return;
    }
    void* handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND);
    if (!handle) {
      const char* why = dlerror();
      error = "cannot load the mumps-mpi module " + path + ": " + (why ? why : "unknown error");
      return;
    }
    create = reinterpret_cast<CreateMumpsMpiFunction>(dlsym(handle, kCreateMumpsMpiSymbol));
    if (!create) error = "the mumps-mpi module " + path + " has no entry point " + kCreateMumpsMpiSymbol;
    const auto rank = reinterpret_cast<MumpsMpiRankFunction>(dlsym(handle, kMumpsMpiRankSymbol));
    if (create && !rank) {
      create = nullptr;
      error = "the mumps-mpi module " + path + " has no entry point " + kMumpsMpiRankSymbol;
    }
    loaded_rank = rank;
  });
  if (!create) throw InputError(error, "engine");
  return create;
}
#endif

}  // namespace

std::vector<std::string> available_factorizations() {
  std::vector<std::string> names;
#define HEMIVEM_NAME(name, Class) names.emplace_back(name);
  HEMIVEM_ENGINES(HEMIVEM_NAME)
#undef HEMIVEM_NAME
#ifdef HEMIVEM_HAVE_MUMPS_MPI
  names.emplace_back("mumps-mpi");
#endif
  return names;
}

ReferenceFactorization measure_reference_factorization(const SparseMatrix& A, bool metis) {
#ifdef HEMIVEM_ENGINE_CHOLMOD
  return measure_cholmod_factorization(A, metis);
#else
  (void)A, (void)metis;
  throw InputError("the reference factorization is CHOLMOD's, and the cholmod engine was not built; available: " +
                       built_list(),
                   "engine");
#endif
}

int factorization_process_rank() {
#ifdef HEMIVEM_HAVE_MUMPS_MPI
  if (const MumpsMpiRankFunction rank = loaded_rank.load()) return rank();
#endif
  return 0;
}

std::string fastest_factorization(int dimension) {
  const std::vector<std::string> built = available_factorizations();
  const auto order = dimension == 3 ? std::array<const char*, 3>{"cholmod", "mumps", "eigen"}
                                    : std::array<const char*, 3>{"mumps", "cholmod", "eigen"};
  for (const char* fastest : order)
    if (std::find(built.begin(), built.end(), fastest) != built.end()) return fastest;
  return built.empty() ? std::string("eigen") : built.front();
}

std::unique_ptr<SparseFactorization> make_factorization(const FactorizationOptions& options) {
  const std::string name =
      normalized_engine_name(options.engine) == "auto" ? fastest_factorization() : normalized_engine_name(options.engine);
  const auto built = available_factorizations();
  if (std::find(built.begin(), built.end(), name) == built.end()) {
    const bool known = is_known_engine(known_linear_engines(), name);
    throw InputError(known ? "linear engine '" + options.engine + "' was not built; available: " + built_list()
                           : "unknown linear engine '" + options.engine + "'; available: " + built_list(),
                     "engine");
  }
  std::string error;
  if (!options.is_valid(&error)) throw InputError(error, "linear engine options");

#define HEMIVEM_MAKE(engine, Class) \
  if (name == engine) return std::make_unique<Class>(options);
  HEMIVEM_ENGINES(HEMIVEM_MAKE)
#undef HEMIVEM_MAKE
#ifdef HEMIVEM_HAVE_MUMPS_MPI
  if (name == "mumps-mpi") return std::unique_ptr<SparseFactorization>(mumps_mpi_entry()(&options));
#endif
  throw InputError("linear engine '" + options.engine + "' was not built; available: " + built_list(), "engine");
}

}  // namespace hemivem
