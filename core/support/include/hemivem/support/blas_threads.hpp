// The BLAS's threads around stretches of small dense work (docs/performance.md, "Threads").
#pragma once

namespace hemivem {

/// While alive, OpenBLAS (when it is the BLAS loaded; found at run time, nothing happens with
/// another) runs on one thread, and on the number it had before once destroyed. For a loop of
/// many small dense operations, such as the steps of a loading path: between two calls
/// OpenBLAS's idle threads spin on the other cores and slow the one doing the work.
class SingleThreadedBlas {
 public:
  SingleThreadedBlas();
  ~SingleThreadedBlas();
  SingleThreadedBlas(const SingleThreadedBlas&) = delete;
  SingleThreadedBlas& operator=(const SingleThreadedBlas&) = delete;

 private:
  int before_ = 0;  // 0: nothing changed
};

}  // namespace hemivem
