// Reading Gmsh 4.1 ASCII meshes: two files written by Gmsh 4.8 (the unit square of
// tests/data/gmsh/unit_square.geo, in triangles and in quadrangles), a hand-written file
// with two surface groups, non-contiguous node tags, a clockwise element and an unused node,
// a linear patch test on the read meshes, and a corpus of malformed files
// (tests/data/gmsh/malformed).
#include <hemivem/vem/assembly.hpp>
#include <hemivem/mesh/gmsh.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>
#include <iterator>
#include <set>
#include <sstream>
#include <string>

#include <unistd.h>

#include "test_support.hpp"

namespace {

namespace fs = std::filesystem;
using namespace hemivem;

fs::path gmsh_dir() { return test::data_dir() / "gmsh"; }

std::vector<int> sorted(std::vector<int> v) {
  std::sort(v.begin(), v.end());
  return v;
}

std::vector<int> side(const Mesh& mesh, const std::string& name) {
  return sorted(select_boundary_edges(mesh, std::vector<Segment>{rectangle_side(mesh.bounding_box(), name)}));
}

/// The checks shared by the two unit-square files (their surface is physical group 21, "body").
void check_unit_square(const Mesh& mesh) {
  EXPECT_NEAR(mesh.total_area(), 1.0, 1e-12);
  const Rectangle box = mesh.bounding_box();
  EXPECT_NEAR(box.x0, 0.0, 1e-12);
  EXPECT_NEAR(box.x1, 1.0, 1e-12);
  EXPECT_NEAR(box.y0, 0.0, 1e-12);
  EXPECT_NEAR(box.y1, 1.0, 1e-12);
  for (int e = 0; e < mesh.num_elements(); ++e) {
    EXPECT_GT(mesh.area(e), 0.0) << "element " << e;
    EXPECT_EQ(mesh.region(e), 21) << "element " << e;
  }
  // The groups are the sides found geometrically.
  EXPECT_EQ(mesh.edge_groups().size(), 3u);
  EXPECT_EQ(mesh.edge_group("contact"), side(mesh, "bottom"));
  EXPECT_EQ(mesh.edge_group("load"), side(mesh, "top"));
  std::vector<int> left_right = side(mesh, "left");
  const std::vector<int> right = side(mesh, "right");
  left_right.insert(left_right.end(), right.begin(), right.end());
  EXPECT_EQ(mesh.edge_group("clamped"), sorted(left_right));
  EXPECT_EQ(select_boundary_edges(mesh, "contact"), mesh.edge_group("contact"));
  // Together they cover the boundary once.
  std::vector<int> all;
  for (const auto& [name, edges] : mesh.edge_groups()) all.insert(all.end(), edges.begin(), edges.end());
  EXPECT_EQ(sorted(all), sorted(mesh.boundary_edges()));
  // The surface group is not an edge group.
  EXPECT_THROW(mesh.edge_group("body"), InputError);
}

std::string read_text(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

/// A file in the temporary folder, removed afterwards.
class TempFile {
 public:
  explicit TempFile(const std::string& text) {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = fs::temp_directory_path() /
            (std::string("hemivem-gmsh-") + info->name() + "-" + std::to_string(::getpid()) + ".msh");
    std::ofstream(path_, std::ios::binary) << text;
  }
  ~TempFile() {
    std::error_code ec;
    fs::remove(path_, ec);
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

}  // namespace

TEST(GmshRead, UnitSquareTrianglesWrittenByGmsh) {
  const Mesh mesh = read_gmsh(gmsh_dir() / "unit_square_triangles.msh");
  EXPECT_EQ(mesh.num_vertices(), 12);
  EXPECT_EQ(mesh.num_elements(), 14);
  for (int e = 0; e < mesh.num_elements(); ++e) EXPECT_EQ(mesh.element_size(e), 3);
  // Node tags 1..12 in order: vertex i is node i + 1.
  EXPECT_EQ(mesh.vertex(0), Vec2(0, 0));
  EXPECT_EQ(mesh.vertex(2), Vec2(1, 1));
  EXPECT_EQ(mesh.edge_group("contact").size(), 2u);
  check_unit_square(mesh);
}

TEST(GmshRead, UnitSquareQuadranglesWrittenByGmsh) {
  const Mesh mesh = read_gmsh(gmsh_dir() / "unit_square_quads.msh");
  EXPECT_EQ(mesh.num_vertices(), 11);
  EXPECT_EQ(mesh.num_elements(), 6);
  for (int e = 0; e < mesh.num_elements(); ++e) EXPECT_EQ(mesh.element_size(e), 4);
  EXPECT_EQ(mesh.vertex(1), Vec2(1, 0));
  EXPECT_EQ(mesh.vertex(10), Vec2(0.6494286120981281, 0.645533117253463));
  // Gmsh element 9 is "8 1 5 10": nodes 8, 1, 5, 10 are vertices 7, 0, 4, 9.
  const auto e0 = mesh.element(0);
  EXPECT_EQ(std::vector<int>(e0.begin(), e0.end()), (std::vector<int>{7, 0, 4, 9}));
  check_unit_square(mesh);
}

TEST(GmshRead, ParametricNodesWithoutPhysicalGroups) {
  // Written by Gmsh with Mesh.SaveParametric = 1 and no physical groups: every entity's
  // elements are saved (points, lines, triangles), node lines carry u (and v) values.
  const Mesh mesh = read_gmsh(gmsh_dir() / "unit_square_parametric.msh");
  EXPECT_EQ(mesh.num_vertices(), 12);
  EXPECT_EQ(mesh.num_elements(), 14);
  EXPECT_EQ(mesh.vertex(8), Vec2(0.2937500000004586, 0.7062500000004164));
  EXPECT_NEAR(mesh.total_area(), 1.0, 1e-12);
  EXPECT_TRUE(mesh.edge_groups().empty());
  EXPECT_EQ(mesh.regions(), std::vector<int>(14, 0));
}

TEST(GmshRead, TwoRegionsNonContiguousTagsClockwiseElementUnusedNode) {
  const Mesh mesh = read_gmsh(gmsh_dir() / "two_regions.msh");
  // Node 99 (a geometry point, used by a point element only) is dropped; the others are
  // numbered in $Nodes order: tags 10, 20, 30, 40, 50, 60.
  ASSERT_EQ(mesh.num_vertices(), 6);
  const std::vector<Vec2> expected{{0, 0}, {1, 0}, {1, 1}, {0, 1}, {2, 0}, {2, 1}};
  for (int v = 0; v < 6; ++v) EXPECT_EQ(mesh.vertex(v), expected[static_cast<std::size_t>(v)]) << v;
  // The quadrangle "10 40 30 20" is clockwise: it is turned around.
  EXPECT_EQ(mesh.elements(), (std::vector<std::vector<int>>{{1, 2, 3, 0}, {1, 4, 5}, {1, 5, 2}}));
  EXPECT_DOUBLE_EQ(mesh.area(0), 1.0);
  // Surface groups keep their tags: "steel" (7) is region 7, "rubber" (3) region 3.
  EXPECT_EQ(mesh.regions(), (std::vector<int>{7, 3, 3}));
  // 1D groups: "bottom" (named) and 9 (unnamed, named by its tag); the 0D group is ignored.
  EXPECT_EQ(mesh.edge_groups().size(), 2u);
  EXPECT_EQ(mesh.edge_group("bottom"), side(mesh, "bottom"));
  EXPECT_EQ(mesh.edge_group("9"), side(mesh, "right"));
  EXPECT_THROW(mesh.edge_group("corner"), InputError);
}

TEST(GmshRead, ElementInSeveralSurfaceGroupsTakesTheFirstListed) {
  std::string text = read_text(gmsh_dir() / "two_regions.msh");
  // Surface 2 is put in groups 7 ("steel") and 3 ("rubber"), in that order.
  const std::string from = "2 1 0 0 2 1 0 1 3 0\n", to = "2 1 0 0 2 1 0 2 7 3 0\n";
  const auto at = text.find(from);
  ASSERT_NE(at, std::string::npos);
  text.replace(at, from.size(), to);
  const TempFile file(text);
  EXPECT_EQ(read_gmsh(file.path()).regions(), (std::vector<int>{7, 7, 7}));
}

// Every prefix of a valid file that stops at a line end reads or throws an InputError
// naming a line of the file, never anything else.
TEST(GmshRead, EveryTruncationIsAnInputErrorOrAMesh) {
  for (const char* name : {"two_regions.msh", "unit_square_quads.msh"}) {
    const std::string text = read_text(gmsh_dir() / name);
    std::size_t cut = 0;
    int lines = 0, errors = 0;
    while ((cut = text.find('\n', cut)) != std::string::npos) {
      ++cut;
      ++lines;
      const TempFile file(text.substr(0, cut));
      SCOPED_TRACE(std::string(name) + " cut after line " + std::to_string(lines));
      try {
        read_gmsh(file.path());
        EXPECT_EQ(cut, text.size()) << "a truncated file read without error";
      } catch (const InputError& e) {
        ++errors;
        EXPECT_EQ(e.where().rfind(file.path().string() + ":", 0), 0u) << e.what();
      }
    }
    EXPECT_EQ(errors, lines - 1) << name;
  }
}

// A linear displacement is reproduced on the read meshes: clamped-group Dirichlet data,
// the exact traction on the "load" and "contact" groups.
TEST(GmshRead, ReadMeshesPassTheLinearPatchTest) {
  for (const char* file : {"unit_square_triangles.msh", "unit_square_quads.msh"}) {
    SCOPED_TRACE(file);
    const Mesh mesh = read_gmsh(gmsh_dir() / file);
    const Vec2 a{0.3, -0.7};
    const Eigen::Matrix2d G = (Eigen::Matrix2d() << 0.011, -0.027, 0.019, 0.005).finished();
    const VectorField exact = [a, G](const Vec2& x) -> Vec2 { return a + G * x; };
    const Material mat{65.0, 0.29};
    ElasticityProblem p;
    p.mesh = &mesh;
    p.materials = MaterialTable(mat, PlaneModel::stress);
    const Lame l = lame(mat, PlaneModel::stress);
    const Eigen::Matrix2d eps = 0.5 * (G + G.transpose());
    const Eigen::Matrix2d sigma = l.lambda * eps.trace() * Eigen::Matrix2d::Identity() + 2 * l.mu * eps;
    p.dirichlet.push_back({select_boundary_edges(mesh, "clamped"), exact, {true, true}});
    for (const char* group : {"load", "contact"}) {
      for (int id : select_boundary_edges(mesh, group)) {
        const auto& e = mesh.edge(id);
        const Vec2 d = mesh.vertex(e.v1) - mesh.vertex(e.v0);
        const Vec2 t = sigma * Vec2(d.y(), -d.x()).normalized();
        p.tractions.push_back({{id}, [t](const Vec2&) { return t; }});
      }
    }
    const Eigen::VectorXd u = test::solve(assemble(p));
    double err = 0.0;
    for (int v = 0; v < mesh.num_vertices(); ++v)
      err = std::max(err, (u.segment<2>(2 * v) - exact(mesh.vertex(v))).cwiseAbs().maxCoeff());
    EXPECT_LT(err, 1e-10);
  }
}

TEST(GmshRead, MissingFileAndFolderNameThePath) {
  const fs::path missing = gmsh_dir() / "no-such-file.msh";
  try {
    read_gmsh(missing);
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(e.where(), missing.string());
    EXPECT_NE(std::string(e.what()).find("cannot open the mesh file"), std::string::npos) << e.what();
  }
  try {
    read_gmsh(gmsh_dir());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find("it is a directory"), std::string::npos) << e.what();
  }
}

// ---- the malformed corpus ----------------------------------------------------------------

namespace {

using hemivem::test::Malformed;
using Kind = hemivem::test::MalformedKind;

// Keep in step with tests/data/gmsh/malformed/README.md (checked below).
const Malformed kMalformed[] = {
    {"empty-file.msh", 1, "the file holds no data: expected $MeshFormat"},
    {"not-a-mesh-file.msh", 1, "expected a section header such as $Nodes, found 'vertices 3'"},
    {"binary.msh", 2, "binary MSH files are not supported"},
    {"version-2.2.msh", 2, "MSH format version '2.2' is not supported: only version 4.1 is read"},
    {"missing-nodes.msh", 20, "missing $Nodes section"},
    {"missing-end-nodes.msh", 39, "expected $EndNodes (closing line 20), found '$Elements'"},
    {"node-count-disagrees.msh", 21, "$Nodes declares 8 nodes but its blocks hold 7"},
    {"absurd-node-count.msh", 21, "the node count 2000000000 exceeds what the rest of the file can hold"},
    {"element-count-disagrees.msh", 41, "$Elements declares 9 elements but its blocks hold 7"},
    {"3d-coordinates.msh", 32, "node 30 has z = 0.5: only plane meshes (z = 0) are read"},
    {"unknown-node-tag.msh", 54, "element 3 refers to node tag 70, which is not in $Nodes"},
    {"element-missing-node.msh", 51, "element 1 (type 3) lists 3 node tags, expected 4"},
    {"second-order-element.msh", 52, "element type 9 (6-node second-order triangle) is not supported"},
    {"line-not-on-edge.msh", 49, "line element 6 (nodes 10 30) is not an edge of the surface mesh"},
    {"truncated.msh", 53, "the file ends inside $Elements (line 40) while expecting 2 element lines"},
    {"overlapping-elements.msh", 54, "Gmsh element 3: element 2 runs edge", Kind::mesh, 2},
};

fs::path malformed_dir() { return gmsh_dir() / "malformed"; }

class MalformedGmsh : public ::testing::TestWithParam<Malformed> {};

}  // namespace

TEST_P(MalformedGmsh, IsRejectedAtTheRightLine) {
  hemivem::test::expect_rejected_at_its_line(malformed_dir(), GetParam(), [](const fs::path& file) { read_gmsh(file); });
}

INSTANTIATE_TEST_SUITE_P(Corpus, MalformedGmsh, ::testing::ValuesIn(kMalformed),
                         [](const ::testing::TestParamInfo<Malformed>& info) {
                           return hemivem::test::corpus_test_name(info.param.file, "f");
                         });

TEST(MalformedGmshCorpus, TableCoversEveryFileAndTheReadme) {
  hemivem::test::expect_table_covers_corpus(malformed_dir(), ".msh", kMalformed);
}
