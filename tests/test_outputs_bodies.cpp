// The output folder of a scene of several bodies ([[body]], docs/two-bodies.md): besides
// solution.vtu, one solution.body-NAME.vtu per body and solution.vtm, the multiblock dataset
// naming them (docs/reference/outputs.md). The shipped scenes two-blocks.toml and
// two-boxes-3d.toml are solved and written as the command writes them; every body's file is read
// back here (its binary arrays decoded) and checked against displacement.csv, stress.csv and
// result.json, which are written by other code; a later run that writes no VTU leaves none.
// Last, the shares of solution.vtu that processes write as the pieces of solution.pvtu.
#include <hemivem/app/run.hpp>
#include <hemivem/app/solve.hpp>
#include <hemivem/app/solve3d.hpp>
#include <hemivem/app/vtu.hpp>
#include <hemivem/error.hpp>
#include <hemivem/mesh/vertex_order.hpp>
#include <hemivem/scene/scene.hpp>

#include <nlohmann/json.hpp>
#include <gtest/gtest.h>

#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <regex>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include "test_support.hpp"
#include "vtu_arrays.hpp"

using namespace hemivem;
namespace fs = std::filesystem;

namespace {

// ---- a small reader of the VTU files hemivem writes (binary, zlib, UInt64 headers) ----------

/// A VTU file: its piece's sizes, and each DataArray's section (Points, Cells, PointData,
/// CellData), components and decoded bytes, by name.
struct Vtu {
  struct Array {
    std::string section;
    int components = 1;
    std::vector<unsigned char> bytes;
  };
  std::size_t points = 0, cells = 0;
  std::map<std::string, Array> arrays;
  std::vector<std::string> order;  ///< the arrays' names in the file's order

  template <class T>
  std::vector<T> values(const std::string& name) const {
    const auto it = arrays.find(name);
    if (it == arrays.end()) {
      ADD_FAILURE() << "no array " << name;
      return {};
    }
    std::vector<T> out(it->second.bytes.size() / sizeof(T));
    std::memcpy(out.data(), it->second.bytes.data(), out.size() * sizeof(T));
    return out;
  }
};


Vtu read_vtu(const fs::path& file) {
  const std::string xml = test::slurp(file);
  Vtu vtu;
  std::smatch m;
  EXPECT_TRUE(std::regex_search(xml, m, std::regex("<VTKFile type=\"UnstructuredGrid\""))) << file;
  if (!std::regex_search(xml, m, std::regex("<Piece NumberOfPoints=\"([0-9]+)\" NumberOfCells=\"([0-9]+)\">"))) {
    ADD_FAILURE() << file << ": no Piece";
    return vtu;
  }
  vtu.points = std::stoul(m[1]);
  vtu.cells = std::stoul(m[2]);
  const std::regex element("<(Points|Cells|PointData|CellData)[ >]|<DataArray type=\"[A-Za-z0-9]+\" Name=\"([A-Za-z_]+)\""
                           "(?: NumberOfComponents=\"([0-9]+)\")? format=\"binary\">([^<]*)</DataArray>");
  std::string section;
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), element); it != std::sregex_iterator(); ++it) {
    const std::smatch& e = *it;
    if (e[1].matched) {
      section = e[1];
      continue;
    }
    Vtu::Array a{section, e[3].matched ? std::stoi(e[3]) : 1, hemivem::test::decode_vtu_array(e[4])};
    vtu.order.push_back(e[2]);
    vtu.arrays[e[2]] = std::move(a);
  }
  return vtu;
}

/// The DataSet entries of a .vtm: index, name, file.
struct Block {
  int index;
  std::string name, file;
  bool operator==(const Block&) const = default;
};
std::ostream& operator<<(std::ostream& os, const Block& b) { return os << b.index << " " << b.name << " " << b.file; }

std::vector<Block> read_vtm(const fs::path& file) {
  const std::string xml = test::slurp(file);
  EXPECT_NE(xml.find("<VTKFile type=\"vtkMultiBlockDataSet\""), std::string::npos) << xml;
  EXPECT_NE(xml.find("<vtkMultiBlockDataSet>"), std::string::npos) << xml;
  std::vector<Block> blocks;
  const std::regex entry("<DataSet index=\"([0-9]+)\" name=\"([^\"]*)\" file=\"([^\"]*)\"/>");
  for (auto it = std::sregex_iterator(xml.begin(), xml.end(), entry); it != std::sregex_iterator(); ++it)
    blocks.push_back({std::stoi((*it)[1]), (*it)[2], (*it)[3]});
  return blocks;
}

