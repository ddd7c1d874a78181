// The readers on hostile input, below the command: the inputs the fuzzers (fuzz/) found
// crashing, hanging or undefined before they were fixed (tests/data/hostile/fuzz/<reader>/,
// one file per finding), and files that are not regular files. Each must fail with a
// hemivem::InputError naming the input, nothing else.
#include <gtest/gtest.h>

#include <hemivem/error.hpp>
#include <hemivem/mesh/gmsh.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/poly2d.hpp>
#include <hemivem/scene/scene.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"

namespace fs = std::filesystem;

namespace {

fs::path hostile_dir() { return hemivem::test::data_dir() / "hostile"; }

std::vector<fs::path> files_in(const fs::path& dir) {
  std::vector<fs::path> files;
  if (fs::is_directory(dir))
    for (const auto& e : fs::directory_iterator(dir))
      if (e.is_regular_file() && e.path().filename() != "README.md") files.push_back(e.path());
  std::sort(files.begin(), files.end());
  return files;
}

/// Runs `read` and expects an InputError whose message starts with `name` (the input's name).
template <class F>
void expect_input_error(const std::string& name, F read) {
  try {
    read();
    ADD_FAILURE() << name << ": accepted";
  } catch (const hemivem::InputError& e) {
    EXPECT_EQ(std::string(e.what()).rfind(name, 0), 0u) << e.what();
  } catch (const std::exception& e) {
    ADD_FAILURE() << name << ": " << typeid(e).name() << " instead of an InputError: " << e.what();
  }
}

TEST(FuzzFindings, SceneInputsAreInputErrors) {
  for (const fs::path& f : files_in(hostile_dir() / "fuzz" / "scene")) {
    SCOPED_TRACE(f.string());
    const std::string text = hemivem::test::slurp(f);
    expect_input_error("fuzz.toml", [&] {
      const hemivem::Scene s = hemivem::parse_scene_string(text, "fuzz.toml");
      if (s.mesh.file.empty() && s.mesh.n <= 8) (void)hemivem::build_problem(s);
    });
  }
}

TEST(FuzzFindings, Poly2dInputsAreInputErrors) {
  for (const fs::path& f : files_in(hostile_dir() / "fuzz" / "poly2d")) {
    SCOPED_TRACE(f.string());
    expect_input_error(f.string(), [&] { (void)hemivem::read_poly2d(f); });
  }
}

TEST(FuzzFindings, GmshInputsAreInputErrors) {
  for (const fs::path& f : files_in(hostile_dir() / "fuzz" / "gmsh")) {
    SCOPED_TRACE(f.string());
    expect_input_error(f.string(), [&] { (void)hemivem::read_gmsh(f); });
  }
}

TEST(NotARegularFile, ReadersRefuseDirectories) {
  const fs::path dir = hostile_dir() / "folder.msh";
  ASSERT_TRUE(fs::is_directory(dir));
  for (auto read : {+[](const fs::path& p) { (void)hemivem::read_gmsh(p); },
                    +[](const fs::path& p) { (void)hemivem::read_poly2d(p); },
                    +[](const fs::path& p) { (void)hemivem::parse_scene(p); }}) {
    try {
      read(dir);
      ADD_FAILURE() << "a directory was read";
    } catch (const hemivem::InputError& e) {
      EXPECT_EQ(e.where(), dir.string());
      EXPECT_NE(std::string(e.what()).find("it is a directory"), std::string::npos) << e.what();
    }
  }
}

TEST(NotARegularFile, ReadersRefuseDevicesWithoutReadingThem) {
  // Symbolic links to /dev/zero: reading one to its end would never finish.
  for (const char* name : {"device.poly2d", "device.toml"}) {
    const fs::path p = hostile_dir() / name;
    ASSERT_TRUE(fs::is_symlink(p)) << p;
    ASSERT_FALSE(fs::is_regular_file(p)) << p;
  }
  const std::string message = "it is not a regular file (a device, a pipe or a socket)";
  try {
    (void)hemivem::read_poly2d(hostile_dir() / "device.poly2d");
    ADD_FAILURE() << "a device was read as a mesh";
  } catch (const hemivem::InputError& e) {
    EXPECT_EQ(e.where(), (hostile_dir() / "device.poly2d").string());
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
  try {
    (void)hemivem::read_gmsh("/dev/null");
    ADD_FAILURE() << "a device was read as a mesh";
  } catch (const hemivem::InputError& e) {
    EXPECT_EQ(e.where(), "/dev/null");
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
  try {
    (void)hemivem::parse_scene(hostile_dir() / "device.toml");
    ADD_FAILURE() << "a device was read as a scene";
  } catch (const hemivem::InputError& e) {
    EXPECT_EQ(e.where(), (hostile_dir() / "device.toml").string());
    EXPECT_NE(std::string(e.what()).find(message), std::string::npos) << e.what();
  }
}

TEST(NotARegularFile, MissingFilesAreNamed) {
  const fs::path p = hostile_dir() / "no-such-file.msh";
  try {
    (void)hemivem::read_gmsh(p);
    ADD_FAILURE() << "a missing file was read";
  } catch (const hemivem::InputError& e) {
    EXPECT_EQ(e.where(), p.string());
    EXPECT_NE(std::string(e.what()).find("cannot open the mesh file"), std::string::npos) << e.what();
  }
}

TEST(StreamReaders, GmshFromAStreamNamesTheGivenName) {
  std::istringstream in("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 4 1 4\n");
  try {
    (void)hemivem::read_gmsh(in, "memory.msh");
    ADD_FAILURE() << "a truncated mesh was read";
  } catch (const hemivem::InputError& e) {
    EXPECT_EQ(e.where(), "memory.msh:5");
  }
  std::istringstream ok(hemivem::test::slurp(hemivem::test::data_dir() / "gmsh" / "unit_square_quads.msh"));
  const hemivem::Mesh m = hemivem::read_gmsh(ok, "memory.msh");
  EXPECT_EQ(m.num_elements(), 6);
  EXPECT_EQ(m.num_vertices(), 11);
}

// ---- what the fuzzers found, as rules

std::string mesh_error(std::vector<hemivem::Vec2> v, std::vector<std::vector<int>> e) {
  try {
    (void)hemivem::Mesh(std::move(v), std::move(e));
  } catch (const hemivem::MeshError& x) {
    return x.what();
  }
  return "";
}

TEST(MeshRules, CoordinatesAbove1e150AreRefused) {
  using hemivem::Vec2;
  // 1e300 made the hanging-vertex check convert an infinite value to int.
  const std::string msg = mesh_error({Vec2(0, 0), Vec2(1e300, 0), Vec2(1e300, 1e300), Vec2(0, 1e300)}, {{0, 1, 2, 3}});
  EXPECT_NE(msg.find("vertex 1"), std::string::npos) << msg;
  EXPECT_NE(msg.find("magnitude above 1e150"), std::string::npos) << msg;
  // The limit itself is legal.
  EXPECT_EQ(mesh_error({Vec2(0, 0), Vec2(1e150, 0), Vec2(1e150, 1e150), Vec2(-1e150, 1e150)}, {{0, 1, 2, 3}}), "");
}

TEST(MeshRules, ReadersNameTheLineOfACoordinateAbove1e150) {
  std::istringstream poly("vertices 3\n0 0\n1 0\n0 -2e150\nelements 1\n3 0 1 2\n");
  try {
    (void)hemivem::read_poly2d(poly, "big.poly2d");
    ADD_FAILURE() << "accepted";
  } catch (const hemivem::InputError& e) {
    EXPECT_EQ(e.where(), "big.poly2d:4");
    EXPECT_NE(std::string(e.what()).find("vertex 2 has a y coordinate '-2e150' of magnitude above 1e150"), std::string::npos)
        << e.what();
  }
  std::istringstream msh("$MeshFormat\n4.1 0 8\n$EndMeshFormat\n$Nodes\n1 3 1 3\n2 1 0 3\n1\n2\n3\n0 0 0\n1e151 0 0\n0 1 0\n"
                         "$EndNodes\n$Elements\n1 1 1 1\n2 1 2 1\n1 1 2 3\n$EndElements\n");
  try {
    (void)hemivem::read_gmsh(msh, "big.msh");
    ADD_FAILURE() << "accepted";
  } catch (const hemivem::InputError& e) {
    EXPECT_EQ(e.where(), "big.msh:11");
    EXPECT_NE(std::string(e.what()).find("node 2 has a x coordinate '1e151' of magnitude above 1e150"), std::string::npos)
        << e.what();
  }
}

TEST(MeshRules, AreasBelowTheSmallestNormalDoubleAreRefused) {
  using hemivem::Vec2;
  const std::string msg = mesh_error({Vec2(0, 0), Vec2(1e-300, 0), Vec2(1e-300, 1e-300), Vec2(0, 1e-300)}, {{0, 1, 2, 3}});
  EXPECT_NE(msg.find("element 0"), std::string::npos) << msg;
  EXPECT_NE(msg.find("too small for double precision"), std::string::npos) << msg;
  // Small but normal areas and edges of 1e-13 stay legal.
  EXPECT_EQ(mesh_error({Vec2(0, 0), Vec2(1e-150, 0), Vec2(1e-150, 1e-150), Vec2(0, 1e-150)}, {{0, 1, 2, 3}}), "");
  EXPECT_EQ(mesh_error({Vec2(0, 0), Vec2(1, 0), Vec2(1, 1), Vec2(1 - 1e-13, 1), Vec2(0, 1)}, {{0, 1, 2, 3, 4}}), "");
}

TEST(GeneratorDomains, UnresolvableDomainsAreInputErrors) {
  using hemivem::Rectangle;
  // [-1.7e308, 1.7e304] x [0, 1] made make_voronoi throw a NumericalError (coinciding seeds).
  for (const auto& name : hemivem::mesh_generator_names()) {
    for (const Rectangle& d : {Rectangle{-1.7e308, 1.7e304, 0, 1}, Rectangle{0, 2e150, 0, 1}, Rectangle{0, 1e-320, 0, 1e-320},
                               Rectangle{1e9, 1e9 + 1e-3, 0, 1}, Rectangle{0, 1e-130, 0, 1e-130}}) {
      SCOPED_TRACE(name + " on [" + std::to_string(d.x0) + ", " + std::to_string(d.x1) + "]");
      try {
        (void)hemivem::make_mesh(name, 4, d);
        ADD_FAILURE() << "accepted";
      } catch (const hemivem::MeshError& e) {
        ADD_FAILURE() << "MeshError instead of a refused domain: " << e.what();
      } catch (const hemivem::InputError& e) {
        EXPECT_NE(std::string(e.what()).find("domain"), std::string::npos) << e.what();
      }
    }
    // Thin and offset rectangles within the limits still work.
    const int elements = hemivem::make_mesh(name, 4).num_elements();
    EXPECT_EQ(hemivem::make_mesh(name, 4, Rectangle{1e6, 1e6 + 1, -3, -2}).num_elements(), elements);
    EXPECT_EQ(hemivem::make_mesh(name, 4, Rectangle{0, 1000, 0, 0.001}).num_elements(), elements);
  }
}

TEST(GeneratorDomains, SceneErrorsNameTheMeshTable) {
  const std::string text = "schema_version = 1\n\n[mesh]\ngenerator = \"squares\"\nn = 2\ndomain = [0.0, 1e-320, 0.0, 1.0]\n";
  const hemivem::Scene s = hemivem::parse_scene_string(text, "tiny.toml");
  try {
    (void)hemivem::build_problem(s);
    ADD_FAILURE() << "accepted";
  } catch (const hemivem::InputError& e) {
    EXPECT_EQ(e.where(), "tiny.toml:3") << e.what();
    EXPECT_NE(std::string(e.what()).find("too small for double precision"), std::string::npos) << e.what();
  }
}

}  // namespace
