#include <hemivem/support/output_folder.hpp>
#include <hemivem/support/atomic_file.hpp>
#include <hemivem/error.hpp>

#include <fcntl.h>
#include <signal.h>

#include <csignal>
#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <set>
#include <system_error>

namespace hemivem {

namespace fs = std::filesystem;

namespace {

const char* const kManifest = ".hemivem-manifest";

/// `.DIR.hemivem-` for the folder `dir` (built by appending: GCC 12 warns wrongly on "." + s).
std::string hidden_prefix(const fs::path& dir) {
  std::string prefix(1, '.');
  return prefix.append(dir.filename().string()).append(".hemivem-");
}

/// The name `.DIR.hemivem-KIND.PID` beside `dir`.
fs::path beside(const fs::path& dir, const std::string& kind, long pid) {
  return dir.parent_path() / hidden_prefix(dir).append(kind).append(".").append(std::to_string(pid));
}

fs::path lock_file(const fs::path& dir) { return dir.parent_path() / hidden_prefix(dir).append("lock"); }

bool running(long pid) { return pid > 0 && (::kill(static_cast<pid_t>(pid), 0) == 0 || errno == EPERM); }

/// Takes the lock file beside `dir`; -1 when another process holds it.
int take_lock(const fs::path& dir) {
  const fs::path lock = lock_file(dir);
  for (int attempt = 0; attempt < 100; ++attempt) {
    const int fd = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
    if (fd < 0) throw WriteError("cannot create the lock file: " + std::string(std::strerror(errno)), lock.string());
    if (::flock(fd, LOCK_EX | LOCK_NB) != 0) {
      const int err = errno;
      ::close(fd);
      if (err == EWOULDBLOCK) return -1;
      throw WriteError("cannot lock the output folder: " + std::string(std::strerror(err)), lock.string());
    }
    // the holder before us may have removed the file after we opened it: lock the file in place
    struct stat held {}, named {};
    if (::fstat(fd, &held) == 0 && ::stat(lock.c_str(), &named) == 0 && held.st_ino == named.st_ino &&
        held.st_dev == named.st_dev)
      return fd;
    ::close(fd);
  }
  throw WriteError("cannot lock the output folder", lock.string());
}

void remove_all_quietly(const fs::path& p) {
  std::error_code ec;
  fs::remove_all(p, ec);
}

/// Moves the complete set in `ready` into `dir` following its manifest ("put NAME" moves the
/// staged file in, "drop NAME" removes the previous one). Repeatable: a run killed halfway is
/// finished by running it again.
void move_in(const fs::path& ready, const fs::path& dir) {
  std::error_code ec;
  if (!fs::exists(fs::symlink_status(dir, ec))) {
    fs::rename(ready, dir, ec);
    if (ec) throw WriteError("cannot move the new outputs into place: " + ec.message(), dir.string());
    fs::remove(dir / kManifest, ec);
    return;
  }
  std::ifstream manifest(ready / kManifest);
  std::vector<std::string> put;
  for (std::string kind, name; manifest >> kind >> name;) {
    if (kind == "drop") fs::remove(dir / name, ec);
    if (kind == "put") put.push_back(name);
  }
  for (const auto& name : put) {
    if (!fs::exists(ready / name, ec)) continue;  // moved already
    fs::rename(ready / name, dir / name, ec);
    if (ec) throw WriteError("cannot move the new file into place: " + ec.message(), (dir / name).string());
  }
  remove_all_quietly(ready);
}

/// Whether `dir` is a folder holding nothing but files named in `owned`.
bool only_owned(const fs::path& dir, const std::vector<std::string>& owned) {
  std::error_code ec;
  if (!fs::is_directory(fs::symlink_status(dir, ec))) return false;
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (std::find(owned.begin(), owned.end(), name) == owned.end() || !entry.is_regular_file(ec)) return false;
  }
  return !ec;
}

/// The process id in `.NAME.tmp.PID.N` (write_file_atomically's temporary) for NAME in
/// `owned`; 0 for any other name.
long temporary_of(const std::string& file, const std::vector<std::string>& owned) {
  for (const auto& name : owned) {
    std::string prefix(1, '.');
    prefix.append(name).append(".tmp.");
    if (file.rfind(prefix, 0) != 0) continue;
    const std::string rest = file.substr(prefix.size());
    const auto dot = rest.find('.');
    const bool digits = dot != std::string::npos && dot > 0 && dot + 1 < rest.size() &&
                        rest.find_first_not_of("0123456789.") == std::string::npos;
    return digits ? std::strtol(rest.c_str(), nullptr, 10) : 0;
  }
  return 0;
}

/// Finishes or removes what runs that no longer run left beside `dir`, and the temporaries
/// of files of the `owned` names inside it.
void recover(const fs::path& dir, const std::vector<std::string>& owned) {
  const std::string prefix = hidden_prefix(dir);
  std::error_code ec;
  std::vector<std::pair<std::string, long>> left;
  for (const auto& entry : fs::directory_iterator(dir.parent_path(), ec)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(prefix, 0) != 0) continue;
    const std::string rest = name.substr(prefix.size());
    const auto dot = rest.find('.');
    if (dot == std::string::npos) continue;
    const long pid = std::strtol(rest.c_str() + dot + 1, nullptr, 10);
    if (pid == ::getpid() || running(pid)) continue;
    left.emplace_back(rest.substr(0, dot), pid);
  }
  for (const auto& [kind, pid] : left) {  // a complete set (with its manifest) first
    const fs::path ready = beside(dir, "ready", pid);
    if (kind == "ready" && fs::exists(ready / kManifest, ec)) move_in(ready, dir);
  }
  for (const auto& [kind, pid] : left) remove_all_quietly(beside(dir, kind, pid));
  fs::remove(dir / kManifest, ec);
  // single files of the owned names an older hemivem was writing when it was killed
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const long pid = temporary_of(entry.path().filename().string(), owned);
    std::error_code rm;
    if (pid > 0 && pid != ::getpid() && !running(pid)) fs::remove(entry.path(), rm);
  }
}

