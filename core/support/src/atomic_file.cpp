#include <hemivem/support/atomic_file.hpp>
#include <hemivem/error.hpp>

#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <fstream>

namespace hemivem {

void write_file_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write) {
  namespace fs = std::filesystem;
  const std::string name = path.string();
  if (path.filename().empty()) throw InputError("the path names no file", name);
  static std::atomic<unsigned> counter{0};
  std::string tmp_name(1, '.');
  tmp_name.append(path.filename().string())
      .append(".tmp.")
      .append(std::to_string(::getpid()))
      .append(".")
      .append(std::to_string(counter.fetch_add(1)));
  const fs::path tmp = path.parent_path() / tmp_name;
  try {
    errno = 0;
    std::ofstream out(tmp, std::ios::binary | std::ios::trunc);
    if (!out) {
      const int err = errno;
      throw InputError(std::string("cannot create the file") + (err != 0 ? std::string(": ") + std::strerror(err) : ""), name);
    }
    write(out);
    out.close();
    if (!out) throw InputError("writing the file failed (disk full?)", name);
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) throw InputError("cannot move the written file into place: " + ec.message(), name);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

}  // namespace hemivem
