// The hemivem command on hostile input (tests/data/hostile/MANIFEST.tsv): every row runs
// `hemivem ARGS` with a fresh, absent output folder and expects the exit code, a message
// fragment on stderr that names the file and line or the field, and no output at all.
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <fstream>
#include <ostream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

struct Row {
  std::string name;      ///< test name
  std::string args;      ///< command line; {data} is tests/data/hostile, {out} the output folder
  int code = -1;         ///< expected exit code
  std::string fragment;  ///< expected on stderr; {data} as in args
  int line = 0;          ///< line of the manifest
};

void PrintTo(const Row& r, std::ostream* os) { *os << r.name << " (MANIFEST.tsv line " << r.line << ")"; }

fs::path hostile_dir() { return hemivem::test::data_dir() / "hostile"; }

std::string expand(std::string s, const std::string& key, const std::string& value) {
  for (std::size_t at = s.find(key); at != std::string::npos; at = s.find(key, at + value.size()))
    s.replace(at, key.size(), value);
  return s;
}

std::vector<std::string> split_tabs(const std::string& line) {
  std::vector<std::string> cells;
  std::size_t start = 0;
  while (true) {
    const std::size_t tab = line.find('\t', start);
    cells.push_back(line.substr(start, tab - start));
    if (tab == std::string::npos) break;
    start = tab + 1;
  }
  return cells;
}

/// The manifest rows (a header line, then name, args, exit code, fragment; '#' lines are comments).
std::vector<Row> manifest() {
  std::vector<Row> rows;
  std::ifstream in(hostile_dir() / "MANIFEST.tsv");
  std::string line;
  int number = 0;
  bool header = true;
  while (std::getline(in, line)) {
    ++number;
    if (line.empty() || line[0] == '#') continue;
    if (header) {
      header = false;
      continue;
    }
    const auto cells = split_tabs(line);
    Row r;
    r.line = number;
    if (cells.size() != 4) {
      r.name = "malformed_manifest_line_" + std::to_string(number);
    } else {
      r.name = cells[0];
      r.args = cells[1];
      r.code = std::stoi(cells[2]);
      r.fragment = cells[3];
    }
    rows.push_back(r);
  }
  return rows;
}

class HostileInput : public testing::TestWithParam<Row> {};

TEST_P(HostileInput, FailsCleanlyWithItsMessageAndWritesNothing) {
  const Row& row = GetParam();
  ASSERT_FALSE(row.args.empty()) << "MANIFEST.tsv line " << row.line << " does not have 4 tab-separated cells";
  const fs::path out = hemivem::test::scratch("hostile-" + row.name);
  ASSERT_FALSE(fs::exists(out));
  const std::string args = expand(expand(row.args, "{data}", hostile_dir().string()), "{out}", out.string());
  const hemivem::test::CommandRun r = hemivem::test::run_hemivem(args);
  EXPECT_EQ(r.code, row.code) << "hemivem " << args << "\nstderr: " << r.err;
  const std::string fragment = expand(row.fragment, "{data}", hostile_dir().string());
  EXPECT_NE(r.err.find(fragment), std::string::npos) << "hemivem " << args << "\nexpected on stderr: " << fragment
                                                     << "\nstderr: " << r.err;
  EXPECT_TRUE(r.out.empty()) << r.out;
  EXPECT_TRUE(!fs::exists(out) || fs::is_empty(out)) << "outputs were left in " << out;
  fs::remove_all(out);
}

INSTANTIATE_TEST_SUITE_P(Manifest, HostileInput, testing::ValuesIn(manifest()),
                         [](const testing::TestParamInfo<Row>& info) {
                           std::string n = info.param.name;
                           for (char& c : n)
                             if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
                           return n;
                         });

TEST(HostileCorpus, HasAtLeastThirtyCasesAndEveryFileIsUsed) {
  const auto rows = manifest();
  EXPECT_GE(rows.size(), 30u);
  std::set<std::string> names;
  std::string all_args;
  for (const Row& r : rows) {
    EXPECT_TRUE(names.insert(r.name).second) << "duplicate name " << r.name;
    all_args += r.args + "\n";
  }
  // Every scene or mesh of the folder is named by a row, directly or by a scene of a row.
  std::string referenced = all_args;
  for (const auto& e : fs::directory_iterator(hostile_dir())) {
    const std::string file = e.path().filename().string();
    if (e.path().extension() == ".toml" && fs::is_regular_file(e.path()) && all_args.find("{data}/" + file) != std::string::npos) {
      std::ifstream in(e.path());
      std::stringstream s;
      s << in.rdbuf();
      referenced += s.str();
    }
  }
  for (const auto& e : fs::directory_iterator(hostile_dir())) {
    const std::string file = e.path().filename().string();
    if (file == "MANIFEST.tsv" || file == "README.md" || file == "fuzz") continue;
    EXPECT_NE(referenced.find(file), std::string::npos) << file << " is used by no row of MANIFEST.tsv";
  }
}

}  // namespace
