// `hemivem solve` of three-dimensional scenes and `hemivem mesh` of 3D kinds, run as a user runs
// them: the exit codes, the report, every file of the output folder read back (solution.vtu's
// binary arrays decoded here), and bad input refused with nothing written.
#include <hemivem/scene/mesh_files3d.hpp>
#include <nlohmann/json.hpp>

#include <gtest/gtest.h>

#include <zlib.h>

#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"
#include "vtu_arrays.hpp"

namespace fs = std::filesystem;
using hemivem::test::CommandRun;
using hemivem::test::run_command;
using hemivem::test::run_hemivem;
using hemivem::test::scenes_dir;
using hemivem::test::scratch;
using hemivem::test::slurp;

namespace {


/// The text of `<DataArray ... Name="name" ...>` in `vtu` (its attributes and its content).
struct DataArrayText {
  std::string attributes, content;
};
DataArrayText data_array(const std::string& vtu, const std::string& name) {
  const auto at = vtu.find("Name=\"" + name + "\"");
  if (at == std::string::npos) return {};
  const auto open = vtu.rfind("<DataArray", at), close = vtu.find('>', at), end = vtu.find("</DataArray>", close);
  return {vtu.substr(open, close - open), vtu.substr(close + 1, end - close - 1)};
}


template <class T>
std::vector<T> values(const std::string& vtu, const std::string& name) {
  const auto bytes = hemivem::test::decode_vtu_array(data_array(vtu, name).content);
  std::vector<T> out(bytes.size() / sizeof(T));
  std::memcpy(out.data(), bytes.data(), out.size() * sizeof(T));
  return out;
}

std::vector<std::vector<std::string>> read_csv(const fs::path& file, std::string* header) {
  std::ifstream in(file);
  std::getline(in, *header);
  std::vector<std::vector<std::string>> rows;
  for (std::string line; std::getline(in, line);) {
    std::vector<std::string> row;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) row.push_back(cell);
    rows.push_back(row);
  }
  return rows;
}

bool is_png(const fs::path& p) { return slurp(p).rfind("\x89PNG\r\n\x1a\n", 0) == 0; }

bool gnuplot_on_path() { return run_command("command -v gnuplot").code == 0; }

}  // namespace

