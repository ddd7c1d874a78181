// The arrays of the VTU files hemivem writes (binary, zlib-compressed, UInt64 headers), decoded:
// what the tests of the VTU outputs read back. Tests that include it link ZLIB::ZLIB.
#pragma once

#include <gtest/gtest.h>
#include <zlib.h>

#include <cctype>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace hemivem::test {

/// The content of a DataArray (base64 of its blocks' header, then of its compressed blocks),
/// uncompressed.
inline std::vector<unsigned char> decode_vtu_array(const std::string& content) {
  std::string text;
  for (char c : content)
    if (!std::isspace(static_cast<unsigned char>(c))) text += c;
  const auto head = from_base64(text.substr(0, 32));  // 24 bytes: 3 UInt64
  std::uint64_t h[3];
  std::memcpy(h, head.data(), sizeof h);
  const std::size_t header_chars = (8 * (3 + h[0]) + 2) / 3 * 4;
  const auto header = from_base64(text.substr(0, header_chars));
  const auto data = from_base64(text.substr(header_chars));
  std::vector<unsigned char> out;
  std::size_t offset = 0;
  for (std::uint64_t b = 0; b < h[0]; ++b) {
    std::uint64_t compressed = 0;
    std::memcpy(&compressed, header.data() + 8 * (3 + b), 8);
    uLongf size = static_cast<uLongf>(b + 1 == h[0] && h[2] != 0 ? h[2] : h[1]);
    std::vector<unsigned char> block(size);
    EXPECT_EQ(uncompress(block.data(), &size, data.data() + offset, static_cast<uLong>(compressed)), Z_OK);
    out.insert(out.end(), block.begin(), block.begin() + static_cast<std::ptrdiff_t>(size));
    offset += compressed;
  }
  return out;
}

}  // namespace hemivem::test
