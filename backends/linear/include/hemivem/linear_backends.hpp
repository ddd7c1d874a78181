// The factory of the sparse factorization engines (as Ceres' SparseCholesky::Create).
//
//   auto f = hemivem::make_factorization({.engine = "cholmod"});
//
// Engine names are case-insensitive ('_' and '-' are the same). Only the engines found at
// configure time are built; asking for another one is an input error that lists those built.
#pragma once

#include <hemivem/reference_factorization.hpp>
#include <hemivem/sparse_factorization.hpp>

#include <memory>
#include <string>
#include <vector>

namespace hemivem {

/// A new engine for `options.engine` ("auto": fastest_factorization()). Throws InputError when
/// the options are invalid, the name is unknown, or the engine was not built; the message lists
/// the engines built.
std::unique_ptr<SparseFactorization> make_factorization(const FactorizationOptions& options);

/// The fastest engine built that runs in one process, by measurement of whole solves in the
/// plane and in a solid (docs/performance.md): cholmod, else mumps, else eigen.
std::string fastest_factorization();

/// The engines built into this library, in the order eigen, cholmod, mumps, mumps-mpi.
std::vector<std::string> available_factorizations();

/// The yardstick of `hemivem bench --limit` (docs/performance.md): one analysis and one
/// numeric factorization of A (its lower triangle) by CHOLMOD alone, supernodal, with AMD
/// (`metis` false) or METIS (`metis` true), timed. InputError when the cholmod engine was not
/// built (see available_factorizations()).
ReferenceFactorization measure_reference_factorization(const SparseMatrix& A, bool metis);

/// This process' rank among the processes of an engine across processes: its rank in
/// MPI_COMM_WORLD once a mumps-mpi engine has been created (the module is loaded), 0 otherwise.
/// Never loads the module nor initializes MPI, so a program can ask it at any time.
int factorization_process_rank();

}  // namespace hemivem
