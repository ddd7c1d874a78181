// The output folder of a solve: result.json, the CSV tables, the VTU file (read back with a
// real VTK reader) and the gnuplot figures.
#include <hemivem/app/outputs.hpp>
#include <hemivem/app/figures.hpp>
#include <hemivem/app/vtu.hpp>
#include "test_support.hpp"

#include <hemivem/contact/solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/vem/stress.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/scene/example.hpp>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <limits>
#include <optional>
#include <sstream>

#include <unistd.h>

using namespace hemivem;
using namespace hemivem::app;
namespace fs = std::filesystem;
using nlohmann::json;
using hemivem::test::slurp;

namespace {

bool have_ssn() {
  const auto m = available_minimizers();
  return std::find(m.begin(), m.end(), "ssn") != m.end();
}

bool have_program(const std::string& check) { return std::system((check + " >/dev/null 2>&1").c_str()) == 0; }

bool have_gnuplot() { return have_program("command -v gnuplot"); }
/// A Python interpreter that can import meshio (the one on PATH, else Debian's), or empty.
std::string python_with_meshio() {
  for (const char* python : {"python3", "/usr/bin/python3"})
    if (have_program(std::string(python) + " -c 'import meshio, numpy'")) return python;
  return {};
}

std::vector<std::string> lines(const fs::path& p) {
  std::ifstream in(p);
  std::vector<std::string> out;
  for (std::string l; std::getline(in, l);) out.push_back(l);
  return out;
}

/// A fresh folder under the system's temporary folder, removed at the end.
struct ScratchDir {
  fs::path path;
  explicit ScratchDir(const std::string& name) {
    path = fs::temp_directory_path() /
           ("hemivem-test-outputs-" + name + "-" + std::to_string(::getpid()));
    fs::remove_all(path);
    fs::create_directories(path);
  }
  ~ScratchDir() {
    std::error_code ec;
    fs::remove_all(path, ec);
  }
};

/// Example 4.1 on an 8 x 8 square mesh, solved once for the whole suite.
struct Solved {
  Mesh mesh = make_squares(8);
  ContactProblem problem = example_4_1(mesh);
  ContactSolution solution;
  RunInfo info;
  Solved() {
    FactorizationOptions f;
    f.engine = "eigen";
    MinimizerOptions o;
    o.tolerance = 1e-10;
    solution = solve_contact(problem, make_factorization(f), *make_minimizer("ssn"), o);
    info.scene_name = "example-4-1";
    info.scene_toml = "# a test scene\nschema = 1\nname = \"example-4-1\"\n";
    info.mesh = "squares n=8";
    info.linear = "eigen";
    info.minimizer = "ssn";
    info.options = {{"tolerance", 1e-10}, {"stabilization", "2mu"}};
    info.mesh_seconds = 0.25;
    info.dofs = 123;
  }
};

const Solved& solved() {
  static const Solved s;
  return s;
}

class Outputs : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_ssn()) GTEST_SKIP() << "the ssn minimizer was not built";
  }
};