TEST(Cli3D, SolveWritesEveryOutput) {
  const fs::path out = scratch("cli-3d");
  const CommandRun r = run_hemivem("solve " + (scenes_dir() / "example-4.1-3d.toml").string() + " --n 4 --out " +
                                   out.string());
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  for (const char* line : {"cubes n=4: 125 vertices, 64 cells", "(three-dimensional)", "status        converged",
                           "contact       15 nodes", "forces        applied (0, 0, -4)", "balance       "})
    EXPECT_NE(r.out.find(line), std::string::npos) << line << " in\n" << r.out;

  const auto j = nlohmann::json::parse(slurp(out / "result.json"));
  EXPECT_EQ(j.at("schema"), "hemivem-result/26");
  EXPECT_EQ(j.at("dimension"), 3);
  EXPECT_EQ(j.at("converged"), true);
  EXPECT_EQ(j.at("mesh").at("vertices"), 125);
  EXPECT_EQ(j.at("mesh").at("elements"), 64);
  EXPECT_LT(j.at("forces").at("balance_residual").get<double>(), 1e-10);
  const auto& contact = j.at("contact");
  ASSERT_EQ(contact.size(), 15u);  // the bottom's 25 vertices less the 10 on x = 0 and x = 1
  for (const auto& n : contact) {
    ASSERT_EQ(n.at("x").size(), 3u);
    EXPECT_EQ(n.at("x")[2], 0.0);
    EXPECT_EQ(n.at("normal"), nlohmann::json({0.0, 0.0, -1.0}));
  }
  ASSERT_EQ(j.at("contact_force").size(), 3u);
  std::set<std::string> listed;
  for (const auto& f : j.at("files")) listed.insert(f.get<std::string>());
  std::set<std::string> expected{"result.json", "contact.csv",         "displacement.csv", "stress.csv",
                                 "history.csv", "solution.vtu",        "contact-surface.vtu", "scene.toml"};
  if (gnuplot_on_path()) expected.insert({"deformed.png", "pressure.png"});
  EXPECT_EQ(listed, expected);
  for (const auto& f : expected) EXPECT_TRUE(fs::exists(out / f)) << f;
  if (gnuplot_on_path()) {
    EXPECT_TRUE(is_png(out / "deformed.png"));
    EXPECT_TRUE(is_png(out / "pressure.png"));
  } else {
    EXPECT_NE(r.out.find("skipped       deformed.png: gnuplot not found on PATH"), std::string::npos) << r.out;
  }

  std::string header;
  const auto displacement = read_csv(out / "displacement.csv", &header);
  EXPECT_EQ(header, "vertex,x,y,z,ux,uy,uz");
  ASSERT_EQ(displacement.size(), 125u);
  const auto rows = read_csv(out / "contact.csv", &header);
  EXPECT_EQ(header, "vertex,x,y,z,u_nu,law_force,reaction,pressure,state,gap,nx,ny,nz");
  ASSERT_EQ(rows.size(), contact.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    EXPECT_EQ(std::stoi(rows[i][0]), contact[i].at("vertex").get<int>());
    EXPECT_EQ(std::stod(rows[i][4]), contact[i].at("u_nu").get<double>());
    // u_nu is the normal component of the displacement of displacement.csv
    const auto& d = displacement[static_cast<std::size_t>(std::stoi(rows[i][0]))];
    EXPECT_NEAR(-std::stod(d[6]), std::stod(rows[i][4]), 1e-14);
  }

  // solution.vtu: 64 VTK_POLYHEDRON cells with their faces, the displacement of displacement.csv
  const std::string vtu = slurp(out / "solution.vtu");
  EXPECT_NE(vtu.find("<Piece NumberOfPoints=\"125\" NumberOfCells=\"64\">"), std::string::npos);
  const auto types = values<std::uint8_t>(vtu, "types");
  ASSERT_EQ(types.size(), 64u);
  for (auto t : types) EXPECT_EQ(t, 42) << "VTK_POLYHEDRON";
  const auto faces = values<std::int64_t>(vtu, "faces");
  const auto faceoffsets = values<std::int64_t>(vtu, "faceoffsets");
  ASSERT_EQ(faceoffsets.size(), 64u);
  EXPECT_EQ(faceoffsets.back(), static_cast<std::int64_t>(faces.size()));
  EXPECT_EQ(faces.size(), 64u * (1 + 6 * 5));  // a cube: 6 faces of 4 points
  EXPECT_EQ(faces.front(), 6);
  const auto u = values<double>(vtu, "displacement");
  ASSERT_EQ(u.size(), 3u * 125);
  for (std::size_t v = 0; v < 125; ++v)
    for (std::size_t c = 0; c < 3; ++c) EXPECT_EQ(u[3 * v + c], std::stod(displacement[v][4 + c]));
  EXPECT_NE(data_array(vtu, "stress").attributes.find("NumberOfComponents=\"6\""), std::string::npos);
  EXPECT_EQ(values<double>(vtu, "stress").size(), 6u * 64);
  EXPECT_EQ(values<double>(vtu, "von_mises").size(), 64u);
  EXPECT_EQ(values<std::int32_t>(vtu, "region").size(), 64u);

  // contact-surface.vtu: the 16 bottom faces as polygons with the pressure of contact.csv
  const std::string surface = slurp(out / "contact-surface.vtu");
  const auto polygon_types = values<std::uint8_t>(surface, "types");
  ASSERT_EQ(polygon_types.size(), 16u);
  for (auto t : polygon_types) EXPECT_EQ(t, 7) << "VTK_POLYGON";
  const auto vertex = values<std::int64_t>(surface, "vertex");
  const auto pressure = values<double>(surface, "pressure");
  ASSERT_EQ(vertex.size(), 25u);
  ASSERT_EQ(pressure.size(), 25u);
  for (const auto& row : rows) {
    const auto at = std::find(vertex.begin(), vertex.end(), std::stoll(row[0]));
    ASSERT_NE(at, vertex.end());
    EXPECT_EQ(pressure[static_cast<std::size_t>(at - vertex.begin())], std::stod(row[7]));
  }
  fs::remove_all(out);
}

