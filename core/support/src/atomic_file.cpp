#include <hemivem/support/atomic_file.hpp>
#include <hemivem/error.hpp>

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstdlib>
#include <cstring>
#include <sstream>
#include <string>
#include <thread>

namespace hemivem {

namespace {

std::atomic<unsigned> files_written{0};
std::atomic<pid_t> counting_process{0};  // the process files_written counts for

/// The number of this file among those this process wrote (1 for the first): a forked child
/// starts its own count rather than going on with its parent's.
unsigned next_file_number() {
  const pid_t self = ::getpid();
  if (counting_process.exchange(self) != self) files_written = 0;
  return files_written.fetch_add(1) + 1;
}

/// The test hooks (docs/reference/testing.md): HEMIVEM_TEST_FAIL_WRITE=N makes the N-th file
/// this process writes fail as on a full disk, after half of its bytes; HEMIVEM_TEST_WRITE_DELAY
/// = seconds sleeps before each written file is moved into place.
bool injected_failure(unsigned call) {
  const char* n = std::getenv("HEMIVEM_TEST_FAIL_WRITE");
  return n != nullptr && std::strtoul(n, nullptr, 10) == call;
}

void injected_delay() {
  const char* s = std::getenv("HEMIVEM_TEST_WRITE_DELAY");
  if (s == nullptr) return;
  const double seconds = std::strtod(s, nullptr);
  if (seconds > 0) std::this_thread::sleep_for(std::chrono::duration<double>(seconds));
}

std::string failure(const char* what, int err) { return std::string(what) + ": " + std::strerror(err); }

/// Writes `size` bytes of `data` to `fd`; closes it and throws WriteError when a write fails.
void write_bytes(int fd, const char* data, std::size_t size, const std::string& name) {
  std::size_t done = 0;
  while (done < size) {
    const ssize_t n = ::write(fd, data + done, size - done);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) {
      const int err = n < 0 ? errno : ENOSPC;
      ::close(fd);
      throw WriteError(failure("writing the file failed", err), name);
    }
    done += static_cast<std::size_t>(n);
  }
}

/// Flushes `fd` to the disk and closes it; throws WriteError.
void sync_and_close(int fd, const std::string& name) {
  if (::fsync(fd) != 0 && errno != EINVAL && errno != EROFS) {
    const int err = errno;
    ::close(fd);
    throw WriteError(failure("writing the file to the disk failed", err), name);
  }
  if (::close(fd) != 0) throw WriteError(failure("closing the written file failed", errno), name);
}

/// Writes all of `data` to `fd`, flushes it to the disk and closes it; throws WriteError (after
/// half of the bytes when `fail`, as on a full disk).
void write_all(int fd, const std::string& data, const std::string& name, bool fail) {
  write_bytes(fd, data.data(), fail ? data.size() / 2 : data.size(), name);
  if (fail) {
    ::close(fd);
    throw WriteError(failure("writing the file failed", ENOSPC), name);
  }
  sync_and_close(fd, name);
}

}  // namespace

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
  std::ostringstream text;
  write(text);
  if (!text) throw WriteError("making the file's contents failed", name);
  const unsigned call = next_file_number();
  try {
    const int fd = ::open(tmp.c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
    if (fd < 0) throw WriteError(failure("cannot create the file", errno), name);
    write_all(fd, text.str(), name, injected_failure(call));
    injected_delay();
    std::error_code ec;
    fs::rename(tmp, path, ec);
    if (ec) throw WriteError("cannot move the written file into place: " + ec.message(), name);
  } catch (...) {
    std::error_code ec;
    fs::remove(tmp, ec);
    throw;
  }
}

FileInPieces::FileInPieces(std::filesystem::path path) : name_(path.string()) {
  if (path.filename().empty()) throw InputError("the path names no file", name_);
  fail_ = injected_failure(next_file_number());
  fd_ = ::open(path.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0666);
  if (fd_ < 0) throw WriteError(failure("cannot create the file", errno), name_);
}

FileInPieces::~FileInPieces() {
  if (fd_ >= 0) ::close(fd_);
}

void FileInPieces::write(const std::function<void(std::ostream&)>& piece) {
  if (fd_ < 0) throw WriteError("the file was closed or failed before", name_);
  std::ostringstream text;
  piece(text);
  if (!text) throw WriteError("making the file's contents failed", name_);
  buffer_ += text.str();
  if (buffer_.size() >= kFlushBytes) flush();
}

void FileInPieces::flush() {
  const int fd = fd_;
  fd_ = -1;  // write_bytes closes it when it fails
  if (fail_) {
    write_bytes(fd, buffer_.data(), buffer_.size() / 2, name_);
    ::close(fd);
    throw WriteError(failure("writing the file failed", ENOSPC), name_);
  }
  write_bytes(fd, buffer_.data(), buffer_.size(), name_);
  fd_ = fd;
  written_ += buffer_.size();
  buffer_.clear();
}

void FileInPieces::close() {
  if (fd_ < 0) throw WriteError("the file was closed or failed before", name_);
  flush();
  const int fd = fd_;
  fd_ = -1;
  sync_and_close(fd, name_);
}

}  // namespace hemivem
