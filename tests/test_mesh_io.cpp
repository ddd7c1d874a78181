// Reading and writing .poly2d meshes: round trips, the shared meshes against the table
// of shared/meshes/README.md, and a corpus of malformed files (tests/data/malformed).
#include <hemivem/mesh/poly2d.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <bit>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <new>
#include <numbers>
#include <set>
#include <sstream>
#include <string>

#include <unistd.h>

#include "test_support.hpp"

// ---- allocation probe ----------------------------------------------------------------
// The global operator new of this test program records the largest single request while
// a probe is armed, so "an absurd count must not allocate" is checked, not assumed.
namespace {
std::atomic<bool> g_probe_armed{false};
std::atomic<std::size_t> g_largest_request{0};
}  // namespace

void* operator new(std::size_t size) {
  if (g_probe_armed.load(std::memory_order_relaxed)) {
    std::size_t seen = g_largest_request.load(std::memory_order_relaxed);
    while (size > seen && !g_largest_request.compare_exchange_weak(seen, size)) {
    }
  }
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }

namespace {

namespace fs = std::filesystem;
using hemivem::InputError;
using hemivem::Mesh;
using hemivem::MeshError;
using hemivem::Poly2dMesh;
using hemivem::Vec2;

/// While alive, records the largest single allocation request.
class AllocationProbe {
 public:
  AllocationProbe() {
    g_largest_request = 0;
    g_probe_armed = true;
  }
  ~AllocationProbe() { g_probe_armed = false; }
  AllocationProbe(const AllocationProbe&) = delete;
  AllocationProbe& operator=(const AllocationProbe&) = delete;
  std::size_t largest() const { return g_largest_request.load(); }
};

std::uint64_t bits(double x) { return std::bit_cast<std::uint64_t>(x); }

/// Bitwise equality of the vertices and equality of the elements of two meshes.
::testing::AssertionResult same_mesh(const Mesh& a, const Mesh& b) {
  if (a.num_vertices() != b.num_vertices())
    return ::testing::AssertionFailure() << "vertex counts " << a.num_vertices() << " vs " << b.num_vertices();
  for (int i = 0; i < a.num_vertices(); ++i) {
    for (int c = 0; c < 2; ++c) {
      if (bits(a.vertex(i)[c]) != bits(b.vertex(i)[c]))
        return ::testing::AssertionFailure() << "vertex " << i << " coordinate " << c << " differs: "
                                             << a.vertex(i)[c] << " vs " << b.vertex(i)[c];
    }
  }
  if (a.elements() != b.elements()) return ::testing::AssertionFailure() << "elements differ";
  return ::testing::AssertionSuccess();
}

/// A fresh empty folder for one test, removed afterwards.
class TempDir {
 public:
  TempDir() {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    std::string name = std::string("hemivem-mesh-io-") + info->test_suite_name() + "-" + info->name() + "-" +
                       std::to_string(::getpid());
    std::replace(name.begin(), name.end(), '/', '_');
    path_ = fs::temp_directory_path() / name;
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~TempDir() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  const fs::path& path() const { return path_; }
  std::vector<std::string> entries() const {
    std::vector<std::string> out;
    for (const auto& e : fs::directory_iterator(path_)) out.push_back(e.path().filename().string());
    std::sort(out.begin(), out.end());
    return out;
  }

 private:
  fs::path path_;
};

/// Three elements (two quadrilaterals and a triangle) with coordinates that have no
/// short decimal form, so a lossy writer would be caught.
Mesh awkward_mesh() {
  const std::vector<Vec2> base{{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}, {1.5, 1.75}};
  std::vector<Vec2> v;
  for (const auto& p : base) v.push_back(p / 3.0 + Vec2(0.1, std::numbers::pi * 1e-7));
  v[2].x() = std::nextafter(v[2].x(), 10.0);
  v[6].y() = std::nextafter(v[6].y(), -10.0);
  return Mesh(v, {{0, 1, 4, 3}, {1, 2, 5, 4}, {4, 5, 6}});
}

Poly2dMesh read_string(const std::string& text, const std::string& name = "memory") {
  std::istringstream in(text);
  return hemivem::read_poly2d(in, name);
}

/// The error message of reading `text`, or "" when it reads.
std::string read_error(const std::string& text) {
  try {
    read_string(text);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

// ---- round trips ---------------------------------------------------------------------

TEST(Poly2dRoundTrip, StreamKeepsVerticesBitwiseAndElements) {
  const Mesh m = awkward_mesh();
  std::ostringstream out;
  hemivem::write_poly2d(out, m, {"awkward mesh", "second line"});
  const Poly2dMesh back = read_string(out.str());
  EXPECT_TRUE(same_mesh(m, back.mesh));
  EXPECT_EQ(back.boundary_list, m.boundary_vertices());
  EXPECT_EQ(back.comments, (std::vector<std::string>{"awkward mesh", "second line"}));
}

TEST(Poly2dRoundTrip, FileKeepsVerticesBitwiseAndLeavesNoTemporary) {
  TempDir dir;
  const fs::path file = dir.path() / "awkward.poly2d";
  const Mesh m = awkward_mesh();
  hemivem::write_poly2d(file, m, {"first"});
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"awkward.poly2d"});
  const Poly2dMesh back = hemivem::read_poly2d(file);
  EXPECT_TRUE(same_mesh(m, back.mesh));
  EXPECT_EQ(back.comments, std::vector<std::string>{"first"});

  // Overwriting an existing file replaces it.
  const Mesh squares({{0, 0}, {1, 0}, {2, 0}, {0, 1}, {1, 1}, {2, 1}}, {{0, 1, 4, 3}, {1, 2, 5, 4}});
  hemivem::write_poly2d(file, squares);
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"awkward.poly2d"});
  EXPECT_TRUE(same_mesh(squares, hemivem::read_poly2d(file).mesh));
}

