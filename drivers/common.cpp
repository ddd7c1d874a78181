#include "common.hpp"

#include <hemivem/atomic_file.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh_generators.hpp>
#include <hemivem/mesh_io.hpp>

#include <fstream>
#include <system_error>

namespace hemivem::cli {

void write_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
  if (path.has_parent_path()) {
    std::error_code ec;
    std::filesystem::create_directories(path.parent_path(), ec);
    if (ec) throw InputError("cannot create folder: " + ec.message(), path.parent_path().string());
  }
  write_file_atomically(path, write);
}

Mesh load_mesh(const std::string& spec, int n, const Rectangle& domain, std::uint64_t seed) {
  const std::filesystem::path p(spec);
  if (p.extension() == ".poly2d") return read_poly2d(p).mesh;
  return make_mesh(spec, n, domain, seed);
}

}  // namespace hemivem::cli