/// A CSV file's header and rows of cells.
struct Csv {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;
  std::size_t column(const std::string& name) const {
    const auto it = std::find(header.begin(), header.end(), name);
    EXPECT_NE(it, header.end()) << name;
    return static_cast<std::size_t>(it - header.begin());
  }
};
Csv read_csv(const fs::path& file) {
  std::ifstream in(file);
  Csv csv;
  auto split = [](const std::string& line) {
    std::vector<std::string> cells;
    std::stringstream ss(line);
    for (std::string cell; std::getline(ss, cell, ',');) cells.push_back(cell);
    return cells;
  };
  std::string line;
  std::getline(in, line);
  csv.header = split(line);
  while (std::getline(in, line)) csv.rows.push_back(split(line));
  return csv;
}

std::set<std::string> folder(const fs::path& dir) {
  std::set<std::string> names;
  for (const auto& e : fs::directory_iterator(dir)) names.insert(e.path().filename().string());
  return names;
}

Scene scene_of(const std::string& file) { return parse_scene(test::scenes_dir() / file); }

/// Solves `scene` and writes its folder `dir` as `hemivem solve --out dir` does.
app::OutputReport solve_into(const Scene& scene, const fs::path& dir) {
  const app::SceneRun run = app::run_scene(scene);
  EXPECT_TRUE(run.converged());
  return run.write(dir);
}