TEST(Poly2dRoundTrip, MultiLineCommentsBecomeCommentLines) {
  std::ostringstream out;
  hemivem::write_poly2d(out, awkward_mesh(), {"a\nb", "", "trailing   "});
  EXPECT_EQ(out.str().rfind("# a\n# b\n#\n# trailing\nvertices 7\n", 0), 0u) << out.str();
  EXPECT_EQ(read_string(out.str()).comments, (std::vector<std::string>{"a", "b", "", "trailing"}));
}

TEST(Poly2dRoundTrip, SharedMeshesKeepVerticesBitwise) {
  const auto files = hemivem::test::shared_meshes();
  if (files.empty()) GTEST_SKIP() << "shared/meshes not found (looked in " << HEMIVEM_SHARED_DIR << ")";
  for (const auto& f : files) {
    SCOPED_TRACE(f.string());
    const Poly2dMesh in = hemivem::read_poly2d(f);
    std::ostringstream out;
    hemivem::write_poly2d(out, in.mesh, in.comments);
    const Poly2dMesh back = read_string(out.str());
    EXPECT_TRUE(same_mesh(in.mesh, back.mesh));
    EXPECT_EQ(back.comments, in.comments);
  }
}

// ---- writing failures ----------------------------------------------------------------

TEST(Poly2dWrite, FailureNamesThePathAndLeavesNoFile) {
  TempDir dir;
  // The target is a folder: the temporary is written, the rename fails, the temporary goes.
  const fs::path folder = dir.path() / "taken.poly2d";
  fs::create_directory(folder);
  try {
    hemivem::write_poly2d(folder, awkward_mesh());
    ADD_FAILURE() << "expected InputError";
  } catch (const MeshError&) {
    ADD_FAILURE() << "a write failure is not a mesh defect";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(folder.string()), std::string::npos) << e.what();
    EXPECT_EQ(e.where(), folder.string());
  }
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"taken.poly2d"});

  // The folder does not exist.
  const fs::path nowhere = dir.path() / "no-such-folder" / "mesh.poly2d";
  try {
    hemivem::write_poly2d(nowhere, awkward_mesh());
    ADD_FAILURE() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(nowhere.string()), std::string::npos) << e.what();
  }
  EXPECT_EQ(dir.entries(), std::vector<std::string>{"taken.poly2d"});
}

