#include "common.hpp"

#include <hemivem/error.hpp>
#include <hemivem/mesh_generators.hpp>
#include <hemivem/mesh_io.hpp>

#include <fstream>
#include <system_error>

namespace hemivem::cli {

void write_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
  namespace fs = std::filesystem;
  if (path.has_parent_path()) {
    std::error_code ec;
    fs::create_directories(path.parent_path(), ec);
    if (ec) throw InputError("cannot create folder: " + ec.message(), path.parent_path().string());
  }
  const fs::path tmp = path.string() + ".part";
  {
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) throw InputError("cannot open for writing", tmp.string());
    try {
      write(out);
    } catch (...) {
      out.close();
      fs::remove(tmp);
      throw;
    }
    out.flush();
    if (!out) {
      out.close();
      fs::remove(tmp);
      throw InputError("write failed", path.string());
    }
  }
  std::error_code ec;
  fs::rename(tmp, path, ec);
  if (ec) {
    fs::remove(tmp);
    throw InputError("cannot move the finished file into place: " + ec.message(), path.string());
  }
}

Mesh load_mesh(const std::string& spec, int n, const Rectangle& domain, std::uint64_t seed) {
  const std::filesystem::path p(spec);
  if (p.extension() == ".poly2d") return read_poly2d(p).mesh;
  return make_mesh(spec, n, domain, seed);
}

}  // namespace hemivem::cli
