// The lines of the text mesh readers (hemivem/support/text_lines.hpp): a LineStream, which reads
// a stream a line at a time without holding its text, gives the lines, numbers and counts that
// split_lines gives of the whole text, from a stream that can go back and from one that cannot;
// a stream that fails is a read error.
#include <hemivem/error.hpp>
#include <hemivem/support/text_lines.hpp>

#include <gtest/gtest.h>

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

Lines split(const std::string& text, int* last) {
  std::vector<text::Line> lines;
  *last = text::split_lines(text, "t", lines);
  Lines out;
  for (const text::Line& l : lines) out.emplace_back(l.number, std::string(l.text));
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
    const Lines expected = split(text, &last);
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
    const Lines expected = split(text, &last);
    OneWay buffer(text);
    std::istream in(&buffer);
    EXPECT_EQ(streamed(in, &streamed_last, &total), expected) << text::quote(text);
    EXPECT_EQ(streamed_last, last);
  }
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