TEST_F(Outputs, ResultJsonHasEveryDocumentedField) {
  const Solved& s = solved();
  ScratchDir dir("json");
  const OutputReport report = write_outputs(dir.path, s.mesh, s.problem.elasticity.materials, s.solution, s.info,
                                            {"result.json"});
  ASSERT_EQ(report.written.size(), 1u);
  const json j = json::parse(slurp(dir.path / "result.json"));
  const auto& sol = s.solution;

  EXPECT_EQ(j.at("schema"), "hemivem-result/26");
  EXPECT_EQ(j.at("version"), HEMIVEM_VERSION);
  EXPECT_EQ(j.at("scene").at("name"), "example-4-1");
  EXPECT_EQ(j.at("scene").at("toml"), s.info.scene_toml);
  EXPECT_EQ(j.at("backends").at("linear"), "eigen");
  EXPECT_EQ(j.at("backends").at("minimizer"), "ssn");
  EXPECT_EQ(j.at("processes"), 1);
  EXPECT_EQ(j.at("options").at("tolerance"), 1e-10);
  EXPECT_EQ(j.at("options").at("stabilization"), "2mu");

  ASSERT_TRUE(sol.converged());
  EXPECT_EQ(j.at("status"), "converged");
  EXPECT_EQ(j.at("converged"), true);
  EXPECT_TRUE(j.at("message").is_string());
  EXPECT_EQ(j.at("schema"), "hemivem-result/26");
  EXPECT_EQ(j.at("dimension"), 2);
  const Certificate& cert = sol.certificate;
  EXPECT_EQ(j.at("certificate").at("primal").get<double>(), cert.primal);
  EXPECT_EQ(j.at("certificate").at("dual").get<double>(), cert.dual);
  EXPECT_EQ(j.at("certificate").at("length_scale").get<double>(), cert.length_scale);
  EXPECT_EQ(j.at("certificate").at("force_scale").get<double>(), cert.force_scale);
  EXPECT_EQ(j.at("certificate").at("tolerance").get<double>(), 1e-10);
  ASSERT_TRUE(j.at("uniqueness_margin").is_number());
  EXPECT_EQ(j.at("uniqueness_margin").get<double>(), sol.uniqueness_margin);
  EXPECT_EQ(j.at("may_be_nonunique"), sol.may_be_nonunique);
  EXPECT_EQ(j.at("potential_energy").get<double>(), sol.energy);
  EXPECT_TRUE(j.at("iterations").is_number_integer());
  EXPECT_EQ(j.at("iterations").get<int>(), sol.iterations());
  EXPECT_TRUE(j.at("evaluations").at("function").is_number_integer());
  EXPECT_TRUE(j.at("evaluations").at("subgradient").is_number_integer());
  EXPECT_EQ(j.at("stages").get<std::vector<std::string>>(), sol.stages);

  const json& t = j.at("timings");
  double stages = 0.0;  // the solver's stages, disjoint intervals of its total
  for (const char* stage :
       {"mesh", "setup", "assembly", "condensation", "minimize", "back_substitution", "post_process", "total"}) {
    ASSERT_TRUE(t.contains(stage)) << stage;
    EXPECT_TRUE(t.at(stage).is_number()) << stage;
    EXPECT_GE(t.at(stage).get<double>(), 0.0) << stage;
    if (std::string(stage) != "mesh" && std::string(stage) != "total") stages += t.at(stage).get<double>();
  }
  EXPECT_LE(stages, sol.timings.at("total"));
  EXPECT_EQ(t.at("mesh").get<double>(), 0.25);
  EXPECT_NEAR(t.at("total").get<double>(), 0.25 + sol.timings.at("total"), 1e-12);
  EXPECT_EQ(t.at("minimize").get<double>(), sol.timings.at("minimize"));

  const json& m = j.at("mesh");
  EXPECT_EQ(m.at("description"), "squares n=8");
  EXPECT_EQ(m.at("vertices").get<int>(), s.mesh.num_vertices());
  EXPECT_EQ(m.at("elements").get<int>(), s.mesh.num_elements());
  EXPECT_EQ(m.at("dofs").get<int>(), 123);
  EXPECT_DOUBLE_EQ(m.at("h").get<double>(), s.mesh.h());

  const json& c = j.at("contact");
  ASSERT_TRUE(c.is_array());
  ASSERT_EQ(c.size(), sol.contact.size());
  ASSERT_FALSE(sol.contact.empty());
  for (std::size_t i = 0; i < c.size(); ++i) {
    const auto& n = sol.contact[i];
    EXPECT_EQ(c[i].at("vertex").get<int>(), n.vertex);
    EXPECT_EQ(c[i].at("x").get<double>(), n.x.x());
    EXPECT_EQ(c[i].at("y").get<double>(), n.x.y());
    EXPECT_EQ(c[i].at("u_nu").get<double>(), n.u_nu);
    EXPECT_EQ(c[i].at("law_force").get<double>(), n.law_force);
    EXPECT_EQ(c[i].at("reaction").get<double>(), n.reaction);
    EXPECT_EQ(c[i].at("pressure").get<double>(), (n.law_force + n.reaction) / n.weight);
    EXPECT_EQ(c[i].at("state"), to_string(n.state));
  }
}

TEST_F(Outputs, NonFiniteNumbersAreNullAndDofsDefaultToTwicePerVertex) {
  const Solved& s = solved();
  ContactSolution sol = s.solution;
  sol.uniqueness_margin = std::numeric_limits<double>::infinity();
  sol.energy = std::numeric_limits<double>::quiet_NaN();
  sol.status = MinimizerStatus::iteration_limit;
  RunInfo info = s.info;
  info.dofs = -1;
  const json j = json::parse(result_json(s.mesh, sol, info).dump());
  EXPECT_TRUE(j.at("uniqueness_margin").is_null());
  EXPECT_TRUE(j.at("potential_energy").is_null());
  EXPECT_EQ(j.at("status"), "iteration limit");
  EXPECT_EQ(j.at("converged"), false);
  EXPECT_EQ(j.at("mesh").at("dofs").get<int>(), 2 * s.mesh.num_vertices());
}