TEST(Poly2dWrite, FailedStreamAndEmptyMeshAreErrors) {
  std::ostringstream broken;
  broken.setstate(std::ios::badbit);
  EXPECT_THROW(hemivem::write_poly2d(broken, awkward_mesh()), InputError);
  std::ostringstream out;
  EXPECT_THROW(hemivem::write_poly2d(out, Mesh()), InputError);
}

// ---- reading ---------------------------------------------------------------------------

TEST(Poly2dRead, MissingFileNamesThePath) {
  TempDir dir;
  const fs::path missing = dir.path() / "no-such-mesh.poly2d";
  try {
    hemivem::read_poly2d(missing);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(missing.string()), std::string::npos) << e.what();
    EXPECT_EQ(e.where(), missing.string());
  }
  try {
    hemivem::read_poly2d(dir.path());
    FAIL() << "expected InputError for a folder";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(dir.path().string()), std::string::npos) << e.what();
  }
}

TEST(Poly2dRead, ToleratesCrlfTrailingWhitespaceCommentsAndBlankLines) {
  const std::string text =
      "# title \r\n"
      "\r\n"
      "vertices 4   \r\n"
      "  0 0\t\r\n"
      "1e0 +0\r\n"
      "# a comment inside the list\r\n"
      "1.0 1\r\n"
      "\t.0 1E+00 \r\n"
      "\r\n"
      "elements 1\r\n"
      "4 0 1 2 3\r\n"
      "boundary 4\r\n"
      "0\r\n1\r\n2\r\n+3\r\n"
      "   \r\n";
  const Poly2dMesh p = read_string(text);
  ASSERT_EQ(p.mesh.num_vertices(), 4);
  EXPECT_EQ(p.mesh.vertex(1), Vec2(1, 0));
  EXPECT_EQ(p.mesh.vertex(3), Vec2(0, 1));
  EXPECT_EQ(p.mesh.elements(), (std::vector<std::vector<int>>{{0, 1, 2, 3}}));
  EXPECT_EQ(p.boundary_list, (std::vector<int>{0, 1, 2, 3}));
  EXPECT_EQ(p.comments, (std::vector<std::string>{"title", "a comment inside the list"}));
  EXPECT_DOUBLE_EQ(p.mesh.total_area(), 1.0);
}

TEST(Poly2dRead, BoundarySectionIsOptionalAndNotCheckedAgainstTheMesh) {
  const std::string base = "vertices 3\n0 0\n1 0\n0 1\nelements 1\n3 0 1 2\n";
  EXPECT_TRUE(read_string(base).boundary_list.empty());
  // Sutton's lists are not always exact: an in-range list is kept as written.
  EXPECT_EQ(read_string(base + "boundary 2\n2\n2\n").boundary_list, (std::vector<int>{2, 2}));
}

TEST(Poly2dRead, MessagesUseTheStreamNameAndLine) {
  try {
    read_string("vertices 3\n0 0\n1 0\n0 1\nelements 1\n3 0 2 1\n", "inline-mesh");
    FAIL() << "expected MeshError";
  } catch (const MeshError& e) {
    EXPECT_EQ(e.where(), "inline-mesh:6");
    EXPECT_EQ(e.element(), 0);
    EXPECT_EQ(std::string(e.what()).rfind("inline-mesh:6: element 0 is clockwise", 0), 0u) << e.what();
  }
}

