// Entry point of the loadable PETSc Krylov module (see hemivem/petsc_krylov_plugin.hpp).
#include <hemivem/petsc_krylov_plugin.hpp>
#include <hemivem/petsc_krylov_solver.hpp>

#include <string_view>

extern "C" {

__attribute__((visibility("default"))) hemivem::KrylovSolver* hemivem_create_petsc_krylov(const char* name) {
  const std::string_view n = name ? name : "";
  if (n == "petsc-gamg") return new hemivem::PetscGamgSolver();
  if (n == "petsc-hypre") return new hemivem::PetscHypreSolver();
  return nullptr;
}

}  // extern "C"

// The signature must match the one the loader casts to.
namespace {
[[maybe_unused]] constexpr hemivem::CreatePetscKrylovFunction kCreate = &hemivem_create_petsc_krylov;
}  // namespace