TEST_F(Outputs, CsvTablesHaveHeadersAndOneRowPerNode) {
  const Solved& s = solved();
  ScratchDir dir("csv");
  write_outputs(dir.path, s.mesh, s.problem.elasticity.materials, s.solution, s.info,
                {"contact.csv", "displacement.csv", "history.csv", "scene.toml"});
  const auto contact = lines(dir.path / "contact.csv");
  ASSERT_EQ(contact.size(), s.solution.contact.size() + 1);
  EXPECT_EQ(contact[0], "vertex,x,y,u_nu,law_force,reaction,pressure,state,gap,nx,ny");
  {
    // the first row holds the first contact node
    std::stringstream row(contact[1]);
    std::string field;
    std::vector<std::string> f;
    while (std::getline(row, field, ',')) f.push_back(field);
    ASSERT_EQ(f.size(), 11u);
    EXPECT_EQ(std::stoi(f[0]), s.solution.contact[0].vertex);
    EXPECT_EQ(std::stod(f[3]), s.solution.contact[0].u_nu);
    EXPECT_EQ(std::stod(f[4]), s.solution.contact[0].law_force);
    EXPECT_EQ(std::stod(f[5]), s.solution.contact[0].reaction);
    EXPECT_EQ(f[7], to_string(s.solution.contact[0].state));
    EXPECT_EQ(std::stod(f[8]), s.solution.contact[0].gap);
    EXPECT_EQ(std::stod(f[9]), s.solution.contact[0].normal.x());
    EXPECT_EQ(std::stod(f[10]), s.solution.contact[0].normal.y());
  }
  const auto disp = lines(dir.path / "displacement.csv");
  ASSERT_EQ(disp.size(), static_cast<std::size_t>(s.mesh.num_vertices()) + 1);
  EXPECT_EQ(disp[0], "vertex,x,y,ux,uy");
  for (int v : {0, s.mesh.num_vertices() / 2, s.mesh.num_vertices() - 1}) {
    std::stringstream row(disp[static_cast<std::size_t>(v) + 1]);
    std::string field;
    std::vector<double> f;
    while (std::getline(row, field, ',')) f.push_back(std::stod(field));
    ASSERT_EQ(f.size(), 5u);
    EXPECT_EQ(static_cast<int>(f[0]), v);
    EXPECT_EQ(f[1], s.mesh.vertex(v).x());
    EXPECT_EQ(f[2], s.mesh.vertex(v).y());
    EXPECT_EQ(f[3], s.solution.u(2 * v));
    EXPECT_EQ(f[4], s.solution.u(2 * v + 1));
  }
  const auto history = lines(dir.path / "history.csv");
  ASSERT_EQ(history.size(), s.solution.minimizer->history.size() + 1);
  EXPECT_EQ(history[0], "iteration,reduced_objective,primal,dual,active,seconds");
  EXPECT_EQ(slurp(dir.path / "scene.toml"), s.info.scene_toml);
  EXPECT_FALSE(fs::exists(dir.path / "result.json"));  // only what was asked for
}

// solution.vtu is VTK's compressed binary form: every array base64-encoded zlib blocks of
// 32 KiB. On 40 x 40 squares the points (1681 x 24 bytes) span two blocks, the last one
// partial; meshio decodes them to the displacement written to displacement.csv.
TEST_F(Outputs, VtuIsCompressedBinaryInBlocks) {
  const std::string python = python_with_meshio();
  if (python.empty()) GTEST_SKIP() << "no python3 with meshio";
  Mesh mesh = make_squares(40);
  ContactProblem problem = example_4_1(mesh);
  FactorizationOptions f;
  f.engine = "eigen";
  const ContactSolution sol = solve_contact(problem, make_factorization(f), *make_minimizer("ssn"), MinimizerOptions{});
  ScratchDir dir("vtu-blocks");
  write_outputs(dir.path, mesh, problem.elasticity.materials, sol, solved().info, {"solution.vtu", "displacement.csv"});
  const std::string text = slurp(dir.path / "solution.vtu");
  EXPECT_NE(text.find("compressor=\"vtkZLibDataCompressor\""), std::string::npos);
  EXPECT_NE(text.find("header_type=\"UInt64\""), std::string::npos);
  EXPECT_EQ(text.find("format=\"ascii\""), std::string::npos);
  EXPECT_NE(text.find("Name=\"displacement\" NumberOfComponents=\"3\" format=\"binary\""), std::string::npos);
  const fs::path report = dir.path / "max.txt";
  const std::string script =
      "import meshio, numpy as np\n"
      "m = meshio.read('" + (dir.path / "solution.vtu").string() + "')\n"
      "c = np.loadtxt('" + (dir.path / "displacement.csv").string() + "', delimiter=',', skiprows=1)\n"
      "d = m.point_data['displacement']\n"
      "scale = abs(c[:, 3:5]).max()\n"
      "with open('" + report.string() + "', 'w') as f:\n"
      "    f.write('%d %.3e %.3e %d\\n' % (len(m.points), abs(m.points[:, :2] - c[:, 1:3]).max(),\n"
      "            abs(d[:, :2] - c[:, 3:5]).max() / scale, sum(len(b.data) for b in m.cells)))\n";
  const fs::path py = dir.path / "read.py";
  std::ofstream(py) << script;
  ASSERT_EQ(std::system((python + " '" + py.string() + "' 2>'" + (dir.path / "err.txt").string() + "'").c_str()), 0)
      << slurp(dir.path / "err.txt");
  std::ifstream in(report);
  int points = 0, cells = 0;
  double point_error = 1, displacement_error = 1;
  in >> points >> point_error >> displacement_error >> cells;
  EXPECT_EQ(points, 41 * 41);
  EXPECT_EQ(cells, 40 * 40 + 38);  // the squares and Gamma_3's 38 edges between its 39 contact nodes
  EXPECT_LE(point_error, 1e-15);
  EXPECT_LE(displacement_error, 1e-12);  // displacement.csv: 17 significant digits
}