TEST(Poly2dRead, NumbersMustBeWholeTokens) {
  const std::string head = "vertices 3\n0 0\n1 0\n";
  const std::string tail = "elements 1\n3 0 1 2\n";
  EXPECT_EQ(read_error(head + "0 1\n" + tail), "");
  EXPECT_NE(read_error(head + "0 1.5x\n" + tail).find("memory:4: vertex 2 has a y coordinate '1.5x'"),
            std::string::npos);
  EXPECT_NE(read_error(head + "0 0x1\n" + tail).find("memory:4:"), std::string::npos);
  EXPECT_NE(read_error(head + "0 1e\n" + tail).find("memory:4:"), std::string::npos);
  EXPECT_NE(read_error(head + "0 --1\n" + tail).find("memory:4:"), std::string::npos);
  EXPECT_NE(read_error(head + "0 +-1\n" + tail).find("memory:4:"), std::string::npos);
  EXPECT_NE(read_error(head + "0 infinity\n" + tail).find("not finite"), std::string::npos);
  EXPECT_NE(read_error(head + "0 -nan\n" + tail).find("not finite"), std::string::npos);
  EXPECT_NE(read_error(head + "0 1\n" + "elements 1\n3 0 1 2x\n").find("memory:6: element 0 has a bad vertex index '2x'"),
            std::string::npos);
  EXPECT_NE(read_error(head + "0 1\n" + "elements 1\n3 0 1 99999999999999999999\n").find("out of range"),
            std::string::npos);
  // A value below the smallest subnormal reads as 0 (here it makes the triangle flat).
  EXPECT_NE(read_error(head + "0 1e-400\n" + tail).find("zero area"), std::string::npos);
}

TEST(Poly2dRead, HugeCountsDoNotAllocate) {
  const std::string text = "vertices 2147483647\n0 0\n1 0\n0 1\n";
  std::string message;
  std::size_t largest = 0;
  {
    AllocationProbe probe;
    message = read_error(text);
    largest = probe.largest();
  }
  EXPECT_NE(message.find("memory:4: expected 2147483647 vertex lines"), std::string::npos) << message;
  EXPECT_LT(largest, std::size_t{1} << 20);
}

// ---- the shared meshes ------------------------------------------------------------------

namespace {

/// One row of the table in shared/meshes/README.md, plus the domain area.
struct SharedRow {
  const char* file;
  int nv, ne, kmin, kmax, non_convex;
  const char* h;         // as printed
  const char* min_edge;  // as printed
  int nb;
  bool list_ok;
  double domain_area;
};

const SharedRow kSharedTable[] = {
    {"sutton-squares.poly2d", 289, 256, 4, 4, 0, "0.0883883", "0.0625", 64, true, 1.0},
    {"sutton-triangles.poly2d", 225, 392, 3, 3, 0, "0.101015", "0.0714", 56, true, 1.0},
    {"sutton-voronoi.poly2d", 870, 400, 3, 10, 0, "0.112591", "2.84e-13", 145, false, 1.0},
    {"sutton-smoothed-voronoi.poly2d", 869, 400, 4, 8, 0, "0.0793764", "1.12e-13", 146, true, 1.0},
    {"sutton-non-convex.poly2d", 1281, 400, 8, 8, 399, "0.0728869", "0.0177", 160, true, 1.0},
    {"sutton-L-domain.poly2d", 239, 100, 4, 8, 1, "0.309893", "2.16e-13", 78, true, 3.0},
    {"sutton-voronoi-merged.poly2d", 802, 400, 3, 10, 0, "0.112591", "1.87e-05", 76, true, 1.0},
    {"sutton-smoothed-voronoi-merged.poly2d", 802, 400, 4, 8, 0, "0.0793764", "5.04e-04", 79, true, 1.0},
    {"sutton-L-domain-merged.poly2d", 204, 100, 4, 7, 1, "0.309893", "2.11e-03", 43, true, 3.0},
};

/// Significant digits of a printed number ("0.0625" -> 3, "5.04e-04" -> 3).
int significant_digits(const std::string& printed) {
  const std::string mantissa = printed.substr(0, printed.find_first_of("eE"));
  int digits = 0;
  bool leading = true;
  for (char c : mantissa) {
    if (c < '0' || c > '9') continue;
    if (leading && c == '0') continue;
    leading = false;
    ++digits;
  }
  return digits;
}

/// `value` rounded to as many significant digits as `printed` shows equals `printed`.
::testing::AssertionResult matches_printed(double value, const std::string& printed) {
  const int digits = significant_digits(printed);
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.*e", digits - 1, value);
  if (std::stod(buf) == std::stod(printed)) return ::testing::AssertionSuccess();
  return ::testing::AssertionFailure() << "computed " << buf << " (from " << value << "), README says " << printed;
}

/// An interior angle above 180 degrees: a clockwise turn at some vertex. Turns whose
/// sine is within 1e-12 of zero are straight (180-degree) vertices, not re-entrant ones.
bool is_non_convex(const Mesh& m, int e) {
  const auto vs = m.element(e);
  const std::size_t k = vs.size();
  for (std::size_t i = 0; i < k; ++i) {
    const Vec2 a = m.vertex(vs[i]) - m.vertex(vs[(i + k - 1) % k]);
    const Vec2 b = m.vertex(vs[(i + 1) % k]) - m.vertex(vs[i]);
    if (a.x() * b.y() - a.y() * b.x() < -1e-12 * a.norm() * b.norm()) return true;
  }
  return false;
}

int count_non_convex(const Mesh& m) {
  int count = 0;
  for (int e = 0; e < m.num_elements(); ++e) count += is_non_convex(m, e) ? 1 : 0;
  return count;
}

fs::path shared_mesh(const std::string& name) { return hemivem::test::shared_dir() / "meshes" / name; }

}  // namespace

