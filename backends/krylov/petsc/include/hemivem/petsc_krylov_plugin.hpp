// The PETSc Krylov engines as a loadable module (PETSc's Debian build links the MPI build of
// MUMPS, whose symbols are those of the sequential MUMPS hemivem's programs hold).
//
// The module hemivem_krylov_petsc_plugin (a CMake MODULE library) contains petsc-gamg and
// petsc-hypre (hemivem/petsc_krylov_solver.hpp) with PETSc, hypre and MPI behind them. The
// Krylov factory loads it with
//
//   void* handle = dlopen(path, RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND);
//
// (RTLD_LOCAL keeps its symbols out of the global scope; RTLD_DEEPBIND makes the module and its
// dependencies resolve their own symbols first), looks up the entry point below with dlsym()
// and never unloads it.
#pragma once

#include <hemivem/krylov_solver.hpp>

namespace hemivem {

/// Signature of "hemivem_create_petsc_krylov": a new engine "petsc-gamg" or "petsc-hypre"
/// (the normalized name), null for another name; the caller deletes it.
using CreatePetscKrylovFunction = KrylovSolver* (*)(const char* name);

inline constexpr const char* kCreatePetscKrylovSymbol = "hemivem_create_petsc_krylov";

}  // namespace hemivem