TEST_F(Outputs, VtuLoadsInARealVtkReader) {
  const std::string python = python_with_meshio();
  if (python.empty()) GTEST_SKIP() << "no python3 with meshio";
  const Solved& s = solved();
  ScratchDir dir("vtu");
  write_outputs(dir.path, s.mesh, s.problem.elasticity.materials, s.solution, s.info, {"solution.vtu"});
  const fs::path vtu = dir.path / "solution.vtu";
  const fs::path report = dir.path / "meshio.txt";
  // meshio reads the file with its own VTU parser and prints what it found
  const std::string script =
      "import meshio, numpy as np\n"
      "m = meshio.read('" + vtu.string() + "')\n"
      "cells = sum(len(b.data) for b in m.cells)\n"
      "types = sorted(set(b.type for b in m.cells))\n"
      "d = m.point_data['displacement']\n"
      "s = np.concatenate(m.cell_data['stress'])\n"
      "vm = np.concatenate(m.cell_data['von_mises'])\n"
      "r = np.concatenate(m.cell_data['region'])\n"
      "with open('" + report.string() + "', 'w') as f:\n"
      "    f.write('%d %d %d %d\\n' % (len(m.points), m.points.shape[1], cells, d.shape[1]))\n"
      "    f.write('%d %d %d\\n' % (s.shape[1], len(vm), len(r)))\n"
      "    f.write(','.join(types) + '\\n')\n"
      "    f.write('%.17g\\n' % abs(m.points[:, 2]).max())\n"
      "    for row in d: f.write('%.17g %.17g %.17g\\n' % tuple(row))\n"
      "    for v in vm: f.write('%.17g\\n' % v)\n"
      "    for row in s: f.write(' '.join('%.17g' % x for x in row) + '\\n')\n"
      "    for x in r: f.write('%d\\n' % x)\n"
      "    c = np.concatenate(m.cell_data['contact'])\n"
      "    f.write('%d %d\\n' % (len(c), c.sum()))\n"
      "    for k in ('u_nu', 'pressure', 'gap'):\n"
      "        for x in m.point_data[k]: f.write('%.17g\\n' % x)\n";
  const fs::path py = dir.path / "read.py";
  std::ofstream(py) << script;
  ASSERT_EQ(std::system((python + " '" + py.string() + "' 2>'" + (dir.path / "err.txt").string() + "'").c_str()), 0)
      << slurp(dir.path / "err.txt");

  std::ifstream in(report);
  const int nv = s.mesh.num_vertices(), ne = s.mesh.num_elements();
  int points = 0, dim = 0, cells = 0, components = 0, stress_components = 0, vm_count = 0, region_count = 0;
  in >> points >> dim >> cells >> components >> stress_components >> vm_count >> region_count;
  // Gamma_3 as line cells after the elements: on 8 x 8 squares the 7 contact nodes of the
  // bottom (the corners are clamped) are joined by 6 edges
  const int nl = 6;
  ASSERT_EQ(s.solution.contact.size(), 7u);
  EXPECT_EQ(points, nv);
  EXPECT_EQ(dim, 3);
  EXPECT_EQ(cells, ne + nl);
  EXPECT_EQ(components, 3);
  EXPECT_EQ(stress_components, 6);
  EXPECT_EQ(vm_count, ne + nl);
  EXPECT_EQ(region_count, ne + nl);
  std::string types;
  in >> types;
  EXPECT_EQ(types, "line,polygon");  // VTK_POLYGON and VTK_LINE cells
  double zmax = -1;
  in >> zmax;
  EXPECT_EQ(zmax, 0.0);
  for (int v = 0; v < nv; ++v) {
    double ux = 0, uy = 0, uz = 1;
    in >> ux >> uy >> uz;
    ASSERT_TRUE(in);
    EXPECT_EQ(ux, s.solution.u(2 * v)) << v;
    EXPECT_EQ(uy, s.solution.u(2 * v + 1)) << v;
    EXPECT_EQ(uz, 0.0);
  }
  const auto stresses = element_stresses(s.mesh, s.problem.elasticity.materials, s.solution.u);
  for (int e = 0; e < ne + nl; ++e) {
    double vm = -1;
    in >> vm;
    if (e < ne) EXPECT_NEAR(vm, stresses[static_cast<std::size_t>(e)].von_mises(), 1e-12 * (1 + vm)) << e;
    else EXPECT_EQ(vm, 0.0) << "a line cell has no stress";
  }
  for (int e = 0; e < ne + nl; ++e) {
    double c[6] = {};
    for (double& x : c) in >> x;
    ASSERT_TRUE(in);
    if (e >= ne) {
      for (double x : c) EXPECT_EQ(x, 0.0);
      continue;
    }
    const auto& expected = stresses[static_cast<std::size_t>(e)];
    const double scale = 1e-12 * (1 + expected.von_mises());
    EXPECT_NEAR(c[0], expected.xx, scale) << e;
    EXPECT_NEAR(c[1], expected.yy, scale) << e;
    EXPECT_NEAR(c[2], expected.zz, scale) << e;
    EXPECT_NEAR(c[3], expected.xy, scale) << e;
    EXPECT_EQ(c[4], 0.0);
    EXPECT_EQ(c[5], 0.0);
  }
  for (int e = 0; e < ne + nl; ++e) {
    int region = 0;
    in >> region;
    EXPECT_EQ(region, e < ne ? s.mesh.region(e) : -1) << e;
  }
  int contact_cells = 0, marked = 0;
  in >> contact_cells >> marked;
  EXPECT_EQ(contact_cells, ne + nl);
  EXPECT_EQ(marked, nl);
  // u_nu, pressure and gap at the contact nodes, 0 elsewhere
  for (int k = 0; k < 3; ++k) {
    std::vector<double> field(static_cast<std::size_t>(nv), -1.0);
    for (double& x : field) in >> x;
    ASSERT_TRUE(in);
    std::vector<double> expected(static_cast<std::size_t>(nv), 0.0);
    for (const auto& n : s.solution.contact)
      expected[static_cast<std::size_t>(n.vertex)] = k == 0 ? n.u_nu : (k == 1 ? n.pressure() : n.gap);
    EXPECT_EQ(field, expected) << (k == 0 ? "u_nu" : (k == 1 ? "pressure" : "gap"));
  }
}

