// The rows of a system distributed over the processes of PETSC_COMM_WORLD (MPI_COMM_WORLD under
// mpirun): the RowDistribution (hemivem/row_distribution.hpp) that the PETSc Krylov engines
// read in KrylovHints::rows, made by make_distributed_rows() (hemivem/krylov_solver.hpp)
// through the module's entry point (hemivem/petsc_krylov_plugin.hpp).
//
//   sum, max        MPI_Allreduce;
//   update_ghosts   a PETSc ghosted vector (VecCreateGhost) made once at construction with this
//                   process's ghosts: each call copies the owned entries in, runs PETSc's ghost
//                   update (VecGhostUpdateBegin/End, INSERT_VALUES, SCATTER_FORWARD) and copies
//                   the ghosts' entries out; the vector's size is checked on every process
//                   (one small MPI_Allreduce) so that a size that does not fit throws
//                   InternalError on every process instead of leaving the others waiting;
//   all_gather      MPI_Allgatherv (any number of entries per process, none included);
//   send_to, receive_from_first
//                   MPI_Send and MPI_Probe, MPI_Get_count, MPI_Recv of bytes (MPI_BYTE) with
//                   a tag of their own; at most what MPI counts in an int (InternalError on
//                   the sender beyond);
//   broadcast_from_first
//                   MPI_Bcast of the size, then of the bytes in parts of at most what MPI
//                   counts in an int.
//
// The construction is collective and checks the layouts of all processes together (every
// process gathers every process's range and the first defect of its ghosts): ranges
// contiguous in the order of the ranks from row 0, their sizes summing to the global count
// that every process gives, ghosts increasing, within the rows and owned by another process.
// An inconsistent layout throws InternalError with the same message on every process; a PETSc
// failure while the ghost exchange is set up throws Error, on every process too.
//
// PETSc must run (the entry point starts it as the engines do). The object keeps PETSc from
// being finalized at program exit while it lives.
#pragma once

#include <hemivem/row_distribution.hpp>

#include <memory>

namespace hemivem {

class PetscRowDistribution final : public RowDistribution {
 public:
  /// Collective over PETSC_COMM_WORLD (see above).
  explicit PetscRowDistribution(RowLayout layout);
  ~PetscRowDistribution() override;
  PetscRowDistribution(const PetscRowDistribution&) = delete;
  PetscRowDistribution& operator=(const PetscRowDistribution&) = delete;

  int rank() const override;
  int size() const override;
  const RowLayout& layout() const override;
  double sum(double value) const override;
  double max(double value) const override;
  void update_ghosts(Eigen::VectorXd& v) const override;
  Eigen::VectorXd all_gather(const Eigen::VectorXd& mine) const override;
  Eigen::VectorXd gather_to_first(const Eigen::VectorXd& mine) const override;
  void send_to(int to, std::span<const char> bytes) const override;
  std::vector<char> receive_from_first() const override;
  void broadcast_from_first(std::vector<char>& bytes) const override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace hemivem
