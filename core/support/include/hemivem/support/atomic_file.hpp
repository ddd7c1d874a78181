// Writing a file so that a failure never leaves a half-written one behind.
#pragma once

#include <filesystem>
#include <functional>
#include <iosfwd>
#include <cstddef>
#include <string>

#include <hemivem/error.hpp>

namespace hemivem {

/// A file that could not be written (a full disk, a read-only folder, a failed rename).
class WriteError : public InputError {
 public:
  using InputError::InputError;
};

/// Writes `path` through `write`: the contents are made in memory, written into a hidden
/// temporary next to `path` (unique per process and call) with every write checked, flushed
/// to the disk (fsync), and renamed into place. On any failure — the file cannot be created,
/// a write is short (a full disk), the flush or the rename fails — the temporary is removed
/// and a WriteError naming `path` is thrown (an exception from `write` is rethrown as is);
/// `path` is then as it was. The parent folder must exist.
void write_file_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

/// A file written in pieces and never held whole in memory (a loading path's files, which grow
/// with its steps). The constructor creates (or empties) `path`; write() makes a piece in memory
/// and appends it, the bytes going to the disk by blocks of a few megabytes with every write
/// checked; close() writes the rest and flushes the file to the disk (fsync). A failure is a
/// WriteError naming `path`, and the file is then closed and incomplete: write it inside a
/// folder that is discarded when it fails (OutputTransaction::staging), never over a file of
/// value. Counted as one file by the test hook HEMIVEM_TEST_FAIL_WRITE.
class FileInPieces {
 public:
  explicit FileInPieces(std::filesystem::path path);
  ~FileInPieces();
  FileInPieces(const FileInPieces&) = delete;
  FileInPieces& operator=(const FileInPieces&) = delete;

  void write(const std::function<void(std::ostream&)>& piece);
  void close();
  /// Bytes written so far (sent to the disk or waiting in memory).
  std::size_t size() const noexcept { return written_ + buffer_.size(); }

 private:
  static constexpr std::size_t kFlushBytes = std::size_t{4} << 20;
  void flush();
  std::string name_;
  std::string buffer_;
  std::size_t written_ = 0;
  int fd_ = -1;
  bool fail_ = false;  ///< HEMIVEM_TEST_FAIL_WRITE names this file
};

}  // namespace hemivem