TEST(OutputStress, PlaneStrainVonMisesIncludesSigmaZz) {
  // a uniform strain eps_xx = 1e-3: sigma_xx = (lambda + 2 mu) e, sigma_yy = sigma_zz = lambda e
  const Mesh mesh = make_squares(2);
  Eigen::VectorXd u(2 * mesh.num_vertices());
  for (int v = 0; v < mesh.num_vertices(); ++v) u.segment<2>(2 * v) = Vec2(1e-3 * mesh.vertex(v).x(), 0.0);
  const Material mat{1000.0, 0.3};
  for (PlaneModel model : {PlaneModel::strain, PlaneModel::stress}) {
    const MaterialTable table(mat, model);
    const Lame l = lame(mat, model);
    const auto s = element_stresses(mesh, table, u);
    ASSERT_EQ(s.size(), static_cast<std::size_t>(mesh.num_elements()));
    const double xx = (l.lambda + 2 * l.mu) * 1e-3, yy = l.lambda * 1e-3;
    const double zz = model == PlaneModel::strain ? yy : 0.0;
    for (const auto& e : s) {
      EXPECT_NEAR(e.xx, xx, 1e-12);
      EXPECT_NEAR(e.yy, yy, 1e-12);
      EXPECT_NEAR(e.zz, zz, 1e-12);
      EXPECT_NEAR(e.xy, 0.0, 1e-12);
      const double vm = std::sqrt(0.5 * ((xx - yy) * (xx - yy) + (yy - zz) * (yy - zz) + (zz - xx) * (zz - xx)));
      EXPECT_NEAR(e.von_mises(), vm, 1e-12);
    }
  }
}

TEST_F(Outputs, CellStressesOfAPlaneAreItsElementStresses) {
  // solution.vtu's stress and von_mises of a plane are element_stresses', bit for bit
  const Solved& s = solved();
  const auto elements = element_stresses(s.mesh, s.problem.elasticity.materials, s.solution.u);
  const std::vector<CellStress> cells = cell_stresses(s.mesh, s.problem.elasticity.materials, s.solution.u);
  ASSERT_EQ(cells.size(), elements.size());
  for (std::size_t e = 0; e < cells.size(); ++e) {
    EXPECT_EQ(cells[e].xx, elements[e].xx);
    EXPECT_EQ(cells[e].yy, elements[e].yy);
    EXPECT_EQ(cells[e].zz, elements[e].zz);
    EXPECT_EQ(cells[e].xy, elements[e].xy);
    EXPECT_EQ(cells[e].yz, 0.0);
    EXPECT_EQ(cells[e].xz, 0.0);
    EXPECT_EQ(cells[e].von_mises(), elements[e].von_mises()) << e;
  }
  EXPECT_THROW((void)cell_stresses(s.mesh, s.problem.elasticity.materials, Eigen::VectorXd::Zero(3)), InputError);
}

