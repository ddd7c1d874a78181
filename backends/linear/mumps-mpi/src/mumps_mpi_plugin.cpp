// Entry points of the loadable mumps-mpi module (see hemivem/mumps_mpi_plugin.hpp).
#include <hemivem/mumps_mpi_factorization.hpp>
#include <hemivem/mumps_mpi_plugin.hpp>

extern "C" {

__attribute__((visibility("default"))) hemivem::SparseFactorization* hemivem_create_mumps_mpi(
    const hemivem::FactorizationOptions* options) {
  return new hemivem::MumpsMpiFactorization(options ? *options : hemivem::FactorizationOptions{});
}

__attribute__((visibility("default"))) int hemivem_mumps_mpi_rank() {
  return hemivem::MumpsMpiFactorization::mpi_rank();
}

}  // extern "C"

// The signatures must match the ones the loader casts to.
namespace {
[[maybe_unused]] constexpr hemivem::CreateMumpsMpiFunction kCreate = &hemivem_create_mumps_mpi;
[[maybe_unused]] constexpr hemivem::MumpsMpiRankFunction kRank = &hemivem_mumps_mpi_rank;
}  // namespace