/// Every body's file of the folder `dir` of a scene of `dim` dimensions: listed in solution.vtm
/// and result.json, its points, cells and arrays those of its part of the mesh, its
/// displacement the body's rows of displacement.csv, its stress its cells' rows of stress.csv.
void expect_a_vtu_per_body(const fs::path& dir, int dim, const std::vector<std::string>& names) {
  const nlohmann::json r = nlohmann::json::parse(test::slurp(dir / "result.json"));
  ASSERT_TRUE(r["bodies"].is_array());
  ASSERT_EQ(r["bodies"].size(), names.size());
  // solution.vtm names one file per body, by the body's name, in the scene's order
  std::vector<Block> expected;
  for (std::size_t b = 0; b < names.size(); ++b)
    expected.push_back({static_cast<int>(b), names[b], "solution.body-" + names[b] + ".vtu"});
  EXPECT_EQ(read_vtm(dir / "solution.vtm"), expected);
  // result.json lists them after solution.vtu, then solution.vtm
  const auto files = r["files"].get<std::vector<std::string>>();
  const auto at = std::find(files.begin(), files.end(), "solution.vtu");
  ASSERT_NE(at, files.end());
  std::vector<std::string> after(at + 1, at + 1 + std::min<std::ptrdiff_t>(files.end() - at - 1, names.size() + 1));
  std::vector<std::string> listed;
  for (const auto& e : expected) listed.push_back(e.file);
  listed.push_back("solution.vtm");
  EXPECT_EQ(after, listed);
  for (const auto& f : files) EXPECT_TRUE(fs::exists(dir / f)) << f;

  const Csv displacement = read_csv(dir / "displacement.csv");
  const Csv stress = read_csv(dir / "stress.csv");
  const Vtu whole = read_vtu(dir / "solution.vtu");
  // solution.vtu still holds every body
  EXPECT_EQ(whole.points, displacement.rows.size());
  const std::vector<double> all = whole.values<double>("displacement");
  ASSERT_EQ(all.size(), 3 * displacement.rows.size());
  const char* axes[] = {"ux", "uy", "uz"};
  const char* coordinates[] = {"x", "y", "z"};
  const std::size_t body_column = displacement.column("body");
  std::size_t polygons_and_lines = 0;
  for (std::size_t b = 0; b < names.size(); ++b) {
    SCOPED_TRACE(names[b]);
    const nlohmann::json& range = r["bodies"][b];
    ASSERT_EQ(range["name"], names[b]);
    const Vtu vtu = read_vtu(dir / expected[b].file);
    // its points and cells
    const auto vertices = range["vertices"].get<std::size_t>(), cells = range["cells"].get<std::size_t>();
    EXPECT_EQ(vtu.points, vertices);
    const std::vector<std::uint8_t> types = vtu.values<std::uint8_t>("types");
    EXPECT_EQ(types.size(), vtu.cells);
    EXPECT_EQ(static_cast<std::size_t>(std::count(types.begin(), types.end(), dim == 2 ? 7 : 42)), cells);
    if (dim == 3) EXPECT_EQ(vtu.cells, cells);  // no line cells in a solid's file
    polygons_and_lines += vtu.cells;
    // numbered from 0
    for (std::int64_t v : vtu.values<std::int64_t>("connectivity")) {
      EXPECT_GE(v, 0);
      EXPECT_LT(v, static_cast<std::int64_t>(vertices));
    }
    // the same arrays as solution.vtu, in the same order
    EXPECT_EQ(vtu.order, whole.order);
    // the body's rows of displacement.csv, in order: positions and displacements, the same doubles
    std::vector<const std::vector<std::string>*> rows;
    for (const auto& row : displacement.rows)
      if (row.size() > body_column && row[body_column] == names[b]) rows.push_back(&row);
    ASSERT_EQ(rows.size(), vertices);
    const std::vector<double> u = vtu.values<double>("displacement"), x = vtu.values<double>("Points");
    ASSERT_EQ(u.size(), 3 * vertices);
    ASSERT_EQ(x.size(), 3 * vertices);
    for (std::size_t v = 0; v < vertices; ++v) {
      EXPECT_EQ(std::stol((*rows[v])[0]), range["first_vertex"].get<long>() + static_cast<long>(v));
      for (int c = 0; c < 3; ++c) {
        const double csv_u = c < dim ? std::stod((*rows[v])[displacement.column(axes[c])]) : 0.0;
        const double csv_x = c < dim ? std::stod((*rows[v])[displacement.column(coordinates[c])]) : 0.0;
        EXPECT_EQ(u[3 * v + static_cast<std::size_t>(c)], csv_u) << "vertex " << v << " component " << c;
        EXPECT_EQ(x[3 * v + static_cast<std::size_t>(c)], csv_x) << "vertex " << v << " coordinate " << c;
      }
    }
    // its cells' stresses: the rows first_cell ... of stress.csv (von Mises), and its regions
    const auto first_cell = range["first_cell"].get<std::size_t>();
    const std::vector<double> von_mises = vtu.values<double>("von_mises");
    ASSERT_EQ(von_mises.size(), vtu.cells);
    for (std::size_t c = 0; c < cells; ++c)
      EXPECT_EQ(von_mises[c], std::stod(stress.rows[first_cell + c][stress.column("von_mises")])) << "cell " << c;
    const std::vector<std::int32_t> region = vtu.values<std::int32_t>("region"), all_regions = whole.values<std::int32_t>("region");
    for (std::size_t c = 0; c < cells; ++c) EXPECT_EQ(region[c], all_regions[first_cell + c]);
    // the contact values of its points: solution.vtu's, restricted
    const std::vector<double> u_nu = vtu.values<double>("u_nu"), all_u_nu = whole.values<double>("u_nu");
    ASSERT_EQ(u_nu.size(), vertices);
    for (std::size_t v = 0; v < vertices; ++v)
      EXPECT_EQ(u_nu[v], all_u_nu[range["first_vertex"].get<std::size_t>() + v]);
  }
  // the bodies' files together hold solution.vtu's cells, the contact lines of a plane included
  EXPECT_EQ(polygons_and_lines, whole.cells);
}

/// The scene with `output.write` = `outputs`.
Scene with_outputs(Scene scene, const std::string& outputs) {
  apply_override(scene, "output.write=" + outputs);
  return scene;
}

/// The scene's text with every `from` replaced by `to`.
std::string replaced(std::string text, const std::string& from, const std::string& to) {
  for (auto at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) text.replace(at, from.size(), to);
  return text;
}

}  // namespace

