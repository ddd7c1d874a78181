// Values and arrays written one after another as bytes, and read back in the same order: what
// one process sends another (RowDistribution::send_to), on machines of one byte order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include <hemivem/error.hpp>

namespace hemivem {

/// Appends to `out`.
class ByteWriter {
 public:
  explicit ByteWriter(std::vector<char>& out) : out_(out) {}
  template <class T>
  void value(const T& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    append(&v, sizeof v);
  }
  /// Its length, then its values.
  template <class T>
  void array(const std::vector<T>& v) {
    static_assert(std::is_trivially_copyable_v<T>);
    value(static_cast<std::uint64_t>(v.size()));
    append(v.data(), v.size() * sizeof(T));
  }
  /// Fixed-size Eigen vectors (Vec2, Vec3: their doubles one after another, nothing between):
  /// their count, then their doubles.
  template <class Point>
  void points(const std::vector<Point>& v) {
    static_assert(sizeof(Point) == sizeof(double) * Point::SizeAtCompileTime);
    value(static_cast<std::uint64_t>(v.size()));
    append(v.data(), v.size() * sizeof(Point));
  }
  void text(const std::string& s) {
    value(static_cast<std::uint64_t>(s.size()));
    append(s.data(), s.size());
  }

 private:
  void append(const void* data, std::size_t bytes) {
    const auto* p = static_cast<const char*>(data);
    out_.insert(out_.end(), p, p + bytes);
  }
  std::vector<char>& out_;
};

/// Reads what a ByteWriter wrote, in its order. InternalError for bytes that end too soon.
class ByteReader {
 public:
  explicit ByteReader(std::span<const char> in) : in_(in) {}
  template <class T>
  T value() {
    static_assert(std::is_trivially_copyable_v<T>);
    T v;
    take(&v, sizeof v);
    return v;
  }
  template <class T>
  std::vector<T> array() {
    static_assert(std::is_trivially_copyable_v<T>);
    std::vector<T> v(count(sizeof(T)));
    take(v.data(), v.size() * sizeof(T));
    return v;
  }
  /// What points() wrote.
  template <class Point>
  std::vector<Point> points() {
    static_assert(sizeof(Point) == sizeof(double) * Point::SizeAtCompileTime);
    std::vector<Point> v(count(sizeof(Point)));
    take(v.data(), v.size() * sizeof(Point));
    return v;
  }
  std::string text() {
    std::string s(count(1), '\0');
    take(s.data(), s.size());
    return s;
  }
  /// Whether every byte was read.
  bool done() const { return at_ == in_.size(); }

 private:
  /// A length that the bytes left can hold, of values of `size` bytes each.
  std::size_t count(std::size_t size) {
    const auto n = value<std::uint64_t>();
    if (size > 0 && n > (in_.size() - at_) / size) fail();
    return static_cast<std::size_t>(n);
  }
  void take(void* data, std::size_t bytes) {
    if (bytes > in_.size() - at_) fail();
    if (bytes > 0) std::memcpy(data, in_.data() + at_, bytes);
    at_ += bytes;
  }
  [[noreturn]] void fail() const {
    throw InternalError("bytes of " + std::to_string(in_.size()) + " that end before what they hold");
  }
  std::span<const char> in_;
  std::size_t at_ = 0;
};

}  // namespace hemivem