TEST_F(Outputs, StressPeakIsTheFirstCellOfTheLargestVonMisesStress) {
  const Solved& s = solved();
  std::vector<CellStress> cells = cell_stresses(s.mesh, s.problem.elasticity.materials, s.solution.u);
  std::size_t largest = 0;
  for (std::size_t e = 1; e < cells.size(); ++e)
    if (cells[e].von_mises() > cells[largest].von_mises()) largest = e;
  const std::optional<StressPeak> peak = stress_peak(s.mesh, cells);
  ASSERT_TRUE(peak.has_value());
  EXPECT_EQ(peak->cell, static_cast<int>(largest));
  EXPECT_EQ(peak->von_mises, cells[largest].von_mises());
  EXPECT_EQ(peak->centroid, (std::vector<double>{s.mesh.centroid(peak->cell).x(), s.mesh.centroid(peak->cell).y()}));
  // a tie goes to the first cell; a value that is not finite leaves no peak
  std::vector<CellStress> tie = cells;
  const std::size_t later = largest + 1 < tie.size() ? largest + 1 : 0;
  tie[later] = tie[largest];
  EXPECT_EQ(stress_peak(s.mesh, tie)->cell, static_cast<int>(std::min(largest, later)));
  cells[cells.size() / 2].xx = std::numeric_limits<double>::quiet_NaN();
  EXPECT_FALSE(stress_peak(s.mesh, cells).has_value());
  cells.pop_back();
  EXPECT_THROW((void)stress_peak(s.mesh, cells), InputError);
}

TEST(OutputNames, EachDimensionKnowsItsOwnFilesAndBothShareTheRest) {
  const std::vector<std::string>& plane = all_outputs(2);
  const std::vector<std::string>& solid = all_outputs(3);
  auto has = [](const std::vector<std::string>& names, const std::string& name) {
    return std::find(names.begin(), names.end(), name) != names.end();
  };
  for (const char* both : {"result.json", "contact.csv", "displacement.csv", "stress.csv", "history.csv", "solution.vtu",
                           "scene.toml", "deformed.png", "adapt.png", "adapt.pvd", "path.json", "solution.pvd", "path.png"})
    EXPECT_TRUE(has(plane, both) && has(solid, both)) << both;
  for (const char* own : {"mesh.poly2d", "u_nu.png", "error.png", "mesh.png"})
    EXPECT_TRUE(has(plane, own) && !has(solid, own)) << own;
  for (const char* own : {"contact-surface.vtu", "pressure.png"}) EXPECT_TRUE(has(solid, own) && !has(plane, own)) << own;
  EXPECT_EQ(plane.front(), "result.json");
  EXPECT_EQ(solid.back(), "path.png");
  EXPECT_THROW((void)all_outputs(1), InputError);
}

TEST_F(Outputs, PlotsArePngsMadeByGnuplot) {
  if (!have_gnuplot()) GTEST_SKIP() << "gnuplot is not on PATH";
  const Solved& s = solved();
  ScratchDir dir("png");
  const OutputReport report =
      write_outputs(dir.path, s.mesh, s.problem.elasticity.materials, s.solution, s.info, {"u_nu.png", "deformed.png"});
  EXPECT_TRUE(report.skipped.empty()) << report.skipped.front();
  for (const char* name : {"u_nu.png", "deformed.png"}) {
    const std::string data = slurp(dir.path / name);
    ASSERT_GT(data.size(), 8u) << name;
    EXPECT_EQ(data.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8)) << name;
  }
  // nothing but the plots
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator()), 2);
}

