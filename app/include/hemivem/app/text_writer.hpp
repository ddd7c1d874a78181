// Large text tables written fast: numbers by std::to_chars through a buffer.
#pragma once

#include <charconv>
#include <cmath>
#include <cstddef>
#include <ostream>
#include <string>
#include <string_view>

namespace hemivem::app {

/// Text for large tables, written through a buffer: each number as the shortest text that
/// reads back as exactly the same double (std::to_chars).
class TextWriter {
 public:
  explicit TextWriter(std::ostream& os) : os_(os) { buffer_.reserve(kFlush + 64); }
  TextWriter(const TextWriter&) = delete;
  TextWriter& operator=(const TextWriter&) = delete;
  ~TextWriter() { flush(); }

  TextWriter& operator<<(double x) {
    if (!std::isfinite(x)) return *this << (std::isnan(x) ? "nan" : x > 0 ? "inf" : "-inf");
    char text[32];
    const auto r = std::to_chars(text, text + sizeof text, x);
    return append(std::string_view(text, static_cast<std::size_t>(r.ptr - text)));
  }
  TextWriter& operator<<(long long k) {
    char text[24];
    const auto r = std::to_chars(text, text + sizeof text, k);
    return append(std::string_view(text, static_cast<std::size_t>(r.ptr - text)));
  }
  TextWriter& operator<<(int k) { return *this << static_cast<long long>(k); }
  TextWriter& operator<<(char c) { return append(std::string_view(&c, 1)); }
  TextWriter& operator<<(std::string_view text) { return append(text); }
  TextWriter& operator<<(const char* text) { return append(std::string_view(text)); }
  TextWriter& operator<<(const std::string& text) { return append(text); }

  void flush() {
    os_.write(buffer_.data(), static_cast<std::streamsize>(buffer_.size()));
    buffer_.clear();
  }

 private:
  static constexpr std::size_t kFlush = std::size_t{1} << 20;
  TextWriter& append(std::string_view text) {
    buffer_.append(text);
    if (buffer_.size() >= kFlush) flush();
    return *this;
  }
  std::ostream& os_;
  std::string buffer_;
};

}  // namespace hemivem::app