TEST(SharedMeshes, ReadAndMatchTheReadmeTable) {
  const auto files = hemivem::test::shared_meshes();
  if (files.empty()) GTEST_SKIP() << "shared/meshes not found (looked in " << HEMIVEM_SHARED_DIR << ")";
  std::set<std::string> present;
  for (const auto& f : files) present.insert(f.filename().string());
  for (const auto& row : kSharedTable) EXPECT_TRUE(present.count(row.file)) << row.file << " is missing";

  for (const auto& f : files) {
    SCOPED_TRACE(f.string());
    Poly2dMesh p;
    ASSERT_NO_THROW(p = hemivem::read_poly2d(f));
    const auto row = std::find_if(std::begin(kSharedTable), std::end(kSharedTable),
                                  [&](const SharedRow& r) { return f.filename() == r.file; });
    if (row == std::end(kSharedTable)) continue;  // a mesh the table does not describe: reading is all we check
    const Mesh& m = p.mesh;
    EXPECT_EQ(m.num_vertices(), row->nv);
    EXPECT_EQ(m.num_elements(), row->ne);
    int kmin = m.element_size(0), kmax = kmin;
    for (int e = 0; e < m.num_elements(); ++e) {
      kmin = std::min(kmin, m.element_size(e));
      kmax = std::max(kmax, m.element_size(e));
    }
    EXPECT_EQ(kmin, row->kmin);
    EXPECT_EQ(kmax, row->kmax);
    EXPECT_EQ(count_non_convex(m), row->non_convex);
    EXPECT_TRUE(matches_printed(m.h(), row->h));
    EXPECT_TRUE(matches_printed(m.min_edge_length(), row->min_edge));
    EXPECT_EQ(static_cast<int>(p.boundary_list.size()), row->nb);
    std::vector<int> listed = p.boundary_list;
    std::sort(listed.begin(), listed.end());
    EXPECT_EQ(listed == m.boundary_vertices(), row->list_ok);
    double area = 0.0;
    for (int e = 0; e < m.num_elements(); ++e) area += m.area(e);
    EXPECT_NEAR(area, row->domain_area, 1e-9);
    EXPECT_FALSE(p.comments.empty());
  }
}