// What the figures say: the scene and the mesh in the title, units on every axis, the gap
// and the law's breakpoints in u_nu.png; the undeformed outline and the foundation in
// deformed.png; x for a straight horizontal contact boundary, the arc length otherwise.
TEST_F(Outputs, FiguresNameTheirSceneMeshUnitsAndReferenceLines) {
  const Solved& s = solved();
  RunInfo info = s.info;
  info.scene_name = "Example 4.1";
  info.law_breakpoints = {0.0, 0.01, 0.02, 5.0};  // 5 is far from every value shown
  info.gap_bound = true;
  const Figure u = u_nu_figure(s.mesh, s.solution, info);
  EXPECT_EQ(u.png, "u_nu.png");
  EXPECT_NE(u.script.find("contact boundary\\nExample 4.1, squares n=8\" noenhanced"), std::string::npos) << u.script;
  EXPECT_NE(u.script.find("set xlabel 'x (scene units)'"), std::string::npos) << u.script;
  EXPECT_NE(u.script.find("u_{/Symbol n} (scene units)'"), std::string::npos);
  EXPECT_NE(u.script.find("set y2label 'contact pressure (force per unit length, scene units"), std::string::npos);
  EXPECT_NE(u.script.find("title 'gap g (u_{/Symbol n} <= g)'"), std::string::npos);
  for (const char* b : {"'law breakpoint 0'", "'law breakpoint 0.01'", "'law breakpoint 0.02'"})
    EXPECT_NE(u.script.find(b), std::string::npos) << b;
  // labels in 6 significant digits (-5e-4 is -0.0005000000000000001 in 17)
  info.law_breakpoints = {-5e-4};
  EXPECT_NE(u_nu_figure(s.mesh, s.solution, info).script.find("'law breakpoint -0.0005'"), std::string::npos);
  info.law_breakpoints = {0.0, 0.01, 0.02, 5.0};
  EXPECT_EQ(u.script.find("law breakpoint 5"), std::string::npos);
  const Figure d = deformed_figure(s.mesh, s.solution, info);
  EXPECT_NE(d.script.find("'outline.dat' using 1:2 with lines"), std::string::npos) << d.script;
  EXPECT_NE(d.script.find("title 'undeformed'"), std::string::npos);
  EXPECT_NE(d.script.find("'foundation.dat'"), std::string::npos);
  for (const char* label : {"set xlabel 'x (scene units)'", "set ylabel 'y (scene units)'", "set cblabel '|u| (scene units)'"})
    EXPECT_NE(d.script.find(label), std::string::npos) << label;
  // the foundation lies where u_nu = g, magnified as the displacement: a node at its bound is
  // drawn on it, every other node above it
  auto points = [&](const std::string& name) {
    std::ostringstream data;
    for (const auto& f : d.data)
      if (f.name == name) f.write(data);
    std::istringstream rows(data.str());
    std::string header;
    std::getline(rows, header);
    std::vector<Vec2> out;
    for (double x = 0, y = 0; rows >> x >> y;) out.emplace_back(x, y);
    return out;
  };
  const std::vector<Vec2> foundation = points("foundation.dat"), nodes = points("contact.dat");
  ASSERT_EQ(foundation.size(), s.solution.contact.size());
  ASSERT_EQ(nodes.size(), s.solution.contact.size());
  int touching = 0;
  for (std::size_t i = 0; i < nodes.size(); ++i) {
    const auto& n = s.solution.contact[i];
    const auto below = std::find_if(foundation.begin(), foundation.end(), [&](const Vec2& q) { return q.x() == n.x.x(); });
    ASSERT_NE(below, foundation.end()) << "no foundation point below node " << n.vertex;
    EXPECT_LT(below->y(), n.x.y());
    if (n.state == ContactState::at_gap) {
      ++touching;
      EXPECT_NEAR(nodes[i].y(), below->y(), 1e-12) << n.vertex;
    } else {
      EXPECT_GT(nodes[i].y(), below->y()) << n.vertex;
    }
  }
  EXPECT_GT(touching, 0);
  // a contact boundary that is not one horizontal line: against its arc length
  ContactSolution bent = s.solution;
  bent.contact.front().x.y() += 0.1;
  EXPECT_NE(u_nu_figure(s.mesh, bent, info).script.find("set xlabel 'arc length s along the contact boundary"),
            std::string::npos);
  // without a constraint there is no foundation and no gap line
  info.gap_bound = false;
  EXPECT_EQ(deformed_figure(s.mesh, s.solution, info).script.find("foundation"), std::string::npos);
  EXPECT_EQ(u_nu_figure(s.mesh, s.solution, info).script.find("gap g"), std::string::npos);
}

TEST_F(Outputs, MissingGnuplotSkipsThePlotsOnly) {
  const Solved& s = solved();
  ScratchDir dir("nognuplot");
  const char* old = std::getenv("PATH");
  const std::string saved = old ? old : "";
  ::setenv("PATH", (dir.path / "empty-bin").c_str(), 1);
  OutputReport report;
  try {
    report = write_outputs(dir.path / "out", s.mesh, s.problem.elasticity.materials, s.solution, s.info);
  } catch (...) {
    ::setenv("PATH", saved.c_str(), 1);
    throw;
  }
  ::setenv("PATH", saved.c_str(), 1);
  // u_nu.png, deformed.png and mesh.png for want of gnuplot; error.png without an estimate,
  // adapt.png and adapt.pvd without an adaptive solve and the five files of a loading path for
  // want of data
  ASSERT_EQ(report.skipped.size(), 11u);
  const auto skipped = [&](const std::string& file, const std::string& why) {
    return std::any_of(report.skipped.begin(), report.skipped.end(), [&](const std::string& s) {
      return s.rfind(file + ": ", 0) == 0 && s.find(why) != std::string::npos;
    });
  };
  EXPECT_TRUE(skipped("u_nu.png", "gnuplot"));
  EXPECT_TRUE(skipped("deformed.png", "gnuplot"));
  EXPECT_TRUE(skipped("mesh.png", "gnuplot"));
  EXPECT_TRUE(skipped("error.png", "no error estimate"));
  EXPECT_TRUE(skipped("adapt.png", "not an adaptive solve"));
  EXPECT_TRUE(skipped("adapt.pvd", "not an adaptive solve"));
  for (const char* file : {"path.json", "path-contact.csv", "path-displacement.csv", "solution.pvd", "path.png"})
    EXPECT_TRUE(skipped(file, "not a loading path")) << file;
  EXPECT_EQ(report.written.size(), all_outputs(2).size() - 11);
  for (const char* name : {"result.json", "contact.csv", "displacement.csv", "history.csv", "solution.vtu", "scene.toml"})
    EXPECT_TRUE(fs::exists(dir.path / "out" / name)) << name;
  EXPECT_FALSE(fs::exists(dir.path / "out" / "u_nu.png"));
}