TEST(OutputsBodies, TwoBlocksWriteAVtuPerBodyAndAMultiblockNamingThem) {
  const fs::path dir = test::scratch("outputs-two-blocks");
  const app::OutputReport report = solve_into(scene_of("two-blocks.toml"), dir);
  const std::set<std::string> names = folder(dir);
  for (const char* f : {"solution.vtu", "solution.body-upper.vtu", "solution.body-lower.vtu", "solution.vtm"})
    EXPECT_EQ(names.count(f), 1u) << f;
  // the report names them as it names the rest
  std::vector<std::string> written;
  for (const auto& p : report.written) written.push_back(p.filename().string());
  EXPECT_NE(std::find(written.begin(), written.end(), "solution.body-lower.vtu"), written.end());
  expect_a_vtu_per_body(dir, 2, {"upper", "lower"});
  // the upper block's bottom is the contact: its line cells are in its file, none in the lower's
  const Vtu upper = read_vtu(dir / "solution.body-upper.vtu"), lower = read_vtu(dir / "solution.body-lower.vtu");
  const auto lines = [](const Vtu& v) {
    const auto t = v.values<std::uint8_t>("types");
    return std::count(t.begin(), t.end(), 3);
  };
  EXPECT_GT(lines(upper), 0);
  EXPECT_EQ(lines(lower), 0);
  const auto contact = upper.values<std::uint8_t>("contact");
  EXPECT_EQ(std::count(contact.begin(), contact.end(), 1), lines(upper));

  // a later run into the folder that writes no VTU leaves no body's file nor solution.vtm, nor
  // an earlier run's pieces of a body's file (written across processes); a file of the user's stays
  std::ofstream(dir / "notes.txt") << "mine\n";
  std::ofstream(dir / "solution.body-upper.piece-1.vtu") << "an earlier run's\n";
  const app::OutputReport again = solve_into(with_outputs(scene_of("two-blocks.toml"), R"(["result-json", "displacement-csv"])"), dir);
  EXPECT_EQ(folder(dir), (std::set<std::string>{"notes.txt", "result.json", "displacement.csv", "scene.toml"}));
  for (const char* f : {"solution.vtu", "solution.body-upper.vtu", "solution.body-lower.vtu", "solution.vtm",
                        "solution.body-upper.piece-1.vtu"})
    EXPECT_NE(std::find(again.removed.begin(), again.removed.end(), f), again.removed.end()) << f;
  const nlohmann::json r = nlohmann::json::parse(test::slurp(dir / "result.json"));
  EXPECT_EQ(r["files"], nlohmann::json({"result.json", "displacement.csv", "scene.toml"}));
  fs::remove_all(dir);
}

TEST(OutputsBodies, TwoBoxesWriteAPolyhedralVtuPerBody) {
  const fs::path dir = test::scratch("outputs-two-boxes");
  solve_into(with_outputs(scene_of("two-boxes-3d.toml"), R"(["result-json", "displacement-csv", "stress-csv", "vtu"])"), dir);
  expect_a_vtu_per_body(dir, 3, {"upper", "lower"});
  // each polyhedron's faces name the body's points, numbered from 0
  const Vtu lower = read_vtu(dir / "solution.body-lower.vtu");
  const std::vector<std::int64_t> faces = lower.values<std::int64_t>("faces");
  const std::vector<std::int64_t> ends = lower.values<std::int64_t>("faceoffsets");
  ASSERT_EQ(ends.size(), lower.cells);
  std::size_t k = 0;
  for (std::size_t c = 0; c < lower.cells; ++c) {
    const auto n = static_cast<std::size_t>(faces.at(k++));
    EXPECT_GE(n, 6u);  // cubes, the top faces of the upper layer cut where the bodies were matched
    for (std::size_t f = 0; f < n; ++f) {
      const auto m = static_cast<std::size_t>(faces.at(k++));
      for (std::size_t i = 0; i < m; ++i) {
        EXPECT_GE(faces.at(k), 0);
        EXPECT_LT(faces.at(k), static_cast<std::int64_t>(lower.points));
        ++k;
      }
    }
    EXPECT_EQ(static_cast<std::size_t>(ends[c]), k);
  }
  // the contact surface is one file, as before
  EXPECT_TRUE(fs::exists(dir / "contact-surface.vtu"));
  // renamed bodies: the earlier run's files of the old names go, the new ones come
  std::string text = test::slurp(test::scenes_dir() / "two-boxes-3d.toml");
  text = replaced(replaced(text, "\"upper", "\"top"), "\"lower", "\"0007");
  solve_into(with_outputs(parse_scene_string(text, "renamed.toml"), R"(["result-json", "displacement-csv", "stress-csv", "vtu"])"), dir);
  const std::set<std::string> names = folder(dir);
  EXPECT_EQ(names.count("solution.body-upper.vtu"), 0u);
  EXPECT_EQ(names.count("solution.body-lower.vtu"), 0u);
  expect_a_vtu_per_body(dir, 3, {"top", "0007"});
  // a body named like a path's frame does not name a frame's file
  EXPECT_EQ(names.count("solution-0007.vtu"), 0u);
  fs::remove_all(dir);
}