TEST(SharedMeshes, VoronoiBoundaryListHasTheInteriorVertex388) {
  if (hemivem::test::shared_meshes().empty()) GTEST_SKIP() << "shared/meshes not found";
  const Poly2dMesh p = hemivem::read_poly2d(shared_mesh("sutton-voronoi.poly2d"));
  const std::vector<int> from_edges = p.mesh.boundary_vertices();
  EXPECT_EQ(from_edges.size(), 144u);
  EXPECT_EQ(p.boundary_list.size(), 145u);
  std::vector<int> listed = p.boundary_list;
  std::sort(listed.begin(), listed.end());
  std::vector<int> extra;
  std::set_difference(listed.begin(), listed.end(), from_edges.begin(), from_edges.end(), std::back_inserter(extra));
  EXPECT_EQ(extra, std::vector<int>{388});
  EXPECT_TRUE(std::includes(listed.begin(), listed.end(), from_edges.begin(), from_edges.end()));
  // 388 belongs to elements 105, 113 and 175.
  std::vector<int> owners;
  for (int e = 0; e < p.mesh.num_elements(); ++e) {
    const auto vs = p.mesh.element(e);
    if (std::find(vs.begin(), vs.end(), 388) != vs.end()) owners.push_back(e);
  }
  EXPECT_EQ(owners, (std::vector<int>{105, 113, 175}));
}

TEST(SharedMeshes, NonConvexMeshHas399NonConvexElements) {
  if (hemivem::test::shared_meshes().empty()) GTEST_SKIP() << "shared/meshes not found";
  const Mesh m = hemivem::read_poly2d(shared_mesh("sutton-non-convex.poly2d")).mesh;
  EXPECT_EQ(count_non_convex(m), 399);
  // Only element 0, the lower-left cell, is convex.
  EXPECT_FALSE(is_non_convex(m, 0));
  for (int e = 1; e < m.num_elements(); ++e) EXPECT_TRUE(is_non_convex(m, e)) << "element " << e;
  // The same count on a hand-made L: one re-entrant corner, and a square with a
  // 180-degree vertex that must not count.
  const Mesh l_and_square({{0, 0}, {2, 0}, {2, 1}, {1, 1}, {1, 2}, {0, 2}, {3, 0}, {3, 1}, {2.5, 0}},
                          {{0, 1, 2, 3, 4, 5}, {1, 8, 6, 7, 2}});
  EXPECT_TRUE(is_non_convex(l_and_square, 0));
  EXPECT_FALSE(is_non_convex(l_and_square, 1));
}

// ---- the malformed corpus ----------------------------------------------------------------