// meshio (when the Python on this machine has it) reads solution.vtu as polyhedra with the
// data written.
TEST(Cli3D, MeshioReadsThePolyhedra) {
  std::string python;
  for (const char* p : {"python3", "/usr/bin/python3"})
    if (run_command(std::string(p) + " -c 'import meshio, numpy' 2>/dev/null").code == 0) {
      python = p;
      break;
    }
  if (python.empty()) GTEST_SKIP() << "no python3 with meshio";
  const fs::path out = scratch("cli-3d-meshio");
  const CommandRun r = run_hemivem("solve " + (scenes_dir() / "hertz-sphere-3d.toml").string() + " --n 3 --out " +
                                   out.string() + " -q --set mesh.generator=tetrahedra");
  ASSERT_EQ(r.code, 0) << r.err;
  const CommandRun m = run_command(
      python + " -c \"import meshio, numpy as np\n"
               "m = meshio.read('" + (out / "solution.vtu").string() + "')\n"
               "print(sum(len(c.data) for c in m.cells), m.point_data['displacement'].shape, "
               "m.cell_data['stress'][0].shape, len(m.points))\"");
  ASSERT_EQ(m.code, 0) << m.err;
  EXPECT_EQ(m.out, "162 (64, 3) (162, 6) 64\n");  // 27 cubes of 6 tetrahedra, 4^3 vertices
  fs::remove_all(out);
}

TEST(Cli3D, BadInputIsRefusedWithNothingWritten) {
  const fs::path dir = scratch("cli-3d-bad");
  fs::create_directories(dir);
  const fs::path out = dir / "out";
  auto refused = [&](const std::string& body, std::initializer_list<std::string> fragments) {
    std::ofstream(dir / "bad.toml") << "schema_version = 1\n[mesh]\ndomain = [0, 1, 0, 1, 0, 1]\nn = 2\n" << body;
    const CommandRun r = run_hemivem("solve " + (dir / "bad.toml").string() + " --out " + out.string());
    EXPECT_EQ(r.code, 2) << body;
    for (const auto& f : fragments) EXPECT_NE(r.err.find(f), std::string::npos) << f << " in " << r.err;
    EXPECT_FALSE(fs::exists(out)) << body;
  };
  refused("[clamped]\nside = \"bottom\"\n[contact]\nside = \"top\"\n[contact.friction]\nlaw = \"coulomb\"\n"
          "coefficient = -0.3\n",
          {"bad.toml:11: contact.friction.coefficient"});
  refused("[clamped]\nside = \"west\"\n", {"bad.toml:6: clamped.side: unknown side 'west'"});
  refused("[clamped]\nside = \"bottom\"\n[contact]\nside = \"top\"\n[contact.obstacle]\nshape = \"polyline\"\n"
          "points = [[0, 1], [1, 1]]\n",
          {"bad.toml:10: contact.obstacle.shape: 'polyline' is an obstacle of two-dimensional scenes"});
  fs::remove_all(dir);
}

TEST(Cli3D, AnUndrivenBodySolvesWithAWarningAndTheAdaptFlagIsRefused) {
  const fs::path dir = scratch("cli-3d-warn");
  fs::create_directories(dir);
  std::ofstream(dir / "still.toml") << "schema_version = 1\n[mesh]\ndomain = [0, 1, 0, 1, 0, 1]\nn = 2\n"
                                       "[clamped]\nside = \"bottom\"\n";
  const CommandRun r = run_hemivem("solve " + (dir / "still.toml").string() + " --out " + (dir / "out").string());
  EXPECT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.err.find("hemivem: warning: nothing drives this problem"), std::string::npos) << r.err;
  EXPECT_NE(r.out.find("(no contact: one linear solve)"), std::string::npos) << r.out;
  EXPECT_FALSE(fs::exists(dir / "out" / "contact.csv"));
  fs::remove_all(dir);
}