TEST(OutputsBodies, ASceneOfOneBodyWritesNoMultiblock) {
  const fs::path dir = test::scratch("outputs-one-body");
  solve_into(with_outputs(scene_of("signorini.toml"), R"(["vtu"])"), dir);
  EXPECT_EQ(folder(dir), (std::set<std::string>{"solution.vtu", "scene.toml"}));
  fs::remove_all(dir);
}

TEST(OutputsBodies, ABodyNameThatCannotNameAFileIsRefused) {
  const std::string text = test::slurp(test::scenes_dir() / "two-blocks.toml");
  auto refusal = [&](const std::string& lower) {
    return test::input_error_of([&] { parse_scene_string(replaced(text, "\"lower", "\"" + lower), "names.toml"); });
  };
  EXPECT_NE(refusal("lo wer").find("body[1].name"), std::string::npos) << refusal("lo wer");
  EXPECT_NE(refusal("lo/wer").find("letters, digits"), std::string::npos) << refusal("lo/wer");
  EXPECT_NE(refusal("l\xc3\xb6wer").find("letters, digits"), std::string::npos);
  // names that differ in case only would write one file where case is ignored
  EXPECT_NE(refusal("Upper").find("differ"), std::string::npos) << refusal("Upper");
  // a scene made in code is refused when written, before anything is
  Scene scene = scene_of("two-blocks.toml");
  scene.bodies[1].name = "lo/wer";
  scene.contact->against_body = "lo/wer";
  const fs::path dir = test::scratch("outputs-bad-name");
  const std::string message = test::input_error_of([&] { solve_into(scene, dir); });
  EXPECT_NE(message.find("solution.body-NAME.vtu"), std::string::npos) << message;
  EXPECT_FALSE(fs::exists(dir));
  fs::remove_all(dir);
}

// ---- one process's share of solution.vtu (solution.piece-K.vtu of solution.pvtu) ---------

