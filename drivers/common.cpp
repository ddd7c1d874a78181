#include "common.hpp"

#include <hemivem/atomic_file.hpp>
#include <hemivem/error.hpp>

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

}  // namespace hemivem::cli
