// The PETSc Krylov engines as a loadable module (PETSc's Debian build links the MPI build of
// MUMPS, whose symbols are those of the sequential MUMPS hemivem's programs hold).
//
// The module hemivem_krylov_petsc_plugin (a CMake MODULE library) contains petsc-gamg and
// petsc-hypre (hemivem/petsc_krylov_solver.hpp) with PETSc, hypre and MPI behind them. The
// Krylov factory loads it with
//
//   void* handle = dlopen(path, RTLD_NOW | RTLD_LOCAL | deep);
//
// where deep is RTLD_DEEPBIND when the program's global scope defines MPI's or MUMPS's symbols
// (the command links the sequential MUMPS, which brings MPI stand-ins) and 0 otherwise (a Python
// interpreter, whose own copy of `environ` MPI must share). RTLD_LOCAL keeps the module's
// symbols out of the global scope; RTLD_DEEPBIND makes the module and its dependencies resolve
// their own symbols first. The factory looks up the entry points below with dlsym() and never
// unloads it. Everything MPI of the Krylov engines goes through this module: the
// processes (krylov_world()) and the distributed rows (make_distributed_rows()) as well as the
// engines.
//
// No exception leaves an entry point: the two below that may fail catch everything and describe
// it in a PetscModuleError (its kind and its message), from which the factory throws the same
// kind of exception again (rethrow()). The engines' own methods throw as their contract says
// (the objects are hemivem classes; the module and the library share the C++ runtime).
#pragma once

#include <hemivem/error.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/row_distribution.hpp>

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <exception>
#include <string>

namespace hemivem {

/// Signature of "hemivem_create_petsc_krylov": a new engine "petsc-gamg" or "petsc-hypre"
/// (the normalized name), null for another name; the caller deletes it.
using CreatePetscKrylovFunction = KrylovSolver* (*)(const char* name);

inline constexpr const char* kCreatePetscKrylovSymbol = "hemivem_create_petsc_krylov";

/// How an entry point failed, in plain C data: `kind` says which exception the caller throws
/// with `message` (truncated to the buffer).
struct PetscModuleError {
  enum Kind : int {
    none = 0,      ///< no failure
    internal = 1,  ///< InternalError: the arguments break the contract (an inconsistent layout)
    input = 2,     ///< InputError: PETSc cannot be used (it failed to start, or was finalized)
    other = 3,     ///< Error: anything else (a PETSc error)
  };
  int kind = none;
  char message[1024] = {};

  /// In the module, within a catch block: the exception being handled.
  void describe_current_exception() noexcept {
    const char* text = "unknown exception";
    kind = other;
    try {
      throw;
    } catch (const InternalError& e) {
      kind = internal, text = e.what();
    } catch (const InputError& e) {
      kind = input, text = e.what();
    } catch (const std::exception& e) {
      text = e.what();
    } catch (...) {
    }
    std::strncpy(message, text, sizeof(message) - 1);
    message[sizeof(message) - 1] = '\0';
  }
};

/// In the library: throws the exception `error` describes (nothing for PetscModuleError::none).
inline void rethrow(const PetscModuleError& error) {
  const std::string message(error.message);
  switch (error.kind) {
    case PetscModuleError::none:
      return;
    case PetscModuleError::internal:
      throw InternalError(message);
    case PetscModuleError::input:
      throw InputError(message, "krylov engine");
    default:
      throw Error(message);
  }
}

/// Signature of "hemivem_petsc_world": starts PETSc as the engines do (PetscInitializeNoArguments,
/// which initializes MPI when nobody did: a program started without mpirun is an MPI singleton)
/// and sets *rank and *size to this process's rank in PETSC_COMM_WORLD (MPI_COMM_WORLD) and their
/// number. Returns 0; otherwise nonzero with *error set (input when PETSc cannot start).
using PetscWorldFunction = int (*)(int* rank, int* size, PetscModuleError* error);

inline constexpr const char* kPetscWorldSymbol = "hemivem_petsc_world";

/// Signature of "hemivem_create_petsc_rows": collective over PETSC_COMM_WORLD, a new
/// PetscRowDistribution (hemivem/petsc_row_distribution.hpp) of the layout {first, owned, global,
/// ghosts[0..ghost_count)} (RowLayout's fields); the caller deletes it. Returns null with *error
/// set on every process otherwise (internal for an inconsistent layout, with the same message
/// on every process).
using CreatePetscRowsFunction = RowDistribution* (*)(std::int64_t first, std::int64_t owned, std::int64_t global,
                                                     const std::int64_t* ghosts, std::int64_t ghost_count,
                                                     PetscModuleError* error);

inline constexpr const char* kCreatePetscRowsSymbol = "hemivem_create_petsc_rows";

}  // namespace hemivem