namespace {

using hemivem::test::Malformed;
using Kind = hemivem::test::MalformedKind;

// Keep in step with tests/data/malformed/README.md (checked below).
const Malformed kMalformed[] = {
    {"empty-file.poly2d", 1, "the file holds no data: expected the header 'vertices NV'", Kind::input},
    {"missing-vertices-header.poly2d", 2, "expected the header 'vertices NV', found '0 0'", Kind::input},
    {"header-without-count.poly2d", 2, "the header 'vertices NV' has no count", Kind::input},
    {"header-extra-content.poly2d", 2, "has extra content after the count", Kind::input},
    {"bad-count-token.poly2d", 2, "bad vertex count '6x'", Kind::input},
    {"negative-count.poly2d", 9, "element count -2 is negative", Kind::input},
    {"absurd-count.poly2d", 2, "vertex count 999999999999 is too large", Kind::input},
    {"count-exceeds-file.poly2d", 8, "expected 2000000000 vertex lines after 'vertices 2000000000' (line 2), but the file ends after 6", Kind::input},
    {"truncated-vertex-list.poly2d", 9, "expected 8 vertex lines after 'vertices 8' (line 2), but the list ends after 6", Kind::input},
    {"truncated-element-list.poly2d", 11, "expected 3 element lines after 'elements 3' (line 9), but the file ends after 2", Kind::input},
    {"missing-elements-header.poly2d", 8, "the file ends before the header 'elements NE'", Kind::input},
    {"non-numeric-coordinate.poly2d", 7, "vertex 4 has a y coordinate 'one' that is not a number", Kind::input},
    {"partial-number.poly2d", 5, "vertex 2 has an x coordinate '1.5x' that is not a number", Kind::input},
    {"nan-coordinate.poly2d", 6, "vertex 3 has an x coordinate 'nan' that is not finite", Kind::input},
    {"inf-coordinate.poly2d", 8, "vertex 5 has a y coordinate '-inf' that is not finite", Kind::input},
    {"overflow-coordinate.poly2d", 4, "vertex 1 has an x coordinate '1e400' outside the range of double", Kind::input},
    {"vertex-extra-value.poly2d", 4, "vertex 1 has 3 values", Kind::input},
    {"element-too-few-vertices.poly2d", 11, "element 1 has 2 vertices; an element needs at least 3", Kind::mesh, 1},
    {"element-missing-index.poly2d", 10, "element 0 declares 4 vertices but lists 3 indices", Kind::input},
    {"element-extra-index.poly2d", 11, "element 1 declares 4 vertices but lists 5 indices", Kind::input},
    {"element-absurd-vertex-count.poly2d", 11, "element 1 declares 1000000000 vertices but lists 3 indices", Kind::input},
    {"element-non-integer-index.poly2d", 10, "element 0 has a bad vertex index '1.0'", Kind::input},
    {"index-out-of-range.poly2d", 11, "element 1 has vertex index 6 out of range [0, 6)", Kind::mesh, 1},
    {"repeated-vertex.poly2d", 11, "element 1 repeats vertex 2", Kind::mesh, 1},
    {"clockwise-element.poly2d", 11, "element 1 is clockwise", Kind::mesh, 1},
    {"zero-area-element.poly2d", 12, "element 1 has zero area", Kind::mesh, 1},
    {"self-intersecting-element.poly2d", 12, "element 1 is self-intersecting", Kind::mesh, 1},
    {"same-direction-edge.poly2d", 11, "element 1 runs edge 0-1 in the same direction as element 0", Kind::mesh, 1},
    {"edge-in-three-elements.poly2d", 11, "element 2 shares edge 0-1 that already belongs to elements 0 and 1", Kind::mesh, 2},
    {"hanging-vertex.poly2d", 12, "has vertex 6 (1, 0.5) inside its boundary edge 1-4 (hanging vertex", Kind::mesh, 0},
    {"duplicate-vertex.poly2d", 13, "element 1 uses vertex 6 (1, 0), which coincides with vertex 1", Kind::mesh, 1},
    {"no-elements.poly2d", 9, "the mesh has no elements", Kind::mesh, -1},
    {"boundary-index-out-of-range.poly2d", 15, "boundary entry 2 has vertex index 17 out of range [0, 6)", Kind::input},
    {"trailing-garbage.poly2d", 19, "unexpected content after the boundary list: 'end of mesh'", Kind::input},
    {"garbage-after-elements.poly2d", 12, "unexpected content after the element list: 'regions 2'", Kind::input},
};

fs::path malformed_dir() { return hemivem::test::data_dir() / "malformed"; }

class MalformedFile : public ::testing::TestWithParam<Malformed> {};

}  // namespace

TEST_P(MalformedFile, IsRejectedAtTheRightLine) {
  AllocationProbe probe;
  hemivem::test::expect_rejected_at_its_line(malformed_dir(), GetParam(),
                                             [](const fs::path& file) { hemivem::read_poly2d(file); });
  // Small files: no count in them may size an allocation.
  EXPECT_LT(probe.largest(), std::size_t{1} << 20);
}

INSTANTIATE_TEST_SUITE_P(Corpus, MalformedFile, ::testing::ValuesIn(kMalformed),
                         [](const ::testing::TestParamInfo<Malformed>& info) {
                           return hemivem::test::corpus_test_name(info.param.file);
                         });

TEST(MalformedCorpus, TableCoversEveryFileAndTheReadme) {
  hemivem::test::expect_table_covers_corpus(malformed_dir(), ".poly2d", kMalformed);
}
