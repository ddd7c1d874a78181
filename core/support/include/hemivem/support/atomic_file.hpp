// Writing a file so that a failure never leaves a half-written one behind.
#pragma once

#include <filesystem>
#include <functional>
#include <iosfwd>

namespace hemivem {

/// Writes `path` through `write` into a hidden temporary next to it (unique per process and
/// call) and renames it into place on success. On any failure — the stream cannot be opened,
/// `write` throws, the data cannot be flushed, the rename fails — the temporary is removed and
/// an InputError naming `path` is thrown (an exception from `write` is rethrown as is).
/// The parent folder must exist.
void write_file_atomically(const std::filesystem::path& path, const std::function<void(std::ostream&)>& write);

}  // namespace hemivem
