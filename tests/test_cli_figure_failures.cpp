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

/// The command line that runs hemivem with the fake gnuplot of `dir`/bin first on PATH.
std::string with_failing_gnuplot(const fs::path& dir, const std::string& args) {
  fs::create_directories(dir / "bin");
  const auto fake = dir / "bin" / "gnuplot";
  std::ofstream(fake) << "#!/bin/sh\necho 'broken on purpose' >&2\nexit 1\n";
  ::chmod(fake.c_str(), 0755);
  return "PATH=" + (dir / "bin").string() + ":\"$PATH\" " + std::string(HEMIVEM_BINARY) + " " + args;
}

TEST(FigureFailures, AStudyWhoseFigureFailsWarnsOnStderrAndInStudyJson) {
  const auto dir = scratch("figure_fails_study");
  const auto out = dir / "out";
  const auto r = run_command(with_failing_gnuplot(dir, "study --n 2,4 --ref 8 --out " + out.string()));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string expected = "figure not drawn: study.png: gnuplot failed (exit status 1): broken on purpose";
  EXPECT_NE(r.err.find("hemivem: warning: " + expected + "\n"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(slurp(out / "study.json"));
  EXPECT_EQ(j.at("warnings"), nlohmann::json::array({expected}));
  EXPECT_EQ(j.at("files"), nlohmann::json::array({"study.csv", "study.json"}));
  EXPECT_FALSE(j.at("rows").empty()) << "the numbers are written all the same";
  EXPECT_FALSE(fs::exists(out / "study.png"));
  // --json prints what study.json holds
  const auto again = run_command(with_failing_gnuplot(dir, "study --n 2,4 --ref 8 --json --out " + (dir / "out2").string()));
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_EQ(nlohmann::json::parse(again.out).at("warnings"), nlohmann::json::array({expected}));
  EXPECT_NE(again.err.find("hemivem: warning: " + expected), std::string::npos) << again.err;
  fs::remove_all(dir);
}

TEST(FigureFailures, ABenchWhosePlotsFailWarnsOnStderrAndInBenchJson) {
  const auto dir = scratch("figure_fails_bench");
  const auto out = dir / "out";
  const auto r = run_command(with_failing_gnuplot(dir, "bench --n 4 --ref 8 --levels 1 -q --out " + out.string()));
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string expected =
      "figure not drawn: bench.png, bench-error.png: gnuplot failed (exit status 1): broken on purpose";
  EXPECT_NE(r.err.find("hemivem: warning: " + expected + "\n"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(slurp(out / "bench.json"));
  EXPECT_EQ(j.at("warnings"), nlohmann::json::array({expected}));
  EXPECT_TRUE(j.at("plot").is_null());
  EXPECT_TRUE(j.at("refinement").at("plot").is_null());
  EXPECT_FALSE(j.at("rows").empty()) << "the numbers are written all the same";
  EXPECT_TRUE(fs::exists(out / "bench.csv"));
  EXPECT_FALSE(fs::exists(out / "bench.png"));
  fs::remove_all(dir);
}

/// Whether `file` parses as XML whose root element is `root` (Python's xml.etree).
bool xml_with_root(const fs::path& file, const std::string& root) {
  const auto r = run_command("/usr/bin/python3 -c \"import sys, xml.etree.ElementTree as E; "
                             "print(E.parse(sys.argv[1]).getroot().tag.split('}')[-1])\" " + file.string());
  return r.code == 0 && r.out == root + "\n";
}

TEST(FigureFormats, SolveWritesEveryFigureInEveryFormatAsked) {
  if (run_command("command -v gnuplot").code != 0) GTEST_SKIP() << "no gnuplot";
  const auto dir = scratch("figure_formats");
  const auto out = dir / "out";
  const auto r = run_hemivem("solve --n 4 --figures png,pdf,svg --out " + out.string());
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(r.err.find("figure not drawn"), std::string::npos) << r.err;
  const auto j = nlohmann::json::parse(slurp(out / "result.json"));
  std::vector<std::string> files = j.at("files").get<std::vector<std::string>>();
  for (const std::string stem : {"u_nu", "deformed", "error"}) {
    EXPECT_TRUE(is_png(out / (stem + ".png"))) << stem;
    EXPECT_EQ(slurp(out / (stem + ".pdf")).rfind("%PDF-", 0), 0u) << stem;
    EXPECT_TRUE(xml_with_root(out / (stem + ".svg"), "svg")) << stem;
    for (const char* ext : {".png", ".pdf", ".svg"})
      EXPECT_NE(std::find(files.begin(), files.end(), stem + ext), files.end()) << stem << ext << " " << j.at("files");
  }
  // the resolved scene keeps the formats; a run with the default writes PNG alone and
  // removes the earlier run's PDF and SVG files
  EXPECT_NE(slurp(out / "scene.toml").find("figure_format = [\"png\", \"pdf\", \"svg\"]"), std::string::npos);
  const auto again = run_hemivem("solve --n 4 --out " + out.string());
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_TRUE(is_png(out / "u_nu.png"));
  EXPECT_FALSE(fs::exists(out / "u_nu.pdf"));
  EXPECT_FALSE(fs::exists(out / "deformed.svg"));
  // a scene asking for SVG alone
  const auto svg = run_hemivem("solve --n 4 --set 'output.figure_format=\"svg\"' --out " + (dir / "svg").string());
  ASSERT_EQ(svg.code, 0) << svg.err;
  EXPECT_TRUE(xml_with_root(dir / "svg" / "deformed.svg", "svg"));
  EXPECT_FALSE(fs::exists(dir / "svg" / "deformed.png"));
  fs::remove_all(dir);
}

TEST(FigureFormats, AnUnknownFormatIsRefusedNamingTheKey) {
  const auto dir = scratch("figure_format_unknown");
  const auto set = run_hemivem("solve --n 4 --set 'output.figure_format=[\"png\", \"jpg\"]' --out " + (dir / "a").string());
  EXPECT_EQ(set.code, 2);
  EXPECT_NE(set.err.find("output.figure_format"), std::string::npos) << set.err;
  EXPECT_NE(set.err.find("unknown figure format 'jpg'"), std::string::npos) << set.err;
  EXPECT_NE(set.err.find("(expected any of: png, pdf, svg)"), std::string::npos) << set.err;
  const auto flag = run_hemivem("solve --n 4 --figures png,tiff --out " + (dir / "b").string());
  EXPECT_EQ(flag.code, 2);
  EXPECT_NE(flag.err.find("--figures"), std::string::npos) << flag.err;
  EXPECT_NE(flag.err.find("unknown figure format 'tiff'"), std::string::npos) << flag.err;
  const auto none = run_hemivem("solve --n 4 --set 'output.figure_format=[]' --out " + (dir / "c").string());
  EXPECT_EQ(none.code, 2);
  EXPECT_NE(none.err.find("output.figure_format"), std::string::npos) << none.err;
  EXPECT_NE(none.err.find("needs at least one format"), std::string::npos) << none.err;
  EXPECT_FALSE(fs::exists(dir / "a"));
  EXPECT_FALSE(fs::exists(dir / "b"));
  fs::remove_all(dir);
}

TEST(FigureFormats, StudyAndBenchTakeTheFiguresFlag) {
  const auto dir = scratch("figure_format_study_bench");
  const auto study = run_hemivem("study --n 2,4 --ref 8 -q --figures svg --out " + (dir / "study").string());
  ASSERT_EQ(study.code, 0) << study.err;
  EXPECT_TRUE(fs::exists(dir / "study" / "study.svg"));
  EXPECT_FALSE(fs::exists(dir / "study" / "study.png"));
  const auto bench = run_hemivem("bench --n 4 --ref 8 --levels 1 -q --figures png,pdf --out " + (dir / "bench").string());
  ASSERT_EQ(bench.code, 0) << bench.err;
  EXPECT_TRUE(fs::exists(dir / "bench" / "bench.png"));
  EXPECT_EQ(slurp(dir / "bench" / "bench.pdf").substr(0, 5), "%PDF-");
  const auto bad = run_hemivem("study --n 2,4 --ref 8 -q --figures gif --out " + (dir / "bad").string());
  EXPECT_EQ(bad.code, 2);
  EXPECT_NE(bad.err.find("unknown figure format 'gif'"), std::string::npos) << bad.err;
  fs::remove_all(dir);
}

}  // namespace
