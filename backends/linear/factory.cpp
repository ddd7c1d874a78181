#include <hemivem/linear_backends.hpp>

#include <hemivem/engine_names.hpp>
#include <hemivem/error.hpp>

#include <algorithm>

// The engines linked (hemivem_add_engine, cmake/HemivemEngines.cmake): their headers,
// HEMIVEM_ENGINES and HEMIVEM_ENGINE_<NAME>. The MPI engine is not among them: it is loaded as
// a module because the sequential and the MPI MUMPS builds export the same symbols
// (hemivem/mumps_mpi_plugin.hpp).
#include "linear_registry.hpp"

#ifdef HEMIVEM_HAVE_MUMPS_MPI
#include <hemivem/mumps_mpi_plugin.hpp>

#include <atomic>
#include <mutex>

#include "engine_module.hpp"
#endif

namespace hemivem {

namespace {

std::string built_list() {
  const std::string list = join_engine_names(available_factorizations());
  return list.empty() ? "none" : list;
}

#ifdef HEMIVEM_HAVE_MUMPS_MPI
// The module, looked for beside this library first (engine_module::candidates);
// HEMIVEM_MUMPS_MPI_PLUGIN in the environment replaces the list.
engine_module::Location mumps_mpi_module() {
  return {"the mumps-mpi module",
          "HEMIVEM_MUMPS_MPI_PLUGIN",
          HEMIVEM_MUMPS_MPI_PLUGIN_NAME,
          HEMIVEM_MUMPS_MPI_PLUGIN_FROM_BINDIR,
          HEMIVEM_MUMPS_MPI_PLUGIN,
          HEMIVEM_MUMPS_MPI_PLUGIN_INSTALLED,
          reinterpret_cast<const void*>(&mumps_mpi_module)};
}

// The module is loaded once and never unloaded (engines it created may outlive any scope).
std::atomic<MumpsMpiRankFunction> loaded_rank{nullptr};

CreateMumpsMpiFunction mumps_mpi_entry() {
  static std::once_flag once;
  static CreateMumpsMpiFunction create = nullptr;
  static std::string error;
  std::call_once(once, [] {
    const engine_module::Module module = engine_module::open(mumps_mpi_module());
    create = module.entry<CreateMumpsMpiFunction>(kCreateMumpsMpiSymbol, &error);
    std::string rank_error;
    const auto rank = module.entry<MumpsMpiRankFunction>(kMumpsMpiRankSymbol, &rank_error);
    if (create && !rank) {
      create = nullptr;
      error = rank_error;
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

std::string fastest_factorization() {
  const std::vector<std::string> built = available_factorizations();
  for (const char* fastest : {"cholmod", "mumps", "eigen"})
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
