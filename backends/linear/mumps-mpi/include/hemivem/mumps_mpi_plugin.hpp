// The mumps-mpi engine as a loadable module, for programs that also hold the sequential MUMPS
// engine (the two MUMPS builds export the same symbols and cannot be linked into one program).
//
// The module hemivem_linear_mumps_mpi_plugin (a CMake MODULE library) contains the MPI
// engine with its MUMPS and MPI dependencies. Load it with
//
//   void* handle = dlopen(path, RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND);
//
// RTLD_LOCAL keeps its symbols out of the global scope; RTLD_DEEPBIND makes the module and its
// dependencies (libdmumps, libmumps_common, MPI) resolve their own symbols first instead of the
// sequential MUMPS already loaded with the program. Then look up the entry points below with
// dlsym(). Every rule of hemivem/mumps_mpi_factorization.hpp applies to the engine returned
// (SPMD, data on rank 0, MPI initialized and finalized by the module when the program did not).
// RTLD_DEEPBIND is a glibc extension and does not combine with AddressSanitizer.
#pragma once

#include <hemivem/sparse_factorization.hpp>

namespace hemivem {

/// Signature of "hemivem_create_mumps_mpi": a new engine (delete it before unloading).
using CreateMumpsMpiFunction = SparseFactorization* (*)(const FactorizationOptions* options);
/// Signature of "hemivem_mumps_mpi_rank": this process' rank in MPI_COMM_WORLD.
using MumpsMpiRankFunction = int (*)();

inline constexpr const char* kCreateMumpsMpiSymbol = "hemivem_create_mumps_mpi";
inline constexpr const char* kMumpsMpiRankSymbol = "hemivem_mumps_mpi_rank";

}  // namespace hemivem