// One folder, a plane run then a solid one: the second replaces the first's files, those of names
// it does not write (u_nu.png, error.png) removed, and says so.
TEST(Cli3D, ASolidRunReplacesAPlaneRunsOutputs) {
  const fs::path out = scratch("cli-3d-replace");
  const CommandRun plane = run_hemivem("solve --n 4 -q --out " + out.string());
  ASSERT_EQ(plane.code, 0) << plane.err;
  const CommandRun solid = run_hemivem("solve " + (scenes_dir() / "example-4.1-3d.toml").string() +
                                       " --n 2 --set output.write='[\"result-json\"]' --out " + out.string());
  ASSERT_EQ(solid.code, 0) << solid.err;
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(out)) names.insert(e.path().filename().string());
  EXPECT_EQ(names, (std::set<std::string>{"result.json", "scene.toml"}));
  EXPECT_NE(solid.out.find("removed       "), std::string::npos) << solid.out;
  EXPECT_NE(solid.out.find("displacement.csv"), std::string::npos) << solid.out;
  fs::remove_all(out);
}

TEST(Cli3D, MeshCommandOfThreeDimensionalKinds) {
  const fs::path dir = scratch("cli-3d-mesh");
  fs::create_directories(dir);
  const CommandRun poly = run_hemivem("mesh cubes --n 2 -o " + (dir / "c.poly2d").string());
  EXPECT_EQ(poly.code, 2);
  EXPECT_NE(poly.err.find("written as a Gmsh file"), std::string::npos) << poly.err;
  const CommandRun five = run_hemivem("mesh cubes --n 2 --domain 0 1 0 1 0 -o " + (dir / "c.msh").string());
  EXPECT_EQ(five.code, 2);
  EXPECT_NE(five.err.find("--domain takes 4 numbers"), std::string::npos) << five.err;
  const CommandRun wrong = run_hemivem("mesh squares --n 2 --domain 0 1 0 1 0 1 -o " + (dir / "c.msh").string());
  EXPECT_EQ(wrong.code, 2);
  EXPECT_NE(wrong.err.find("unknown three-dimensional mesh generator 'squares'"), std::string::npos) << wrong.err;
  const CommandRun cubes = run_hemivem("mesh tetrahedra --n 2 --nz 1 -o " + (dir / "t.msh").string());
  ASSERT_EQ(cubes.code, 0) << cubes.err;
  EXPECT_NE(cubes.out.find("(18 vertices, 24 cells)"), std::string::npos) << cubes.out;
  EXPECT_EQ(slurp(dir / "t.msh").rfind("$MeshFormat", 0), 0u);
  EXPECT_EQ(hemivem::gmsh_file_dimension(dir / "t.msh"), 3);
  // the mesh written is a scene's mesh: solved as the generator's
  std::ofstream(dir / "t.toml") << "schema_version = 1\n[mesh]\nfile = \"t.msh\"\n[clamped]\nside = \"bottom\"\n"
                                   "[loads]\nbody_force = [0, 0, -1]\n";
  const CommandRun file = run_hemivem("solve " + (dir / "t.toml").string() + " --json -q --out " + (dir / "out").string());
  ASSERT_EQ(file.code, 0) << file.err;
  const CommandRun generated = run_hemivem("solve " + (dir / "t.toml").string() +
                                           " --json -q --set mesh.generator=tetrahedra --set mesh.n=[2,2,1] --out " +
                                           (dir / "out").string());
  ASSERT_EQ(generated.code, 0) << generated.err;
  const auto a = nlohmann::json::parse(file.out), b = nlohmann::json::parse(generated.out);
  EXPECT_EQ(a.at("dimension"), 3);
  EXPECT_EQ(a.at("mesh").at("elements"), 24);
  EXPECT_NEAR(a.at("potential_energy").get<double>(), b.at("potential_energy").get<double>(),
              1e-12 * std::abs(b.at("potential_energy").get<double>()));
  // a Voronoi polyhedron has no Gmsh element: refused, nothing written
  const CommandRun voronoi = run_hemivem("mesh voronoi --n 2 --domain 0 1 0 1 0 1 -o " + (dir / "v.msh").string());
  EXPECT_EQ(voronoi.code, 2);
  EXPECT_NE(voronoi.err.find("Gmsh has no polyhedron element"), std::string::npos) << voronoi.err;
  EXPECT_FALSE(fs::exists(dir / "v.msh"));
  fs::remove_all(dir);
}
