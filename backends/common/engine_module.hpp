// Private helper of the factories (not installed): the engines built as a module loaded at run
// time (hemivem/mumps_mpi_plugin.hpp, hemivem/petsc_krylov_plugin.hpp), found, opened and read
// the same way by hemivem::linear and hemivem::krylov. Each factory opens its module once and
// never closes it (engines it created may outlive any scope).
#pragma once

#include <dlfcn.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

namespace hemivem::engine_module {

/// A module: what the messages call it and where it may be.
struct Location {
  const char* description;  // in messages: "the mumps-mpi module"
  const char* environment;  // the variable whose value, when set, is the only path tried
  const char* file_name;    // the module's file name
  const char* from_bindir;  // <libdir>/hemivem relative to <bindir>
  const char* build_tree;   // the module's path in the build tree
  const char* installed;    // the module's path in the install prefix chosen at configure time
  const void* anchor;       // the address of a function of the calling library (for dladdr)
};

/// Where the module may be, in this order:
///   1. the folder hemivem/ beside the file holding `anchor` (found with dladdr): for a shared
///      library, the installed layout, which the build tree reproduces;
///   2. <libdir>/hemivem relative to that file's folder taken as <bindir>: an installed program
///      holding a static library;
///   3. the path of the module in the build tree;
///   4. the path of the module in the install prefix chosen at configure time.
/// The environment variable `where.environment` replaces the list.
inline std::vector<std::string> candidates(const Location& where) {
  const char* env = std::getenv(where.environment);
  if (env && *env) return {env};
  std::vector<std::string> paths;
  Dl_info info{};
  if (dladdr(where.anchor, &info) != 0 && info.dli_fname && *info.dli_fname) {
    std::error_code ec;
    std::filesystem::path self = std::filesystem::weakly_canonical(info.dli_fname, ec);
    if (ec) self = std::filesystem::path(info.dli_fname).lexically_normal();
    paths.push_back((self.parent_path() / "hemivem" / where.file_name).string());
    paths.push_back((self.parent_path() / where.from_bindir / where.file_name).lexically_normal().string());
  }
  paths.emplace_back(where.build_tree);
  paths.emplace_back(where.installed);
  return paths;
}

/// A module opened, or why it could not be.
struct Module {
  const char* description = "";
  std::string path;
  void* handle = nullptr;
  std::string error;  // empty when handle is set

  /// The entry point `symbol` of the module; null, with the message in *message, when the
  /// module was not opened or has no such symbol.
  template <class Function>
  Function entry(const char* symbol, std::string* message) const {
    if (!handle) {
      *message = error;
      return nullptr;
    }
    const auto function = reinterpret_cast<Function>(dlsym(handle, symbol));
    if (!function) *message = std::string(description) + " " + path + " has no entry point " + symbol;
    return function;
  }
};

/// Whether the program's global scope (the program, the libraries it started with and those
/// opened RTLD_GLOBAL) defines a symbol that the modules' libraries define too: MPI's entry
/// points, which the sequential MUMPS brings as stand-ins, or MUMPS's own. The command links the
/// sequential MUMPS; a Python interpreter holds it only in the local scope of hemivem's module.
inline bool program_defines_module_symbols() {
  void* program = dlopen(nullptr, RTLD_NOW);
  if (!program) return true;
  bool defined = false;
  for (const char* symbol : {"MPI_Init", "dmumps_c"}) defined = defined || dlsym(program, symbol) != nullptr;
  dlclose(program);
  return defined;
}

/// The first of candidates(where) that is a file, opened with RTLD_NOW | RTLD_LOCAL; never
/// closed. Call it once. Where the program's global scope defines the module's libraries'
/// symbols (program_defines_module_symbols), RTLD_DEEPBIND makes the module and its libraries
/// bind to their own first. Elsewhere the module binds as any library does, so that it shares
/// the program's data: a Python interpreter holds its own copy of `environ`, which MPI's
/// libraries bound deep would not see (they would reach the C library's instead, and MPI_Init
/// grows the interpreter's array behind the C library's back).
inline Module open(const Location& where) {
  Module module;
  module.description = where.description;
  const std::vector<std::string> paths = candidates(where);
  for (const std::string& candidate : paths) {
    std::error_code ec;
    if (std::filesystem::is_regular_file(candidate, ec)) {
      module.path = candidate;
      break;
    }
  }
  if (module.path.empty()) {
    std::string tried;
    for (const std::string& candidate : paths) tried += (tried.empty() ? "" : ", ") + candidate;
    module.error = std::string("cannot find ") + where.description + " (looked for " + tried +
                   "; the environment variable " + where.environment + " sets its path)";
    return module;
  }
  const int deep = program_defines_module_symbols() ? RTLD_DEEPBIND : 0;
  module.handle = dlopen(module.path.c_str(), RTLD_NOW | RTLD_LOCAL | deep);
  if (!module.handle) {
    const char* why = dlerror();
    module.error =
        std::string("cannot load ") + where.description + " " + module.path + ": " + (why ? why : "unknown error");
  }
  return module;
}

}  // namespace hemivem::engine_module
