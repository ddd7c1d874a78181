// The lines of the text mesh readers (hemivem/support/text_lines.hpp): a LineStream, which reads
// a stream a line at a time without holding its text, gives the lines, numbers, counts and
// comments of the whole text split at once (split_whole, below), from a stream that can go back
// and from one that cannot; a line put back is read again; a stream that fails is a read error.
#include <hemivem/error.hpp>
#include <hemivem/support/text_lines.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <sstream>
#include <stdexcept>
#include <streambuf>
#include <string>
#include <utility>
#include <vector>

namespace {

using namespace hemivem;

/// A stream buffer over a text that cannot seek (as a pipe), or that fails after `fail_after`
/// characters (as a device's read error).
class OneWay : public std::streambuf {
 public:
  explicit OneWay(std::string text, std::size_t fail_after = std::string::npos)
      : text_(std::move(text)), fail_after_(fail_after) {}

 protected:
  int_type underflow() override {
    if (at_ >= text_.size()) return traits_type::eof();
    if (at_ >= fail_after_) throw std::runtime_error("the device failed");
    current_ = text_[at_];
    setg(&current_, &current_, &current_ + 1);
    ++at_;
    return traits_type::to_int_type(current_);
  }

 private:
  std::string text_;
  std::size_t fail_after_, at_ = 0;
  char current_ = 0;
};

using Lines = std::vector<std::pair<int, std::string>>;

/// The whole text split at its '\n': each line numbered, blank ones skipped, the others trimmed
/// of " \t\r\v\f"; a line beginning with `comment` goes to `comments`, without it and one space.
/// `last` is the number of the last line (at least 1).
Lines split_whole(const std::string& text, int* last, char comment = 0, std::vector<std::string>* comments = nullptr) {
  Lines out;
  std::vector<std::string> pieces;
  std::string current;
  for (char c : text) {
    if (c == '\n') {
      pieces.push_back(current);
      current.clear();
    } else {
      current += c;
    }
  }
  if (!current.empty()) pieces.push_back(current);
  const std::string space = " \t\r\v\f";
  for (std::size_t k = 0; k < pieces.size(); ++k) {
    const std::string& p = pieces[k];
    const std::size_t first = p.find_first_not_of(space);
    if (first == std::string::npos) continue;
    std::string trimmed = p.substr(first, p.find_last_not_of(space) - first + 1);
    if (comment != 0 && trimmed[0] == comment) {
      trimmed.erase(0, trimmed.size() > 1 && trimmed[1] == ' ' ? 2 : 1);
      if (comments) comments->push_back(trimmed);
      continue;
    }
    out.emplace_back(static_cast<int>(k) + 1, trimmed);
  }
  *last = std::max(static_cast<int>(pieces.size()), 1);
  return out;
}

Lines streamed(std::istream& in, int* last, std::size_t* total) {
  text::LineStream stream(in, "t", "mesh");
  *last = stream.last_line();
  *total = stream.total();
  Lines out;
  text::Line line;
  while (stream.next(line)) {
    out.emplace_back(line.number, std::string(line.text));
    EXPECT_EQ(stream.remaining(), *total - out.size());
  }
  EXPECT_EQ(stream.remaining(), 0u);
  return out;
}

const std::vector<std::string>& texts() {
  static const std::vector<std::string> all = {
      "",
      "\n",
      "a",
      "a\n",
      "  a  \r\n\n\t\nb c\n   ",
      "\n\n$MeshFormat\r\n4.1 0 8\r\n$EndMeshFormat",
      std::string("x\0y\n\v\f\n z", 9),
      std::string(200000, 'q') + "\n" + std::string(70000, ' ') + "\nlast",
  };
  return all;
}

TEST(LineStream, GivesTheLinesSplitLinesGivesOfTheWholeText) {
  for (const std::string& text : texts()) {
    int last = 0, streamed_last = 0;
    std::size_t total = 0;
    const Lines expected = split_whole(text, &last);
    std::istringstream in(text);
    EXPECT_EQ(streamed(in, &streamed_last, &total), expected) << text::quote(text);
    EXPECT_EQ(streamed_last, last) << text::quote(text);
    EXPECT_EQ(total, expected.size()) << text::quote(text);
  }
}

TEST(LineStream, AStreamThatCannotGoBackIsReadIntoACopy) {
  for (const std::string& text : texts()) {
    int last = 0, streamed_last = 0;
    std::size_t total = 0;
    const Lines expected = split_whole(text, &last);
    OneWay buffer(text);
    std::istream in(&buffer);
    EXPECT_EQ(streamed(in, &streamed_last, &total), expected) << text::quote(text);
    EXPECT_EQ(streamed_last, last);
  }
}

TEST(LineStream, GivesTheCommentsSplitLinesGivesAsItMeetsThem) {
  const std::string text = "# a .poly2d file\n  #indented  \nvertices 3\n#\n#  two spaces\r\n 0 0\n# last";
  std::vector<std::string> comments;
  int last = 0;
  const Lines lines = split_whole(text, &last, '#', &comments);
  std::istringstream in(text);
  std::vector<std::string> streamed_comments;
  text::LineStream stream(in, "t", "mesh", '#', &streamed_comments);
  EXPECT_EQ(stream.total(), lines.size());
  EXPECT_EQ(stream.last_line(), last);
  text::Line line;
  for (const auto& [number, expected] : lines) {
    ASSERT_TRUE(stream.next(line));
    EXPECT_EQ(line.number, number);
    EXPECT_EQ(line.text, expected);
  }
  EXPECT_FALSE(stream.next(line));
  EXPECT_EQ(streamed_comments, comments);
  EXPECT_EQ(comments, (std::vector<std::string>{"a .poly2d file", "indented", "", " two spaces", "last"}));
}

TEST(LineStream, ALinePutBackIsReadAgain) {
  std::istringstream in("one\n\ntwo\n");
  text::LineStream stream(in, "t", "mesh");
  text::Line line;
  EXPECT_THROW(stream.put_back(), InternalError);  // none read yet
  ASSERT_TRUE(stream.next(line));
  EXPECT_EQ(stream.remaining(), 1u);
  stream.put_back();
  EXPECT_THROW(stream.put_back(), InternalError);  // twice
  EXPECT_EQ(stream.remaining(), 2u);
  ASSERT_TRUE(stream.next(line));
  EXPECT_EQ(line.number, 1);
  EXPECT_EQ(line.text, "one");
  ASSERT_TRUE(stream.next(line));
  EXPECT_EQ(line.number, 3);
  EXPECT_EQ(line.text, "two");
  EXPECT_FALSE(stream.next(line));
  EXPECT_EQ(stream.remaining(), 0u);
}

TEST(LineStream, AStreamThatFailsIsAReadError) {
  OneWay buffer("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n", 20);
  std::istream in(&buffer);
  try {
    text::LineStream stream(in, "broken.msh", "mesh");
    FAIL() << "a failing stream was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("read error while reading the mesh"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("broken.msh"), std::string::npos) << e.what();
  }
}

}  // namespace
