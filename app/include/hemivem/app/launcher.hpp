// The processes an MPI launcher started a run as, read from the launcher's environment.
#pragma once

namespace hemivem::app {

/// The processes an MPI launcher (mpirun, mpiexec, srun) started for this run, as the launcher's
/// environment tells (Open MPI: OMPI_COMM_WORLD_SIZE / _RANK; MPICH, Intel MPI, srun with PMI:
/// PMI_SIZE / PMI_RANK; MVAPICH: MV2_COMM_WORLD_SIZE / _RANK): size 1, rank 0 without one.
/// Read without MPI: neither the command nor the Python module links MPI (docs/cluster.md).
struct LaunchedProcesses {
  int rank = 0;
  int size = 1;
};
LaunchedProcesses launched_processes();

}  // namespace hemivem::app