TEST_F(Outputs, AFolderThatIsAFileThrowsAndWritesNothing) {
  const Solved& s = solved();
  ScratchDir dir("notafolder");
  const fs::path file = dir.path / "out";
  std::ofstream(file) << "a file\n";
  EXPECT_THROW(write_outputs(file, s.mesh, s.problem.elasticity.materials, s.solution, s.info), InputError);
  EXPECT_EQ(slurp(file), "a file\n");
  EXPECT_EQ(std::distance(fs::directory_iterator(dir.path), fs::directory_iterator()), 1);
}

TEST_F(Outputs, AFailedFileLeavesNoTemporaryBehind) {
  const Solved& s = solved();
  ScratchDir dir("blocked");
  fs::create_directories(dir.path / "contact.csv" / "inside");  // the name is taken by a folder
  EXPECT_THROW(write_outputs(dir.path, s.mesh, s.problem.elasticity.materials, s.solution, s.info), InputError);
  // the outputs are one transaction: the folder is as it was, and nothing is left beside it
  std::vector<std::string> names;
  for (const auto& entry : fs::directory_iterator(dir.path)) names.push_back(entry.path().filename().string());
  EXPECT_EQ(names, (std::vector<std::string>{"contact.csv"}));
  EXPECT_TRUE(fs::is_directory(dir.path / "contact.csv" / "inside"));
  const std::string beside = "." + dir.path.filename().string() + ".hemivem-";
  for (const auto& entry : fs::directory_iterator(dir.path.parent_path()))
    EXPECT_NE(entry.path().filename().string().rfind(beside, 0), 0u) << entry.path();
}

TEST_F(Outputs, UnknownOutputNameIsAnInputErrorBeforeAnyWrite) {
  const Solved& s = solved();
  ScratchDir dir("unknown");
  EXPECT_THROW(write_outputs(dir.path / "out", s.mesh, s.problem.elasticity.materials, s.solution, s.info,
                             {"result.json", "solution.vtk"}),
               InputError);
  EXPECT_FALSE(fs::exists(dir.path / "out"));
}

TEST(OutputsWithoutContact, LinearSolveSkipsTheContactPlotOnly) {
  const Mesh mesh = make_squares(4);
  ContactProblem p = example_4_1(mesh);
  p.parts.clear();
  FactorizationOptions f;
  f.engine = "eigen";
  struct Unused final : NonsmoothMinimizer {
    std::string name() const override { return "unused"; }
   protected:
    MinimizerResult run(MinimizerRun&) const override {
      return {};
    }
  } unused;
  const ContactSolution sol = solve_contact(p, make_factorization(f), unused, MinimizerOptions{});
  ASSERT_TRUE(sol.contact.empty());
  const json j = json::parse(result_json(mesh, sol, RunInfo{}).dump());
  EXPECT_TRUE(j.at("uniqueness_margin").is_null());
  EXPECT_TRUE(j.at("contact").is_array());
  EXPECT_TRUE(j.at("contact").empty());
  EXPECT_EQ(j.at("stages"), json({"assembly", "linear_solve"}));
  EXPECT_EQ(j.at("timings").at("minimize").get<double>(), 0.0);
  EXPECT_TRUE(j.at("timings").contains("linear_solve"));

  ScratchDir dir("nocontact");
  const OutputReport report = write_outputs(dir.path, mesh, p.elasticity.materials, sol, RunInfo{});
  EXPECT_EQ(lines(dir.path / "contact.csv").size(), 1u);  // the header only
  EXPECT_TRUE(fs::exists(dir.path / "solution.vtu"));
  EXPECT_FALSE(fs::exists(dir.path / "u_nu.png"));
  ASSERT_FALSE(report.skipped.empty());
  EXPECT_TRUE(std::any_of(report.skipped.begin(), report.skipped.end(),
                          [](const std::string& s) { return s.rfind("u_nu.png: no contact boundary", 0) == 0; }))
      << report.skipped[0];
  if (have_gnuplot()) {  // and error.png (no estimate given), adapt.png and adapt.pvd (not an
                         // adaptive solve) and the five files of a loading path (not a loading path)
    EXPECT_EQ(report.skipped.size(), 9u);
    EXPECT_TRUE(fs::exists(dir.path / "deformed.png"));
  }
}

}  // namespace
