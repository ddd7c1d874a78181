// Entry points of the loadable PETSc Krylov module (see hemivem/petsc_krylov_plugin.hpp): the
// engines, the processes of PETSC_COMM_WORLD and their distributed rows. None lets an exception
// out: failures are described in a PetscModuleError.
#include <hemivem/petsc_krylov_plugin.hpp>
#include <hemivem/petsc_krylov_solver.hpp>
#include <hemivem/petsc_row_distribution.hpp>

#include <string_view>

#include "petsc_support.hpp"

extern "C" {

__attribute__((visibility("default"))) hemivem::KrylovSolver* hemivem_create_petsc_krylov(const char* name) {
  const std::string_view n = name ? name : "";
  if (n == "petsc-gamg") return new hemivem::PetscGamgSolver();
  if (n == "petsc-hypre") return new hemivem::PetscHypreSolver();
  return nullptr;
}

__attribute__((visibility("default"))) int hemivem_petsc_world(int* rank, int* size,
                                                               hemivem::PetscModuleError* error) {
  try {
    if (const std::string& why = hemivem::petsc::PetscRuntime::instance().start(); !why.empty())
      throw hemivem::InputError("the PETSc Krylov module cannot start PETSc: " + why);
    if (!hemivem::petsc::PetscRuntime::running()) throw hemivem::InputError("PETSc was finalized in this process");
    *rank = hemivem::petsc::comm_rank(PETSC_COMM_WORLD);
    *size = hemivem::petsc::comm_size(PETSC_COMM_WORLD);
    return 0;
  } catch (...) {
    error->describe_current_exception();
    return 1;
  }
}

__attribute__((visibility("default"))) hemivem::RowDistribution* hemivem_create_petsc_rows(
    std::int64_t first, std::int64_t owned, std::int64_t global, const std::int64_t* ghosts, std::int64_t ghost_count,
    hemivem::PetscModuleError* error) {
  try {
    hemivem::RowLayout layout;
    layout.first = static_cast<Eigen::Index>(first);
    layout.owned = static_cast<Eigen::Index>(owned);
    layout.global = static_cast<Eigen::Index>(global);
    if (ghost_count > 0) layout.ghosts.assign(ghosts, ghosts + ghost_count);
    return new hemivem::PetscRowDistribution(std::move(layout));
  } catch (...) {
    error->describe_current_exception();
    return nullptr;
  }
}

}  // extern "C"

// The signatures must match those the loader casts to.
namespace {
[[maybe_unused]] constexpr hemivem::CreatePetscKrylovFunction kCreate = &hemivem_create_petsc_krylov;
[[maybe_unused]] constexpr hemivem::PetscWorldFunction kWorld = &hemivem_petsc_world;
[[maybe_unused]] constexpr hemivem::CreatePetscRowsFunction kRows = &hemivem_create_petsc_rows;
}  // namespace