/// Holds SIGINT and SIGTERM back in this thread while alive.
class SignalsHeld {
 public:
  SignalsHeld() {
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT);
    sigaddset(&set, SIGTERM);
    ::pthread_sigmask(SIG_BLOCK, &set, &old_);
  }
  ~SignalsHeld() { ::pthread_sigmask(SIG_SETMASK, &old_, nullptr); }
  SignalsHeld(const SignalsHeld&) = delete;
  SignalsHeld& operator=(const SignalsHeld&) = delete;

 private:
  sigset_t old_{};
};

volatile std::sig_atomic_t committed_count = 0;

}  // namespace

int committed_transactions() noexcept { return committed_count; }

std::string previous_outputs_kept(const fs::path& dir) {
  std::error_code ec;
  return fs::exists(dir, ec) ? dir.string() + " keeps its previous outputs"
                             : "no outputs were written to " + dir.string();
}

OutputTransaction::OutputTransaction(fs::path dir, std::vector<std::string> owned)
    : shown_(dir), owned_(std::move(owned)) {
  std::error_code ec;
  dir_ = fs::absolute(dir, ec).lexically_normal();
  if (dir_.filename().empty()) dir_ = dir_.parent_path();
  if (dir_.filename().empty() || dir_ == dir_.root_path())
    throw InputError("cannot write outputs into the root folder", dir.string());
  const fs::file_status st = fs::status(dir_, ec);
  if (fs::exists(st) && !fs::is_directory(st)) throw InputError("the output folder is a file, not a folder", dir.string());
  fs::create_directories(dir_.parent_path(), ec);
  if (ec) throw WriteError("cannot create the folder: " + ec.message(), dir_.parent_path().string());
  lock_fd_ = take_lock(dir_);
  if (lock_fd_ < 0) throw InputError("another hemivem run is writing " + dir.string());
  try {
    recover(dir_, owned_);
    staging_ = beside(dir_, "new", ::getpid());
    remove_all_quietly(staging_);
    fs::create_directory(staging_, ec);
    if (ec) throw WriteError("cannot create a folder beside the output folder: " + ec.message(), staging_.string());
  } catch (...) {
    ::close(lock_fd_);
    throw;
  }
}

OutputTransaction::~OutputTransaction() {
  if (!committed_) remove_all_quietly(staging_);
  ::unlink(lock_file(dir_).c_str());  // while still held: a waiting opener rechecks the file (take_lock)
  ::close(lock_fd_);
}

void OutputTransaction::write(const std::string& name, const std::function<void(std::ostream&)>& body) {
  stage([&](const fs::path& staging) { write_file_atomically(staging / name, body); });
}

void OutputTransaction::stage(const std::function<void(const fs::path&)>& writes) {
  try {
    writes(staging_);
  } catch (const WriteError& e) {
    throw WriteError(e.detail() + "; " + previous_outputs_kept(shown_),
                     (shown_ / fs::path(e.where()).filename()).string());
  }
}

std::vector<std::string> OutputTransaction::commit() {
  std::error_code ec;
  std::vector<std::string> put, removed;
  for (const auto& entry : fs::directory_iterator(staging_, ec)) put.push_back(entry.path().filename().string());
  std::sort(put.begin(), put.end());
  for (const auto& name : put) {  // a name taken by a folder (or anything but a file) cannot be replaced
    const fs::file_status st = fs::symlink_status(dir_ / name, ec);
    if (fs::exists(st) && !fs::is_regular_file(st))
      throw WriteError("cannot replace it: it is not a file; " + previous_outputs_kept(shown_),
                       (shown_ / name).string());
  }
  for (const auto& name : owned_)
    if (!std::binary_search(put.begin(), put.end(), name) && fs::is_regular_file(fs::symlink_status(dir_ / name, ec)))
      removed.push_back(name);
  write(kManifest, [&](std::ostream& os) {
    for (const auto& n : put) os << "put " << n << "\n";
    for (const auto& n : removed) os << "drop " << n << "\n";
  });
  const SignalsHeld held;
  const fs::path ready = beside(dir_, "ready", ::getpid());
  fs::rename(staging_, ready, ec);
  if (ec) throw WriteError("cannot move the new outputs into place: " + ec.message() + "; " + previous_outputs_kept(shown_),
                                shown_.string());
  committed_ = true;
  committed_count = committed_count + 1;  // signals are held: no handler reads it meanwhile
  if (only_owned(dir_, owned_) &&
      ::renameat2(AT_FDCWD, ready.c_str(), AT_FDCWD, dir_.c_str(), RENAME_EXCHANGE) == 0) {
    fs::remove(dir_ / kManifest, ec);  // the folders swapped at once: `ready` holds the previous set
    remove_all_quietly(ready);
    return removed;
  }
  move_in(ready, dir_);
  return removed;
}

}  // namespace hemivem