/// The shares of three processes of the scene's solution.vtu (SolutionVtu::write_share of an
/// even split of the vertices) hold each of the whole file's cells once, with its cell data,
/// and at each of their points the whole file's point data at that point, bit for bit; with
/// `body`, the shares of the body's file (solution.body-NAME.piece-K.vtu) those of its file.
template <class Solved>
void expect_shares_make_the_whole(const Solved& s, const fs::path& dir, const BodyRange* body = nullptr) {
  const auto& mesh = s.built->mesh;
  const app::SolutionVtu vtu(mesh, s.built->problem.elasticity.materials, s.solution);
  fs::create_directories(dir);
  const auto write = [&](const std::string& name, const std::function<void(std::ostream&)>& body) {
    {
      std::ofstream os(dir / name, std::ios::binary);
      body(os);
    }
    return read_vtu(dir / name);
  };
  const Vtu whole = write("whole.vtu", [&](std::ostream& os) { body ? vtu.write(os, *body) : vtu.write(os); });
  ASSERT_GT(whole.cells, 0u);
  // the whole file's point data by the point's coordinates, its cells' by their data
  std::map<std::vector<double>, std::vector<double>> at;
  const std::vector<double> x = whole.values<double>("Points"), u = whole.values<double>("displacement");
  for (std::size_t p = 0; p < whole.points; ++p)
    at[{x[3 * p], x[3 * p + 1], x[3 * p + 2]}] = {u[3 * p], u[3 * p + 1], u[3 * p + 2]};
  const auto cells_of = [](const Vtu& v) {
    std::multiset<std::vector<double>> cells;
    const std::vector<double> stress = v.values<double>("stress"), vm = v.values<double>("von_mises");
    const std::vector<std::uint8_t> types = v.values<std::uint8_t>("types");
    for (std::size_t c = 0; c < v.cells; ++c)
      cells.insert({static_cast<double>(types[c]), stress[6 * c], stress[6 * c + 1], stress[6 * c + 2], stress[6 * c + 3],
                    stress[6 * c + 4], stress[6 * c + 5], vm[c]});
    return cells;
  };
  const int nv = mesh.num_vertices(), cut[] = {0, nv / 3, 2 * nv / 3, nv};
  // shares of the mesh's own order and of its Hilbert order (a mesh made whole, shared along it)
  for (const std::vector<int>& order : {std::vector<int>(), hilbert_vertex_order(mesh)}) {
    SCOPED_TRACE(order.empty() ? "the mesh's order" : "the Hilbert order");
    std::multiset<std::vector<double>> cells;
    for (int k = 0; k < 3; ++k) {
      SCOPED_TRACE("share " + std::to_string(k));
      const VertexShare mine{cut[k], cut[k + 1], order};
      const Vtu share =
          write("piece-" + std::to_string(k) + ".vtu", [&](std::ostream& os) { vtu.write_share(os, mine, body); });
      if (!body) {  // a share may hold none of a body's cells
        EXPECT_GT(share.cells, 0u);
      }
      EXPECT_EQ(share.order, whole.order);  // the same arrays, in the same order
      const std::vector<double> xs = share.values<double>("Points"), us = share.values<double>("displacement");
      for (std::size_t p = 0; p < share.points; ++p) {
        const auto it = at.find({xs[3 * p], xs[3 * p + 1], xs[3 * p + 2]});
        ASSERT_NE(it, at.end()) << "point " << p;
        EXPECT_EQ(it->second, (std::vector<double>{us[3 * p], us[3 * p + 1], us[3 * p + 2]})) << "point " << p;
      }
      for (const std::int64_t v : share.values<std::int64_t>("connectivity")) {
        EXPECT_GE(v, 0);
        EXPECT_LT(v, static_cast<std::int64_t>(share.points));
      }
      const auto of_share = cells_of(share);
      cells.insert(of_share.begin(), of_share.end());
    }
    EXPECT_EQ(cells, cells_of(whole));
  }
  // the pvtu names them and declares the whole file's arrays
  std::ostringstream pvtu;
  vtu.write_pieces(pvtu, {"piece-0.vtu", "piece-1.vtu", "piece-2.vtu"});
  for (const auto& name : whole.order)
    if (whole.arrays.at(name).section == "PointData" || whole.arrays.at(name).section == "CellData")
      EXPECT_NE(pvtu.str().find("Name=\"" + name + "\""), std::string::npos) << name;
  EXPECT_NE(pvtu.str().find("<Piece Source=\"piece-2.vtu\"/>"), std::string::npos) << pvtu.str();
  EXPECT_EQ(test::input_error_of([&] { std::ostringstream os; vtu.write_share(os, VertexShare{0, nv + 1, {}}); }),
            "the vertices 0 to " + std::to_string(nv) + " are not a share of a mesh of " + std::to_string(nv) + " vertices");
}

TEST(OutputsShares, APlanesSharesHoldEachPolygonAndContactLineOnce) {
  Scene scene = scene_of("paper-example-4.1.toml");
  scene.mesh.n = 8;
  scene.mesh.ny.reset();
  scene.solver.linear = "eigen";
  expect_shares_make_the_whole(app::solve_scene(scene), test::scratch("outputs-shares-plane"));
}

TEST(OutputsShares, EachBodysSharesHoldEachOfItsCellsAndContactLinesOnce) {
  for (const char* name : {"upper", "lower"}) {
    SCOPED_TRACE(name);
    Scene plane = scene_of("two-blocks.toml");
    plane.solver.linear = "eigen";
    const app::SceneSolve s = app::solve_scene(plane);
    const auto body = std::find_if(s.built->bodies.begin(), s.built->bodies.end(), [&](const BodyRange& b) { return b.name == name; });
    ASSERT_NE(body, s.built->bodies.end());
    expect_shares_make_the_whole(s, test::scratch("outputs-shares-body-plane"), &*body);
    Scene solid = scene_of("two-boxes-3d.toml");
    solid.solver.linear = "eigen";
    const app::SceneSolve3D s3 = app::solve_scene_3d(solid);
    expect_shares_make_the_whole(s3, test::scratch("outputs-shares-body-solid"), &s3.built->bodies.at(name == std::string("upper") ? 0 : 1));
  }
}

TEST(OutputsShares, ASolidsSharesHoldEachPolyhedronOnce) {
  Scene scene = scene_of("example-4.1-3d.toml");
  scene.mesh.n = 4;
  scene.mesh.ny.reset();
  scene.mesh.nz.reset();
  scene.solver.linear = "eigen";
  expect_shares_make_the_whole(app::solve_scene_3d(scene), test::scratch("outputs-shares-solid"));
}
