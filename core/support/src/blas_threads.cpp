#include <hemivem/support/blas_threads.hpp>

#include <dlfcn.h>

#include <cstdlib>
#include <initializer_list>
#include <mutex>

namespace hemivem {

namespace {

using GetThreads = int (*)();
using SetThreads = void (*)(int);

// A symbol of a library already loaded: in the global scope (a program linked against it), or
// in one of `libraries` itself when it was loaded privately (a Python module's dependencies).
void* loaded_symbol(const char* name, std::initializer_list<const char*> libraries) {
  if (void* symbol = dlsym(RTLD_DEFAULT, name)) return symbol;
  for (const char* file : libraries) {
    void* library = dlopen(file, RTLD_LAZY | RTLD_NOLOAD);
    if (!library) continue;
    void* symbol = dlsym(library, name);
    dlclose(library);
    if (symbol) return symbol;
  }
  return nullptr;
}

void* openblas_symbol(const char* name) { return loaded_symbol(name, {"libopenblas.so.0"}); }

void* openmp_symbol(const char* name) { return loaded_symbol(name, {"libgomp.so.1", "libomp.so.5", "libomp.so"}); }

// Whether the environment sets `variable` (to anything but the empty string).
bool environment_sets(const char* variable) {
  const char* value = std::getenv(variable);
  return value && *value;
}

// OpenBLAS's thread count is one per process: the first holder sets it to 1 and remembers the
// count of before, the last one restores it.
struct BlasHolders {
  std::mutex mutex;
  int holders = 0;
  int before = 0;  // 0: nothing changed
};

BlasHolders& blas_holders() {
  static BlasHolders holders;
  return holders;
}

void hold_blas() {
  BlasHolders& h = blas_holders();
  const std::lock_guard lock(h.mutex);
  if (h.holders++ > 0) return;
  const auto get = reinterpret_cast<GetThreads>(openblas_symbol("openblas_get_num_threads"));
  const auto set = reinterpret_cast<SetThreads>(openblas_symbol("openblas_set_num_threads"));
  if (!get || !set) return;
  const int threads = get();
  if (threads <= 1) return;
  h.before = threads;
  set(1);
}

void release_blas() {
  BlasHolders& h = blas_holders();
  const std::lock_guard lock(h.mutex);
  if (--h.holders > 0 || h.before <= 1) return;
  if (const auto set = reinterpret_cast<SetThreads>(openblas_symbol("openblas_set_num_threads"))) set(h.before);
  h.before = 0;
}

}  // namespace

SingleThreadedBlas::SingleThreadedBlas() { hold_blas(); }

SingleThreadedBlas::~SingleThreadedBlas() { release_blas(); }

SingleThreadedRun::SingleThreadedRun() {
  if (!environment_sets("OPENBLAS_NUM_THREADS")) {
    hold_blas();
    blas_ = true;
  }
  if (environment_sets("OMP_NUM_THREADS")) return;
  const auto get = reinterpret_cast<GetThreads>(openmp_symbol("omp_get_max_threads"));
  const auto set = reinterpret_cast<SetThreads>(openmp_symbol("omp_set_num_threads"));
  if (!get || !set) return;
  const int threads = get();
  if (threads <= 1) return;
  openmp_before_ = threads;
  set(1);
}

SingleThreadedRun::~SingleThreadedRun() {
  if (openmp_before_ > 1) {
    if (const auto set = reinterpret_cast<SetThreads>(openmp_symbol("omp_set_num_threads"))) set(openmp_before_);
  }
  if (blas_) release_blas();
}

}  // namespace hemivem
