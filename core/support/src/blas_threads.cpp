#include <hemivem/support/blas_threads.hpp>

#include <dlfcn.h>

namespace hemivem {

namespace {

using GetThreads = int (*)();
using SetThreads = void (*)(int);

// A symbol of the OpenBLAS already loaded: in the global scope (a program linked against it), or
// in the library itself when it was loaded privately (a Python module's dependencies).
void* openblas_symbol(const char* name) {
  if (void* symbol = dlsym(RTLD_DEFAULT, name)) return symbol;
  void* library = dlopen("libopenblas.so.0", RTLD_LAZY | RTLD_NOLOAD);
  if (!library) return nullptr;
  void* symbol = dlsym(library, name);
  dlclose(library);
  return symbol;
}

}  // namespace

SingleThreadedBlas::SingleThreadedBlas() {
  const auto get = reinterpret_cast<GetThreads>(openblas_symbol("openblas_get_num_threads"));
  const auto set = reinterpret_cast<SetThreads>(openblas_symbol("openblas_set_num_threads"));
  if (!get || !set) return;
  const int threads = get();
  if (threads <= 1) return;
  before_ = threads;
  set(1);
}

SingleThreadedBlas::~SingleThreadedBlas() {
  if (before_ <= 1) return;
  if (const auto set = reinterpret_cast<SetThreads>(openblas_symbol("openblas_set_num_threads"))) set(before_);
}

}  // namespace hemivem
