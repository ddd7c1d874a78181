// A figure is drawn whatever the scene's title holds, and one that cannot be drawn is a warning
// on stderr and in result.json, never silence.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <sys/stat.h>

#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using hemivem::test::run_command;
using hemivem::test::run_hemivem;
using hemivem::test::scratch;
using hemivem::test::slurp;

bool is_png(const fs::path& p) { return fs::exists(p) && slurp(p).rfind("\x89PNG\r\n\x1a\n", 0) == 0; }

// Example 4.1 on a coarse mesh under a title with a line break, quotes and backslashes
fs::path scene_titled(const fs::path& dir) {
  fs::create_directories(dir);
  std::string text = slurp(hemivem::test::scenes_dir() / "paper-example-4.1.toml");
  const auto at = text.find("\ntitle = ");
  EXPECT_NE(at, std::string::npos);
  const auto end = text.find('\n', at + 1);
  text.replace(at, end - at, "\ntitle = \"first line\\nsecond \\\"quoted\\\" 'single' back\\\\slash\"");
  std::ofstream(dir / "titled.toml") << text;
  return dir / "titled.toml";
}

// the figures of Example 4.1, in the order README lists them
const std::vector<std::string> kFigures{"u_nu.png", "deformed.png", "error.png"};

TEST(FigureFailures, ATitleWithALineBreakQuotesAndBackslashesIsDrawn) {
  if (run_command("command -v gnuplot").code != 0) GTEST_SKIP() << "no gnuplot";
  const auto dir = scratch("figure_title");
  const auto out = dir / "out";
  const auto r = run_hemivem("solve " + scene_titled(dir).string() + " --n 4 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  for (const auto& f : kFigures) EXPECT_TRUE(is_png(out / f)) << f << "\n" << r.out;
  EXPECT_EQ(r.err.find("figure not drawn"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(slurp(out / "result.json"));
  for (const auto& f : kFigures)
    EXPECT_NE(std::find(j.at("files").begin(), j.at("files").end(), f), j.at("files").end()) << f;
  fs::remove_all(dir);
}

TEST(FigureFailures, AFailingGnuplotIsAWarningOnStderrAndInResultJson) {
  const auto dir = scratch("figure_fails");
  fs::create_directories(dir / "bin");
  const auto fake = dir / "bin" / "gnuplot";
  std::ofstream(fake) << "#!/bin/sh\necho 'broken on purpose' >&2\nexit 1\n";
  ::chmod(fake.c_str(), 0755);
  const auto out = dir / "out";
  const auto r = run_command("PATH=" + (dir / "bin").string() + ":\"$PATH\" " + std::string(HEMIVEM_BINARY) +
                             " solve --n 4 --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string expected =
      "figure not drawn: u_nu.png, deformed.png, error.png: gnuplot failed (exit status 1): broken on purpose";
  EXPECT_NE(r.err.find("hemivem: warning: " + expected + "\n"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(slurp(out / "result.json"));
  std::vector<std::string> figure_warnings;
  for (const auto& w : j.at("warnings"))
    if (w.get<std::string>().rfind("figure not drawn", 0) == 0) figure_warnings.push_back(w);
  ASSERT_EQ(figure_warnings.size(), 1u) << j.at("warnings").dump();
  EXPECT_EQ(figure_warnings[0], expected);
  for (const auto& f : kFigures) {
    EXPECT_FALSE(fs::exists(out / f)) << f;
    EXPECT_EQ(std::find(j.at("files").begin(), j.at("files").end(), f), j.at("files").end()) << f;
  }
  // --json prints the same warnings
  const auto again = run_command("PATH=" + (dir / "bin").string() + ":\"$PATH\" " + std::string(HEMIVEM_BINARY) +
                                 " solve --n 4 --json --out " + (dir / "out2").string());
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_EQ(nlohmann::json::parse(again.out).at("warnings"),
            nlohmann::json::parse(slurp(dir / "out2" / "result.json")).at("warnings"));
  fs::remove_all(dir);
}

}  // namespace
