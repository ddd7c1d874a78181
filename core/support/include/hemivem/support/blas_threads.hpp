// The threads of the BLAS and of OpenMP around a run and around stretches of small dense work
// (docs/performance.md, "Threads").
#pragma once

namespace hemivem {

/// While alive, OpenBLAS (when it is the BLAS loaded; found at run time, nothing happens with
/// another) runs on one thread, and on the number it had before once the last such guard of the
/// process is destroyed (guards may overlap, in one thread or in several). For a loop of many
/// small dense operations, such as the steps of a loading path: between two calls OpenBLAS's
/// idle threads spin on the other cores and slow the one doing the work.
class SingleThreadedBlas {
 public:
  SingleThreadedBlas();
  ~SingleThreadedBlas();
  SingleThreadedBlas(const SingleThreadedBlas&) = delete;
  SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;
};

/// While alive, a run is single-threaded in its dense and sparse libraries: OpenBLAS runs on one
/// thread (as under SingleThreadedBlas) unless the environment sets OPENBLAS_NUM_THREADS, and
/// the OpenMP parallel regions the calling thread starts (the assembly's element loop, MUMPS,
/// CHOLMOD) run on one thread (omp_set_num_threads(1)) unless the environment sets
/// OMP_NUM_THREADS. Each is back to its count of before once destroyed, OpenMP's on the
/// constructing thread, which destroys the guard. The OpenMP runtime and OpenBLAS are found at
/// run time among the libraries loaded (libgomp, LLVM's libomp); what is not loaded is left
/// alone. app::run_scene holds one for the whole run.
class SingleThreadedRun {
 public:
  SingleThreadedRun();
  ~SingleThreadedRun();
  SingleThreadedRun(const SingleThreadedRun&) = delete;
  SingleThreadedRun& operator=(const SingleThreadedRun&) = delete;

 private:
  bool blas_ = false;      // holds a SingleThreadedBlas's share
  int openmp_before_ = 0;   // OpenMP's count before; 0: nothing changed
};

}  // namespace hemivem
