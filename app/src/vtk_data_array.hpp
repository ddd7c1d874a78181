// The binary DataArray of VTK's XML files, as solution.vtu and contact-surface.vtu hold them
// (private to hemivem::app): zlib-compressed blocks of 32 KiB, base64-encoded inline, UInt64
// headers.
#pragma once

#include <algorithm>
#include <cstdint>
#include <ostream>
#include <string>
#include <type_traits>
#include <vector>

#include <zlib.h>

#include <hemivem/error.hpp>

namespace hemivem::app::detail {

/// RFC 4648 base64 of `n` bytes, padded.
inline std::string base64(const unsigned char* p, std::size_t n) {
  static constexpr char digits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((n + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 2 < n; i += 3) {
    const std::uint32_t w = (std::uint32_t{p[i]} << 16) | (std::uint32_t{p[i + 1]} << 8) | p[i + 2];
    for (int s = 18; s >= 0; s -= 6) out += digits[(w >> s) & 63];
  }
  if (i < n) {
    const std::uint32_t w = (std::uint32_t{p[i]} << 16) | (i + 1 < n ? std::uint32_t{p[i + 1]} << 8 : 0);
    out += digits[(w >> 18) & 63];
    out += digits[(w >> 12) & 63];
    out += i + 1 < n ? digits[(w >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

/// The VTK type name of T.
template <class T>
constexpr const char* vtk_type() {
  if constexpr (std::is_same_v<T, double>) return "Float64";
  else if constexpr (std::is_same_v<T, std::int64_t>) return "Int64";
  else if constexpr (std::is_same_v<T, std::int32_t>) return "Int32";
  else return "UInt8";
}

/// One DataArray: the values' bytes cut into blocks of 32 KiB, each compressed by zlib; the
/// header (block count, block size, size of a partial last block or 0, compressed sizes) and
/// the compressed blocks, each base64-encoded.
template <class T>
void data_array(std::ostream& os, const char* name, int components, const std::vector<T>& values) {
  constexpr std::size_t kBlock = 32768;
  const auto* bytes = reinterpret_cast<const unsigned char*>(values.data());
  const std::size_t size = values.size() * sizeof(T);
  const std::size_t blocks = (size + kBlock - 1) / kBlock;
  std::vector<std::uint64_t> header{blocks, kBlock, size % kBlock};
  std::vector<unsigned char> compressed;
  std::vector<unsigned char> chunk(compressBound(kBlock));
  for (std::size_t b = 0; b < blocks; ++b) {
    const std::size_t length = std::min(kBlock, size - b * kBlock);
    uLongf out = static_cast<uLongf>(chunk.size());
    if (compress2(chunk.data(), &out, bytes + b * kBlock, static_cast<uLong>(length), Z_BEST_SPEED) != Z_OK)
      throw InternalError("zlib could not compress a block of solution.vtu");
    header.push_back(out);
    compressed.insert(compressed.end(), chunk.begin(), chunk.begin() + static_cast<std::ptrdiff_t>(out));
  }
  os << "        <DataArray type=\"" << vtk_type<T>() << "\" Name=\"" << name << "\"";
  if (components > 1) os << " NumberOfComponents=\"" << components << "\"";
  os << " format=\"binary\">\n          "
     << base64(reinterpret_cast<const unsigned char*>(header.data()), header.size() * sizeof(std::uint64_t))
     << base64(compressed.data(), compressed.size()) << "\n        </DataArray>\n";
}

}  // namespace hemivem::app::detail
