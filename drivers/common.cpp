#include "common.hpp"

#include <hemivem/atomic_file.hpp>
#include <hemivem/error.hpp>

#include <cmath>
#include <fstream>
#include <iomanip>
#include <sstream>
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

std::string sci(double v, int precision) {
  if (std::isnan(v)) return "-";
  std::ostringstream s;
  s << std::setprecision(precision) << std::scientific << v;
  return s.str();
}

std::string fixed(double v, int precision) {
  std::ostringstream s;
  s << std::setprecision(precision) << std::fixed << v;
  return s.str();
}

nlohmann::json number(double v) {
  if (!std::isfinite(v)) return nullptr;
  return v;
}

}  // namespace hemivem::cli
