// Line splitting, tokenizing and number parsing shared by the text mesh readers (.poly2d, Gmsh).
#pragma once

#include <hemivem/error.hpp>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <istream>
#include <sstream>
#include <string>
#include <string_view>
#include <system_error>
#include <vector>

namespace hemivem::text {

/// Throws InputError (where: the path) unless `path` names a regular file (after following
/// symbolic links): a folder, a device, a pipe or a socket is refused before it is opened, so
/// a reader never blocks on a pipe or reads /dev/zero without end. A path that does not exist
/// passes (opening it reports that). `what` is e.g. "mesh file".
inline void require_regular_file(const std::filesystem::path& path, const std::string& what) {
  namespace fs = std::filesystem;
  std::error_code ec;
  const fs::file_status st = fs::status(path, ec);
  if (ec || st.type() == fs::file_type::not_found || st.type() == fs::file_type::regular) return;
  if (st.type() == fs::file_type::directory)
    throw InputError("cannot read the " + what + ": it is a directory", path.string());
  throw InputError("cannot read the " + what + ": it is not a regular file (a device, a pipe or a socket)", path.string());
}

/// `path` opened for reading as bytes, after require_regular_file; InputError (at the path)
/// with the system's reason when it cannot be opened. `what` is e.g. "mesh file".
inline std::ifstream open_for_reading(const std::filesystem::path& path, const std::string& what) {
  require_regular_file(path, what);
  errno = 0;
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    const int err = errno;
    throw InputError("cannot open the " + what + (err != 0 ? ": " + std::system_category().message(err) : std::string()),
                     path.string());
  }
  return in;
}

/// Everything `in` holds; InputError (at `name`) when reading fails ("read error while reading
/// the <what>").
inline std::string read_all(std::istream& in, const std::string& name, const std::string& what) {
  std::string data;
  char chunk[1 << 16];
  while (in.read(chunk, sizeof chunk) || in.gcount() > 0) data.append(chunk, static_cast<std::size_t>(in.gcount()));
  if (in.bad()) throw InputError("read error while reading the " + what, name);
  return data;
}

/// A token or line for an error message: at most 48 characters, control and non-ASCII
/// bytes shown as \xNN.
inline std::string shown(std::string_view s) {
  constexpr std::size_t limit = 48;
  std::string out;
  for (std::size_t i = 0; i < s.size() && i < limit; ++i) {
    const auto c = static_cast<unsigned char>(s[i]);
    if (c >= 0x20 && c < 0x7f) {
      out += static_cast<char>(c);
    } else {
      char buf[8];
      std::snprintf(buf, sizeof buf, "\\x%02X", c);
      out += buf;
    }
  }
  if (s.size() > limit) out += "...";
  return out;
}

/// `s` in single quotes, as shown() shows it.
inline std::string quote(std::string_view s) {
  std::string out(1, '\'');
  out += shown(s);
  out += '\'';
  return out;
}

inline constexpr std::string_view kWhitespace = " \t\r\v\f";

struct Line {
  int number = 0;         ///< 1-based line number in the file
  std::string_view text;  ///< without leading/trailing whitespace (and without '\r')
};

/// The non-blank lines of a stream, trimmed of whitespace (kWhitespace) and numbered from 1 by
/// the '\n' that ends each, blank ones counted; given `comment`, a line that begins with it is a
/// comment, which goes to `comments` as it is met (without it and one following space). Read one
/// at a time without holding the stream's text: a line's text is valid until the next call of next(). The stream
/// is read through once on construction, counting its lines (remaining(), last_line()), then
/// again from where it stood; a stream that cannot go back is read into a copy held here.
/// InputError (at `name`) when reading fails ("read error while reading the <what>") or the
/// stream has more than INT_MAX lines.
class LineStream {
 public:
  LineStream(std::istream& in, std::string name, std::string what, char comment = 0,
             std::vector<std::string>* comments = nullptr)
      : in_(&in), name_(std::move(name)), what_(std::move(what)), comment_(comment), comments_(comments) {
    const std::istream::pos_type start = in.tellg();
    if (start == std::istream::pos_type(-1)) {  // not seekable: a copy
      copy_.str(read_all(in, name_, what_));
      in_ = &copy_;
    }
    const std::istream::pos_type from = in_->tellg();
    char chunk[1 << 16];
    long long number = 0;
    bool open = false, blank = true, data = false;  // a line begun, only whitespace in it so far, not a comment
    const auto close = [&] {
      if (number == INT_MAX) throw InputError("the file has too many lines", name_ + ":" + std::to_string(number));
      ++number;
      if (data) ++total_;
      open = false, blank = true, data = false;
    };
    while (in_->read(chunk, sizeof chunk) || in_->gcount() > 0) {
      const std::string_view read(chunk, static_cast<std::size_t>(in_->gcount()));
      for (std::size_t i = 0; i < read.size();) {
        if (read[i] == '\n') {
          close();
          ++i;
          continue;
        }
        open = true;
        if (blank && kWhitespace.find(read[i]) == std::string_view::npos) blank = false, data = comment_ == 0 || read[i] != comment_;
        // a line known not blank: on to its end
        i = blank ? i + 1 : std::min(read.find('\n', i), read.size());
      }
    }
    if (in_->bad()) throw InputError("read error while reading the " + what_, name_);
    if (open) close();
    last_line_ = std::max(static_cast<int>(number), 1);
    in_->clear();
    in_->seekg(from);
    if (!*in_) throw InputError("read error while reading the " + what_, name_);
  }
  LineStream(const LineStream&) = delete;
  LineStream& operator=(const LineStream&) = delete;

