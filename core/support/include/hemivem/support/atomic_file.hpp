// Writing a file so that a failure never leaves a half-written one behind.
#pragma once

#include <filesystem>
#include <functional>
#include <iosfwd>
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

}  // namespace hemivem