  /// The next non-blank line that is no comment; false at the end of the stream.
  bool next(Line& line) {
    if (put_back_) {
      put_back_ = false;
      line = last_;
      ++returned_;
      return true;
    }
    while (std::getline(*in_, buffer_)) {
      ++number_;
      std::string_view text = buffer_;
      const std::size_t first = text.find_first_not_of(kWhitespace);
      if (first == std::string_view::npos) continue;
      text = text.substr(first, text.find_last_not_of(kWhitespace) - first + 1);
      if (comment_ != 0 && text.front() == comment_) {
        text.remove_prefix(1);
        if (!text.empty() && text.front() == ' ') text.remove_prefix(1);
        if (comments_) comments_->emplace_back(text);
        continue;
      }
      line = last_ = {number_, text};
      ++returned_;
      return true;
    }
    if (in_->bad()) throw InputError("read error while reading the " + what_, name_);
    return false;
  }
  /// The line next() returned last is returned again by the next call.
  void put_back() {
    if (put_back_ || returned_ == 0) throw InternalError("a line put back twice, or before one was read");
    put_back_ = true;
    --returned_;
  }
  /// The number of non-blank lines that are no comments, and of those next() has not returned yet.
  std::size_t total() const noexcept { return total_; }
  std::size_t remaining() const noexcept { return total_ - std::min(returned_, total_); }
  /// The number of the stream's last line (at least 1), blank or not.
  int last_line() const noexcept { return last_line_; }

 private:
  std::istream* in_;
  std::istringstream copy_;
  std::string name_, what_, buffer_;
  char comment_;
  std::vector<std::string>* comments_;
  Line last_;
  bool put_back_ = false;
  int number_ = 0, last_line_ = 1;
  std::size_t total_ = 0, returned_ = 0;
};

/// The whitespace-separated tokens of `text` (replacing the contents of `tokens`).
inline void tokenize(std::string_view text, std::vector<std::string_view>& tokens) {
  tokens.clear();
  std::size_t i = 0;
  while (true) {
    i = text.find_first_not_of(kWhitespace, i);
    if (i == std::string_view::npos) break;
    std::size_t j = text.find_first_of(kWhitespace, i);
    if (j == std::string_view::npos) j = text.size();
    tokens.push_back(text.substr(i, j - i));
    i = j;
  }
}

/// Skips one leading '+' when a digit (or '.' for reals) follows: from_chars rejects it.
inline std::string_view strip_plus(std::string_view t, bool real) {
  if (t.size() >= 2 && t[0] == '+' && ((t[1] >= '0' && t[1] <= '9') || (real && t[1] == '.'))) t.remove_prefix(1);
  return t;
}

enum class Parse { ok, bad, out_of_range };

/// The whole token must be an integer (one leading '+' allowed).
inline Parse parse_integer(std::string_view token, long long& value) {
  const std::string_view t = strip_plus(token, false);
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  if (ec == std::errc::invalid_argument || ptr != t.data() + t.size()) return Parse::bad;
  if (ec == std::errc::result_out_of_range) return Parse::out_of_range;
  return Parse::ok;
}

/// The whole token must be a real number (nan and inf are parsed; the caller rejects them).
/// A value too small for a double reads as the nearest double (0 or a subnormal);
/// one too large is out_of_range.
inline Parse parse_real(std::string_view token, double& value) {
  const std::string_view t = strip_plus(token, true);
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), value, std::chars_format::general);
  if (ec == std::errc::invalid_argument || ptr != t.data() + t.size()) return Parse::bad;
  if (ec == std::errc::result_out_of_range) {
    // from_chars does not say whether it overflowed or underflowed; strtod does.
    const std::string copy(t);
    errno = 0;
    const double v = std::strtod(copy.c_str(), nullptr);
    if (std::isinf(v)) return Parse::out_of_range;
    value = v;
  }
  return Parse::ok;
}

}  // namespace hemivem::text
