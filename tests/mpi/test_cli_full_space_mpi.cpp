// The hemivem command on the full-space route under mpiexec (docs/cluster.md): `solve --linear
// petsc-gamg` on two and three processes, each posing and solving its share, agrees with the
// condensed route on one process in every displacement; rank 0 alone prints and writes; what the
// route does not run across processes is refused by every process alike, with one message.
//
// "Rank 0 alone writes" is observed as in test_cli_mpi.cpp: mpiexec starts the ranks with
// different --out folders (MPMD), everything else on their command lines equal.
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <sstream>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/gmsh3d.hpp>
#include <hemivem/mesh/poly2d.hpp>

#include "command_mpi.hpp"
#include "gmsh_squares.hpp"
#include "stacked_bodies.hpp"
#include "test_support.hpp"
#include "vtu_arrays.hpp"

namespace {

namespace fs = std::filesystem;

using namespace hemivem::test::mpi;  // run, mpiexec, np, binary, count, CommandRun, slurp

fs::path scratch(const std::string& name) { return hemivem::test::mpi::scratch("full-space", name); }
std::string scene(const std::string& name) { return std::string(HEMIVEM_SOURCE_DIR) + "/scenes/" + name; }

/// The rows of a CSV file after its header, each as numbers (a field that is not one: NaN).
std::vector<std::vector<double>> numbers(const fs::path& csv) {
  std::istringstream in(slurp(csv));
  std::string line;
  std::getline(in, line);
  std::vector<std::vector<double>> rows;
  while (std::getline(in, line)) {
    std::vector<double> row;
    std::istringstream fields(line);
    for (std::string f; std::getline(fields, f, ',');) {
      try {
        row.push_back(std::stod(f));
      } catch (const std::exception&) {
        row.push_back(std::nan(""));
      }
    }
    rows.push_back(std::move(row));
  }
  return rows;
}

/// The largest difference of the columns `from`.. of two tables of the same shape, and the
/// largest magnitude in `b`'s.
std::pair<double, double> difference(const std::vector<std::vector<double>>& a, const std::vector<std::vector<double>>& b,
                                     std::size_t from, std::size_t to) {
  double diff = 0.0, scale = 0.0;
  EXPECT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < std::min(a.size(), b.size()); ++i)
    for (std::size_t c = from; c < to && c < a[i].size() && c < b[i].size(); ++c) {
      diff = std::max(diff, std::abs(a[i][c] - b[i][c]));
      scale = std::max(scale, std::abs(b[i][c]));
    }
  return {diff, scale};
}

/// The columns from..to-1 of the tables `a` and `b` agree to 1e-8 of `scale`, or (scale 0) of
/// the largest magnitude of those columns in `b`, which must not vanish; returns that magnitude.
double expect_columns_agree(const fs::path& a, const fs::path& b, std::size_t from, std::size_t to, double scale = 0.0) {
  SCOPED_TRACE(a.filename().string() + " columns " + std::to_string(from) + ".." + std::to_string(to - 1));
  const auto [diff, largest] = difference(numbers(a), numbers(b), from, to);
  if (scale == 0.0) {
    EXPECT_GT(largest, 0.0);
  }
  EXPECT_LE(diff, 1e-8 * (scale == 0.0 ? largest : scale));
  return largest;
}

/// The NumberOfCells of a VTU file.
int vtu_cells(const fs::path& file) {
  const std::string text = slurp(file);
  const std::size_t at = text.find("NumberOfCells=\"");
  if (at == std::string::npos) return -1;
  return std::stoi(text.substr(at + 15));
}

/// The values of the Float64 array `name` of a VTU file, decoded; empty without it.
std::vector<double> vtu_doubles(const fs::path& file, const std::string& name) {
  const std::string text = slurp(file);
  const std::size_t at = text.find("Name=\"" + name + "\"");
  if (at == std::string::npos) return {};
  const std::size_t from = text.find('>', at) + 1, to = text.find("</DataArray>", from);
  const std::vector<unsigned char> bytes = hemivem::test::decode_vtu_array(text.substr(from, to - from));
  std::vector<double> values(bytes.size() / sizeof(double));
  std::memcpy(values.data(), bytes.data(), values.size() * sizeof(double));
  return values;
}

/// The cells' values of the arrays `names` of the pieces `stem`.piece-K.vtu of `processes`
/// processes in `out` (decoded, sorted: each cell once), those of `whole_vtu` to 1e-7 of the
/// largest in magnitude.
void expect_values_of_pieces(const fs::path& out, const std::string& stem, const fs::path& whole_vtu, int processes,
                             const std::vector<std::string>& names) {
  for (const std::string& name : names) {
    std::vector<double> mine, whole = vtu_doubles(whole_vtu, name);
    for (int k = 0; k < processes; ++k) {
      const std::vector<double> piece = vtu_doubles(out / (stem + ".piece-" + std::to_string(k) + ".vtu"), name);
      mine.insert(mine.end(), piece.begin(), piece.end());
    }
    ASSERT_EQ(mine.size(), whole.size()) << name;
    ASSERT_FALSE(whole.empty()) << name;
    std::sort(mine.begin(), mine.end());
    std::sort(whole.begin(), whole.end());
    const double largest = std::max(std::abs(whole.front()), std::abs(whole.back()));
    for (std::size_t c = 0; c < whole.size(); ++c) EXPECT_NEAR(mine[c], whole[c], 1e-7 * largest) << name << " " << c;
  }
}

/// The pieces `stem`.piece-K.vtu of `processes` processes in `out`, named by `stem`.pvtu and
/// listed in `files` (result.json's) before it, in place of `stem`.vtu: each cell of the one
/// process's `whole` in one piece, and the cells' values of the arrays `names` (decoded,
/// sorted: each cell once) whole's to 1e-7 of the largest.
void expect_pieces_make_the_whole(const fs::path& out, const std::string& stem, const fs::path& whole_vtu, int processes,
                                  const std::vector<std::string>& names, const nlohmann::json& files) {
  SCOPED_TRACE(stem);
  const auto listed = [&](const std::string& file) {
    return static_cast<long>(std::find(files.begin(), files.end(), file) - files.begin());
  };
  EXPECT_FALSE(fs::exists(out / (stem + ".vtu")));
  EXPECT_EQ(listed(stem + ".vtu"), static_cast<long>(files.size())) << files.dump();
  const std::string pvtu = slurp(out / (stem + ".pvtu"));
  EXPECT_NE(pvtu.find("<VTKFile type=\"PUnstructuredGrid\""), std::string::npos) << pvtu;
  ASSERT_LT(listed(stem + ".pvtu"), static_cast<long>(files.size())) << files.dump();
  int written = 0;
  for (int k = 0; k < processes; ++k) {
    const std::string file = stem + ".piece-" + std::to_string(k) + ".vtu";
    EXPECT_NE(pvtu.find("<Piece Source=\"" + file + "\"/>"), std::string::npos) << pvtu;
    const int n = vtu_cells(out / file);
    EXPECT_GT(n, 0) << file;
    written += n;
    EXPECT_LT(listed(file), listed(stem + ".pvtu")) << files.dump();
  }
  EXPECT_FALSE(fs::exists(out / (stem + ".piece-" + std::to_string(processes) + ".vtu")));
  EXPECT_EQ(written, vtu_cells(whole_vtu));
  expect_values_of_pieces(out, stem, whole_vtu, processes, names);
}

/// The pieces solution.body-NAME.piece-K.vtu of `processes` processes in `out` of each body of
/// `bodies`, in place of solution.body-NAME.vtu (one process's files in `ref`): listed in
/// `files` (result.json's) before solution.vtm, which names them, each body a block of its
/// pieces; each cell of the body's whole file in one piece, and the cells' values of `names`
/// the whole file's (expect_values_of_pieces).
void expect_body_pieces_make_the_bodies(const fs::path& out, const fs::path& ref, int processes,
                                        const std::vector<std::string>& bodies, const std::vector<std::string>& names,
                                        const nlohmann::json& files) {
  const auto listed = [&](const std::string& file) {
    return static_cast<long>(std::find(files.begin(), files.end(), file) - files.begin());
  };
  const std::string vtm = slurp(out / "solution.vtm");
  ASSERT_LT(listed("solution.vtm"), static_cast<long>(files.size())) << files.dump();
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    const std::string stem = "solution.body-" + bodies[b];
    SCOPED_TRACE(stem);
    ASSERT_TRUE(fs::exists(ref / (stem + ".vtu")));
    EXPECT_FALSE(fs::exists(out / (stem + ".vtu")));
    EXPECT_EQ(listed(stem + ".vtu"), static_cast<long>(files.size())) << files.dump();
    const std::size_t block = vtm.find("<Piece index=\"" + std::to_string(b) + "\" name=\"" + bodies[b] + "\">");
    ASSERT_NE(block, std::string::npos) << vtm;
    int written = 0;
    for (int k = 0; k < processes; ++k) {
      const std::string file = stem + ".piece-" + std::to_string(k) + ".vtu";
      const std::size_t named = vtm.find("<DataSet index=\"" + std::to_string(k) + "\" file=\"" + file + "\"/>");
      EXPECT_TRUE(named != std::string::npos && named > block && named < vtm.find("</Piece>", block)) << vtm;
      written += std::max(vtu_cells(out / file), 0);
      EXPECT_LT(listed(file), listed("solution.vtm")) << files.dump();
    }
    EXPECT_FALSE(fs::exists(out / (stem + ".piece-" + std::to_string(processes) + ".vtu")));
    EXPECT_EQ(written, vtu_cells(ref / (stem + ".vtu")));
    expect_values_of_pieces(out, stem, ref / (stem + ".vtu"), processes, names);
  }
}

/// The names of result.json `result`'s bodies, in its order.
std::vector<std::string> body_names(const nlohmann::json& result) {
  std::vector<std::string> names;
  for (const auto& body : result["bodies"]) names.push_back(body["name"].get<std::string>());
  return names;
}

/// result.json's bodies of a run across `processes` processes (`a`, written in `out`) and of one
/// process (`b`): each body's ranges of the whole mesh, and its load, its reactions and its
/// contact force those of one process to 1e-8 of the largest force of a body or of a contact
/// node (a body whose resultants vanish, pressed by another, has contact nodes' forces).
void expect_bodies_agree(const fs::path& out, const nlohmann::json& a, const nlohmann::json& b, int processes) {
  SCOPED_TRACE(out.string() + " on " + std::to_string(processes) + " processes");
  ASSERT_TRUE(b["bodies"].is_array());
  ASSERT_GE(b["bodies"].size(), 2u);
  ASSERT_EQ(a["bodies"].size(), b["bodies"].size());
  double nodes = 0.0;
  for (const auto& n : b["contact"])
    nodes = std::max(nodes, std::abs(n["law_force"].get<double>() + n["reaction"].get<double>()));
  for (std::size_t i = 0; i < b["bodies"].size(); ++i) {
    const nlohmann::json &ba = a["bodies"][i], &bb = b["bodies"][i];
    for (const char* key : {"name", "first_vertex", "vertices", "first_cell", "cells"}) EXPECT_EQ(ba[key], bb[key]) << key;
    const nlohmann::json &fa = ba["forces"], &fb = bb["forces"];
    double scale = nodes;
    const auto each = [](const nlohmann::json& forces,
                         const std::function<void(const std::string&, const nlohmann::json&)>& f) {
      f("applied", forces["applied"]);
      f("contact", forces["contact"]);
      for (const auto& [name, force] : forces["reactions"].items()) f(name, force);
    };
    each(fb, [&](const std::string&, const nlohmann::json& v) {
      for (const auto& c : v) scale = std::max(scale, std::abs(c.get<double>()));
    });
    EXPECT_GT(scale, 0.0);
    EXPECT_EQ(fa["reactions"].size(), fb["reactions"].size());
    each(fb, [&](const std::string& name, const nlohmann::json& v) {
      const nlohmann::json& mine = name == "applied" || name == "contact" ? fa[name] : fa["reactions"][name];
      ASSERT_EQ(mine.size(), v.size()) << name;
      for (std::size_t c = 0; c < v.size(); ++c)
        EXPECT_NEAR(mine[c].get<double>(), v[c].get<double>(), 1e-8 * scale) << bb["name"] << " " << name << " " << c;
    });
  }
}

/// The scene of `flags` solved on the condensed route in one process (eigen) into the scratch
/// folder `name`; empty (a failure recorded) when the run fails.
fs::path solve_condensed(const std::string& flags, const std::string& name) {
  const fs::path ref = scratch(name);
  const CommandRun c = run(binary() + " solve " + flags + " --linear eigen -q --out " + ref.string());
  EXPECT_EQ(c.code, 0) << c.err;
  return c.code == 0 ? ref : fs::path();
}

/// `processes` ranks of `solve` with `flags` on the full-space route, each with its own --out
/// folder; rank 0's folder.
fs::path solve_across(int processes, const std::string& flags, const std::string& name, CommandRun* out) {
  std::string command = mpiexec();
  const fs::path rank0 = scratch(name + "-rank0");
  for (int r = 0; r < processes; ++r)
    command += (r ? " : " : " ") + np(1) + " " + binary() + " solve " + flags + " --out " +
               (r ? scratch(name + "-rank" + std::to_string(r)) : rank0).string();
  *out = run(command);
  return rank0;
}

/// The scene of `flags` solved by `processes` ranks on the full-space route against the condensed
/// route in one process (its outputs in `ref`): rank 0 alone writes, and every displacement,
/// contact node's normal displacement and force (and with `friction` its tangential displacement
/// and friction force) is the condensed route's to 1e-8, as is the error estimate; the mesh was
/// made in `pieces` pieces (result.json's mesh.pieces: the processes, or 1 where each made it
/// whole), and the outputs are of the whole mesh. Rank 0's result.json into *result when given.
void expect_processes_agree(const std::string& flags, const fs::path& ref, int processes, const std::string& name,
                            bool friction, int pieces, nlohmann::json* result = nullptr) {
  SCOPED_TRACE(std::to_string(processes) + " processes");
  CommandRun m;
  const std::string folder = name + "-np" + std::to_string(processes);
  const fs::path out = solve_across(processes, flags + " --linear petsc-gamg", folder, &m);
  ASSERT_EQ(m.code, 0) << m.out << m.err;
  EXPECT_EQ(count(m.out, "hemivem solve:"), 1u) << m.out;
  EXPECT_EQ(count(m.out, "linear petsc-gamg (" + std::to_string(processes) + " processes)"), 1u) << m.out;
  for (int r = 1; r < processes; ++r)
    EXPECT_FALSE(fs::exists(out.parent_path() / (folder + "-rank" + std::to_string(r)))) << "rank " << r << " wrote outputs";
  const nlohmann::json a = nlohmann::json::parse(slurp(out / "result.json"));
  const nlohmann::json b = nlohmann::json::parse(slurp(ref / "result.json"));
  if (result) *result = a;
  EXPECT_EQ(a["processes"], processes);
  EXPECT_EQ(a["backends"]["linear"], "petsc-gamg");
  EXPECT_TRUE(a["converged"].get<bool>());
  // the stages and timings of the route in one process: the stages' times, disjoint intervals of the total
  ASSERT_TRUE(a["full_space"].is_object()) << a.dump();
  const bool sequenced = !a["full_space"]["grid_sequence"].empty();  // coarser grids solved first
  nlohmann::json expected_stages = {"assembly", "posing", "full_space", "estimate"};
  if (sequenced) expected_stages.insert(expected_stages.begin(), "grid_sequence");
  EXPECT_EQ(a["stages"], expected_stages);
  double stages = sequenced ? a["timings"]["grid_sequence"].get<double>() : 0.0;
  for (const char* stage : {"mesh", "setup", "assembly", "posing", "full_space", "post_process", "release", "estimate"}) {
    ASSERT_TRUE(a["timings"].contains(stage)) << stage;
    EXPECT_GE(a["timings"][stage].get<double>(), 0.0) << stage;
    stages += a["timings"][stage].get<double>();
  }
  EXPECT_LE(stages, a["timings"]["total"].get<double>() * (1 + 1e-12)) << a["timings"].dump();
  // the route's counts of the whole iteration, which every process made alike
  EXPECT_EQ(a["full_space"]["newton_iterations"], a["iterations"]);
  EXPECT_GE(a["full_space"]["krylov_iterations"].get<int>(), a["iterations"].get<int>());
  EXPECT_GE(a["full_space"]["preconditioner_setups"].get<int>(), 1);
  EXPECT_TRUE(b["full_space"].is_null());
  EXPECT_EQ(a["mesh"]["dofs"], b["mesh"]["dofs"]);
  EXPECT_EQ(a["mesh"]["pieces"], pieces);
  EXPECT_EQ(b["mesh"]["pieces"], 1);
  for (const char* key : {"vertices", "elements", "faces", "h"})  // a plane's mesh has no faces
    EXPECT_EQ(a["mesh"].value(key, nlohmann::json()), b["mesh"].value(key, nlohmann::json())) << key;
  const double eta_a = a["error_estimate"]["energy"].get<double>(), eta_b = b["error_estimate"]["energy"].get<double>();
  EXPECT_GT(eta_b, 0.0);
  EXPECT_NEAR(eta_a, eta_b, 1e-8 * eta_b);
  const int cells = b["mesh"]["elements"].get<int>();
  if (fs::exists(ref / "solution.vtm")) expect_bodies_agree(out, a, b, processes);
  if (pieces > 1) {  // each process wrote its piece, each cell in one piece, named by solution.pvtu
    expect_pieces_make_the_whole(out, "solution", ref / "solution.vtu", processes, {"von_mises", "error_indicator"}, a["files"]);
    if (fs::exists(ref / "solution.vtm"))  // and its piece of each body's file
      expect_body_pieces_make_the_bodies(out, ref, processes, body_names(b), {"von_mises", "error_indicator"}, a["files"]);
  } else {  // of the whole mesh
    const std::string vtu = slurp(out / "solution.vtu");
    EXPECT_NE(vtu.find("NumberOfCells=\"" + std::to_string(cells) + "\""), std::string::npos);
  }
  const double ea = a["potential_energy"].get<double>(), eb = b["potential_energy"].get<double>();
  EXPECT_NEAR(ea, eb, 1e-9 * std::abs(eb));
  // every displacement (ux, uy, uz) and every contact node's normal displacement and force
  const fs::path contact_a = out / "contact.csv", contact_b = ref / "contact.csv";
  const double u = expect_columns_agree(out / "displacement.csv", ref / "displacement.csv", 4, 7);
  expect_columns_agree(contact_a, contact_b, 4, 5, u);
  expect_columns_agree(contact_a, contact_b, 5, 8);
  if (friction) {
    // u_tau_x, u_tau_y, u_tau_z, then friction_force_x, friction_force_y, friction_force_z
    EXPECT_GT(expect_columns_agree(contact_a, contact_b, 13, 16, u), 0.0);
    expect_columns_agree(contact_a, contact_b, 16, 19);
  }
}

TEST(CliFullSpaceMpi, ProcessesSolvingTheirSharesAgreeWithTheCondensedRouteAndRankZeroAloneWrites) {
  const std::string flags = scene("example-4.1-3d.toml") + " --set 'mesh.n=[6, 6, 6]' --tol 1e-11";
  const fs::path ref = solve_condensed(flags, "condensed");
  if (ref.empty()) return;
  for (int processes : {2, 3}) expect_processes_agree(flags, ref, processes, "example", false, processes);
}

// a plane's pieces: its polygons and its contact lines, each in one piece
TEST(CliFullSpaceMpi, APlanesPiecesHoldEachPolygonAndContactLineOnce) {
  const std::string flags = scene("paper-example-4.1.toml") + " --n 12 -q --set 'output.write=[\"vtu\"]'";
  const fs::path ref = solve_condensed(flags, "plane-one");
  if (ref.empty()) return;
  CommandRun m;
  const fs::path out = solve_across(3, flags + " --linear petsc-gamg", "plane-pieces", &m);
  ASSERT_EQ(m.code, 0) << m.out << m.err;
  const int whole = vtu_cells(ref / "solution.vtu");
  EXPECT_GT(whole, 144);  // the polygons and the contact lines after them
  int cells = 0;
  for (int k = 0; k < 3; ++k) cells += vtu_cells(out / ("solution.piece-" + std::to_string(k) + ".vtu"));
  EXPECT_EQ(cells, whole);
  EXPECT_FALSE(fs::exists(out / "solution.vtu"));
  EXPECT_TRUE(fs::exists(out / "solution.pvtu"));
}

// the pieces of solution.pvtu go into the folder's transaction, which the first process opens:
// where it cannot (another run holds the folder), it says so, and every process ends, none
// waiting for it and nothing written
TEST(CliFullSpaceMpi, AFolderThatCannotBeOpenedEndsEveryProcessWritingNothing) {
  const fs::path out = scratch("held");
  const fs::path lock = out.parent_path() / ("." + out.filename().string() + ".hemivem-lock");
  fs::create_directories(out.parent_path());
  const int fd = ::open(lock.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0666);
  ASSERT_GE(fd, 0);
  ASSERT_EQ(::flock(fd, LOCK_EX | LOCK_NB), 0);  // another run writing the folder
  // a static solve, and a path whose processes would write their pieces of each frame as it runs
  for (const std::string& flags : {scene("example-4.1-3d.toml") + " --set 'mesh.n=[4, 4, 4]'",
                                  scene("coulomb-block-3d.toml") + " --set 'mesh.n=[4, 4, 2]'"}) {
    SCOPED_TRACE(flags);
    const CommandRun m = run(mpiexec() + " " + np(2) + " " + binary() + " solve " + flags + " --linear petsc-gamg -q --out " +
                             out.string());
    EXPECT_EQ(m.code, 2) << m.out << m.err;
    EXPECT_EQ(count(m.err, "another hemivem run is writing"), 1u) << m.err;  // the first process alone says so
    EXPECT_FALSE(fs::exists(out));
  }
  ::close(fd);
}

// a process that cannot write its pieces (rank 1 under a limit of the file size, which its
// pieces exceed; Open MPI's shared memory, which the limit would also stop, left out): every
// process ends with the error, which the first tells, and the folder keeps its previous outputs
TEST(CliFullSpaceMpi, APieceThatCannotBeWrittenEndsEveryProcessAndTheFolderKeepsItsOutputs) {
  const std::vector<std::pair<std::string, std::string>> runs = {
      {scene("example-4.1-3d.toml") + " --set 'mesh.n=[4, 4, 4]'", "solution.piece-1.vtu"},
      {scene("coulomb-block-3d.toml") + " --set 'mesh.n=[4, 4, 2]'", "its pieces of the path's frames"},
      {scene("two-boxes-3d.toml"), "its pieces of the solution"}};  // of solution.pvtu and of each body's file
  for (const auto& [flags, piece] : runs) {
    SCOPED_TRACE(flags);
    const fs::path out = scratch("unwritable");
    fs::create_directories(out);
    std::ofstream(out / "result.json") << "earlier";
    const std::string solve = binary() + " solve " + flags + " --linear petsc-gamg -q --out " + out.string();
    const CommandRun m = run("OMPI_MCA_btl=self,tcp " + mpiexec() + " " + np(1) + " " + solve + " : " + np(1) +
                             " sh -c \"trap '' XFSZ; ulimit -f 1; exec " + solve + "\"");
    EXPECT_EQ(m.code, 2) << m.out << m.err;
    EXPECT_EQ(count(m.err, "process 1 could not write " + piece), 1u) << m.err;  // the first process tells
    EXPECT_EQ(count(m.err, "keeps its previous outputs"), 1u) << m.err;
    EXPECT_EQ(slurp(out / "result.json"), "earlier");
    std::vector<std::string> names;
    for (const auto& entry : fs::directory_iterator(out)) names.push_back(entry.path().filename().string());
    EXPECT_EQ(names, std::vector<std::string>{"result.json"});
  }
}

// started from its coarser grids (solver.grid_sequence), each solved on the processes' pieces of
// its own mesh: the same answer, the same grids recorded
TEST(CliFullSpaceMpi, AGridSequenceAcrossProcessesIsTheCondensedAnswer) {
  const std::string flags = scene("example-4.1-3d.toml") + " --set 'mesh.n=[8, 8, 8]' --tol 1e-11";
  const fs::path ref = solve_condensed(flags, "condensed-sequence");
  if (ref.empty()) return;
  nlohmann::json a;
  expect_processes_agree(flags + " --set solver.grid_sequence=2", ref, 2, "sequence", false, 2, &a);
  const nlohmann::json& grids = a["full_space"]["grid_sequence"];
  ASSERT_EQ(grids.size(), 2u) << a["full_space"].dump();
  EXPECT_EQ(grids[0]["n"], "2");
  EXPECT_EQ(grids[1]["n"], "4");
  for (const auto& g : grids) EXPECT_TRUE(g["converged"].get<bool>()) << g.dump();
}

// a solid's Tresca friction: the processes' slabs split the bottom, where nodes slip and stick
TEST(CliFullSpaceMpi, ASolidsFrictionAcrossProcessesIsTheCondensedAnswer) {
  const std::string flags = scene("friction-block-3d.toml") + " --set 'mesh.n=[6, 6, 2]' --tol 1e-11";
  const fs::path ref = solve_condensed(flags, "condensed-friction");
  if (ref.empty()) return;
  const std::string table = slurp(ref / "contact.csv");
  EXPECT_NE(table.find(",slip"), std::string::npos) << "no node slips";
  EXPECT_NE(table.find(",stick"), std::string::npos) << "no node sticks";
  expect_processes_agree(flags, ref, 2, "friction", true, 2);
}

// two solids joined at their contact, with Tresca friction between them, each process keeping
// its piece of each body along the Hilbert order of both (the library's test of the bodies
// across processes, FullSpaceMpi, puts the pairs' nodes and the vertices across from them on
// different processes)
/// A scratch scene `name` of two solids of `n` cells each, the upper's top moved by (0.004,
/// 0.002, -0.01), joined with Tresca friction (bound 0.004), and `more` after them.
fs::path joined_solids(const std::string& name, const std::string& n, const std::string& more = "") {
  const fs::path toml = scratch(name);
  fs::create_directories(toml.parent_path());
  std::ofstream out(toml);
  hemivem::test::StackedBodies b;
  b.n = n;
  b.top = "[0.004, 0.002, -0.01]";
  b.contact = "friction = {law = \"tresca\", bound = 0.004}\n" + more;
  out << hemivem::test::stacked_bodies(b);
  return toml;
}

// each process makes its piece of each body, matches the pieces and joins them: two solids whose
// meshes match, and two plane blocks whose meshes do not (triangles or Voronoi cells on
// squares: matching adds vertices to both), under their weight (a displacement no element
// reproduces exactly); a block of Voronoi cells on a box of cubes; a lower block or box read
// from a file (a .poly2d file of triangles, a Gmsh file of tetrahedra), of which each process
// reads its piece
TEST(CliFullSpaceMpi, TwoJoinedBodiesAcrossProcessesAreTheCondensedAnswer) {
  const fs::path toml = joined_solids("two-solids.toml", "[4, 4, 3]");
  const std::string weight = " --set 'body[0].loads.body_force=[0.0, -1.0]' --set 'body[1].loads.body_force=[0.0, -1.0]'";
  const std::string weight3 =
      " --set 'body[0].loads.body_force=[0.0, 0.0, -1.0]' --set 'body[1].loads.body_force=[0.0, 0.0, -1.0]'";
  const fs::path poly = scratch("lower-block.poly2d"), tets = scratch("lower-box.msh");
  fs::create_directories(poly.parent_path());
  hemivem::write_poly2d(poly, hemivem::make_mesh("triangles", hemivem::GridSize(7, 4), hemivem::Rectangle{0.0, 1.0, 0.0, 0.5}));
  hemivem::write_gmsh3d(hemivem::make_mesh3d("tetrahedra", hemivem::GridSize3(3, 3, 2), hemivem::Box{0.0, 1.0, 0.0, 1.0, 0.0, 0.5}),
                        tets);
  const struct {
    std::string flags, name;
    bool friction;
  } cases[] = {{toml.string() + " --tol 1e-11", "two-solids", true},
               {scene("two-blocks.toml") + " --set 'body[0].mesh.generator=\"triangles\"' --set 'body[0].mesh.n=[5, 4]'" +
                    " --set 'body[1].mesh.n=[7, 4]'" + weight + " --tol 1e-11",
                "two-blocks-triangles", false},
               {scene("two-blocks.toml") + " --set 'body[0].mesh.n=[8, 5]' --set 'body[1].mesh.n=[7, 4]'" + weight +
                    " --tol 1e-11",
                "two-blocks-voronoi", false},
               {scene("two-boxes-3d.toml") + " --set 'body[0].mesh.generator=\"voronoi\"' --set 'body[0].mesh.n=[4, 4, 2]'" +
                    " --set 'body[0].loads.body_force=[0.0, 0.0, -1.0]' --set 'body[1].loads.body_force=[0.0, 0.0, -1.0]'" +
                    " --tol 1e-11",
                "two-boxes-voronoi", false},
               {scene("two-blocks.toml") + " --set 'body[0].mesh.n=[8, 5]' --set 'body[1].mesh.file=\"" + poly.string() + "\"'" +
                    weight + " --tol 1e-11",
                "two-blocks-file", false},
               {scene("two-boxes-3d.toml") + " --set 'body[1].mesh.file=\"" + tets.string() + "\"'" + weight3 + " --tol 1e-11",
                "two-boxes-file", false}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const fs::path ref = solve_condensed(c.flags, "condensed-" + c.name);
    if (ref.empty()) return;
    for (const int processes : {2, 3}) expect_processes_agree(c.flags, ref, processes, c.name, c.friction, processes);
  }
}

/// The last field of each row of a CSV file after its header.
std::vector<std::string> last_fields(const fs::path& csv) {
  std::istringstream in(slurp(csv));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> out;
  while (std::getline(in, line)) out.push_back(line.substr(line.rfind(',') + 1));
  return out;
}

// a loading path of two bodies (the stacked blocks of two-blocks.toml on two steps; two solids
// joined with Tresca friction): each process keeps its piece of each body for the whole path and
// writes its piece of every frame, as the steps come, and of the last step's solution.vtu and
// each body's file; rank 0 writes the rest from its piece, and no process makes the whole mesh
TEST(CliFullSpaceMpi, APathOfTwoBodiesAcrossProcessesKeepsEachProcesssPieces) {
  const fs::path solids = joined_solids("two-solids-path.toml", "[3, 3, 2]", "[path]\nt = [0.5, 1.0]\n");
  const struct {
    std::string flags, name;
    std::size_t u;  // path-displacement.csv's first displacement column
    int dim;
  } cases[] = {{scene("two-blocks.toml") + " --set 'path.t=[0.5, 1.0]'", "two-blocks-path", 5, 2},
               {solids.string(), "two-solids-path", 6, 3}};
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string flags = c.flags + " --tol 1e-11";
    const fs::path ref = solve_condensed(flags, "condensed-" + c.name);
    if (ref.empty()) return;
    CommandRun m;
    const fs::path out = solve_across(2, flags + " --linear petsc-gamg", c.name + "-np2", &m);
    ASSERT_EQ(m.code, 0) << m.out << m.err;
    EXPECT_FALSE(fs::exists(out.parent_path() / (c.name + "-np2-rank1"))) << "rank 1 wrote outputs";
    const nlohmann::json a = nlohmann::json::parse(slurp(out / "result.json"));
    const nlohmann::json b = nlohmann::json::parse(slurp(ref / "result.json"));
    EXPECT_TRUE(a["converged"].get<bool>());
    EXPECT_EQ(a["mesh"]["pieces"], 2);
    for (const char* key : {"vertices", "elements", "h"}) EXPECT_EQ(a["mesh"][key], b["mesh"][key]) << key;
    const nlohmann::json pa = nlohmann::json::parse(slurp(out / "path.json"));
    const nlohmann::json pb = nlohmann::json::parse(slurp(ref / "path.json"));
    ASSERT_EQ(pa["steps"].size(), 2u);
    ASSERT_EQ(pb["steps"].size(), 2u);
    for (std::size_t k = 0; k < 2; ++k) {
      const double ea = pa["steps"][k]["energy"].get<double>(), eb = pb["steps"][k]["energy"].get<double>();
      EXPECT_NE(eb, 0.0);
      EXPECT_NEAR(ea, eb, 1e-8 * std::abs(eb)) << "step " << k + 1;
    }
    // every frame's displacement at every vertex, and the body of each row
    const fs::path rows_a = out / "path-displacement.csv", rows_b = ref / "path-displacement.csv";
    expect_columns_agree(rows_a, rows_b, c.u, c.u + static_cast<std::size_t>(c.dim));
    const std::vector<std::string> bodies = last_fields(rows_b);
    EXPECT_EQ(last_fields(rows_a), bodies);
    EXPECT_NE(std::find(bodies.begin(), bodies.end(), "upper"), bodies.end());
    EXPECT_NE(std::find(bodies.begin(), bodies.end(), "lower"), bodies.end());
    // each frame in pieces, of both bodies' cells
    for (const char* stem : {"solution-0001", "solution-0002"})
      expect_pieces_make_the_whole(out, stem, ref / (std::string(stem) + ".vtu"), 2, {"von_mises"}, a["files"]);
    // the last step's files in pieces: the whole mesh's and each body's (the stacked blocks'
    // error indicators are round-off), its bodies' records
    expect_pieces_make_the_whole(out, "solution", ref / "solution.vtu", 2, {"von_mises", "stress"}, a["files"]);
    expect_body_pieces_make_the_bodies(out, ref, 2, {"upper", "lower"}, {"von_mises", "stress"}, a["files"]);
    expect_bodies_agree(out, a, b, 2);
    expect_columns_agree(out / "displacement.csv", ref / "displacement.csv", static_cast<std::size_t>(c.dim + 1),
                         static_cast<std::size_t>(2 * c.dim + 1));
  }
}

// two polar rings held by points and in contact along their edge groups (shrink-fit.toml), and
// two half-disks held along a side of their bounding boxes (two-cylinders.toml): each process
// makes its piece of each body, with the cells around the points and along the grids' sides
TEST(CliFullSpaceMpi, TwoPolarBodiesMadeInPiecesAreTheCondensedAnswer) {
  const std::pair<std::string, std::string> runs[] = {
      {"shrink-fit", scene("shrink-fit.toml") + " --tol 1e-11"},
      {"two-cylinders", scene("two-cylinders.toml") +
                            " --set 'body[0].mesh.n=[24, 48]' --set 'body[1].mesh.n=[24, 52]' --tol 1e-11"}};
  for (const auto& [name, flags] : runs) {
    SCOPED_TRACE(name);
    const fs::path ref = solve_condensed(flags, "condensed-" + name);
    if (ref.empty()) return;
    for (const int processes : {2, 3}) expect_processes_agree(flags, ref, processes, name, false, processes);
  }
}

// a distorted mesh (paper-example-4.1-distorted.toml): each process makes its piece of the
// squares, every vertex moved as the whole mesh's; and of the nonconvex cells, numbered on a grid
// twice as fine (paper-example-4.1-nonconvex.toml)
TEST(CliFullSpaceMpi, ADistortedOrNonconvexMeshEachProcessMakesItsPieceOfIsTheCondensedAnswer) {
  for (const std::string name : {"distorted", "nonconvex"}) {
    SCOPED_TRACE(name);
    const std::string flags = scene("paper-example-4.1-" + name + ".toml") + " --n 24 --tol 1e-11";
    const fs::path ref = solve_condensed(flags, "condensed-" + name);
    if (ref.empty()) return;
    for (const int processes : {2, 3}) expect_processes_agree(flags, ref, processes, name, false, processes);
  }
}

/// A scene's flags and the name of its outputs' folders.
struct SceneRun {
  std::string flags, name;
};

/// Each of `runs` on 2 and 3 processes, each making its piece of the mesh, against the condensed
/// route in one (expect_processes_agree).
void expect_pieces_agree(std::span<const SceneRun> runs) {
  for (const SceneRun& c : runs) {
    SCOPED_TRACE(c.name);
    const std::string flags = c.flags + " --tol 1e-11";
    const fs::path ref = solve_condensed(flags, "condensed-" + c.name);
    if (ref.empty()) return;
    for (const int processes : {2, 3}) expect_processes_agree(flags, ref, processes, c.name, false, processes);
  }
}

// segments across a generated box (lines through Example 4.1's squares, which pick no edge) and
// along a polar grid's rays (a half ring held along its diameter): each process makes its piece,
// holding every side, and no segment picks an edge where the pieces meet
TEST(CliFullSpaceMpi, SegmentsOnAGeneratedBoxOrPolarGridEachProcessMakesItsPieceOfAreTheCondensedAnswer) {
  const fs::path ring = scratch("polar-segments.toml");
  fs::create_directories(ring.parent_path());
  std::ofstream(ring) << R"(schema_version = 1
[mesh]
generator = "polar"
radii = [0.5, 1.0]
angles = [180.0, 360.0]
n = [6, 24]
[material]
E = 65.0
nu = 0.29
[clamped]
segments = [[-1.0, 0.0, -0.5, 0.0], [0.5, 0.0, 1.0, 0.0]]
[[loads.traction]]
group = "inner"
pressure = 2.0
[contact]
group = "outer"
law = "paper"
gap = 0.02
constraint = "box"
)";
  const SceneRun cases[] = {{scene("paper-example-4.1.toml") + " --n 16 --set 'contact.segments=[[0.0, 0.5, 1.0, 0.5], [0.0, 0.25, 1.0, 0.25]]'",
                "squares-segments"},
               {ring.string(), "polar-segments"}};
  expect_pieces_agree(cases);
}

// a plane clamped on a segment of its top and a solid clamped on its top, pushed from a side:
// each process's piece holds the cells along the contact's side alone, the support's facets among
// its own cells (none, or the first column's, on the middle one) and the clamped vertices of the
// others, gathered; the body held whole
TEST(CliFullSpaceMpi, SupportsAPieceMeetsLittleOfAreGatheredAndTheCondensedAnswer) {
  const SceneRun cases[] = {{scene("paper-example-4.1.toml") +
                    " --n 16 --set 'clamped={segments=[[0.3, 1.0, 0.7, 1.0]]}' --set 'loads.traction[0].side=\"right\"'"
                    " --set 'loads.traction[0].value=[-2.0, 0.0]'",
                "clamped-segment"},
               {scene("example-4.1-3d.toml") +
                    " --set 'mesh.n=[4, 3, 12]' --set 'clamped.side=[\"top\"]' --set 'loads.traction[0].side=\"x1\"'"
                    " --set 'loads.traction[0].value=[-2.0, 0.0, 0.0]'",
                "clamped-top-3d"}};
  expect_pieces_agree(cases);
}

// a Voronoi mesh of a plane and of a solid, each process computing the cells of its share of the
// seeds in the Lloyd iterations (in the plane from the seeds around them alone): the one
// process's mesh (its vertices, cells, faces and h) and answer; each process makes its piece of
// the plane's from the cells' vertex lists, and keeps its piece of the solid's made whole
TEST(CliFullSpaceMpi, AVoronoiMeshSplitAmongProcessesIsOneProcesss) {
  const std::pair<std::string, std::string> runs[] = {
      {"voronoi-2d", scene("paper-example-4.1-voronoi.toml") + " --n 24 --tol 1e-11"},
      {"voronoi-3d", scene("example-4.1-3d.toml") + " --set mesh.generator=\"voronoi\" --set 'mesh.n=[5, 5, 5]' --tol 1e-11"}};
  for (const auto& [name, flags] : runs) {
    SCOPED_TRACE(name);
    const fs::path ref = solve_condensed(flags, "condensed-" + name);
    if (ref.empty()) return;
    for (const int processes : {2, 3}) expect_processes_agree(flags, ref, processes, name, false, processes);
  }
}

// a Gmsh file's solid, which each process reads its piece of, a polygon's triangles and Voronoi
// cells, and a plane Voronoi mesh whose contact is a segment, each process making its piece from
// the cells' lists (the cells around its share of the mesh's Hilbert order, and those of every
// boundary edge): the condensed answer, the solution written in pieces
TEST(CliFullSpaceMpi, MeshesOfOneBodyMadeOrReadInPiecesAreTheCondensedAnswer) {
  const struct {
    std::string flags, name;
  } cases[] = {{scene("gmsh-bracket-3d.toml"), "gmsh-bracket-3d"},  // a file read in pieces
               {scene("polygon-bracket.toml"), "polygon-bracket"},  // a polygon's triangles made in pieces
               {scene("polygon-bracket.toml") + " --set mesh.generator=\"voronoi\" --n 20", "polygon-voronoi"},
               {scene("rollers-pressure.toml"), "rollers-pressure"}};  // a Voronoi mesh, a contact segment
  for (const auto& c : cases) {
    SCOPED_TRACE(c.name);
    const std::string flags = c.flags + " --tol 1e-11";
    const fs::path ref = solve_condensed(flags, "condensed-" + c.name);
    if (ref.empty()) return;
    for (const int processes : {2, 3}) expect_processes_agree(flags, ref, processes, "pieces-" + c.name, false, processes);
  }
}

/// Example 4.1 on the plane Gmsh file `msh` (squares; its contact the file's line "bottom"),
/// written to a scratch scene `name`.
fs::path example_on_file(const fs::path& msh, const std::string& name) {
  std::string text = slurp(scene("paper-example-4.1.toml"));
  const auto from = text.find("[mesh]"), to = text.find("[material]");
  EXPECT_TRUE(from != std::string::npos && to != std::string::npos);
  text.replace(from, to - from, "[mesh]\nfile = \"" + msh.string() + "\"\n\n");
  const std::string contact = "[contact]            # Gamma_3\nside = \"bottom\"";
  const auto at = text.find(contact);
  EXPECT_NE(at, std::string::npos);
  if (at != std::string::npos) text.replace(at, contact.size(), "[contact]\ngroup = \"bottom\"");
  const fs::path toml = scratch(name);
  fs::create_directories(toml.parent_path());
  std::ofstream(toml) << text;
  return toml;
}

/// Example 4.1 on the plane Gmsh file `msh` (example_on_file) with `more` added to its scene,
/// solved by 2 and 3 processes on the full-space route: the condensed route's answer in one.
void expect_example_on_file_agrees(const fs::path& msh, const std::string& name, const std::string& more = "") {
  SCOPED_TRACE(name);
  const fs::path toml = example_on_file(msh, name + ".toml");
  std::ofstream(toml, std::ios::app) << more;
  const std::string flags = toml.string() + " --tol 1e-11";
  const fs::path ref = solve_condensed(flags, "condensed-" + name);
  if (ref.empty()) return;
  for (const int processes : {2, 3}) expect_processes_agree(flags, ref, processes, name, false, processes);
}

// a Gmsh file that each process reads its piece of (a plane's, whose contact is a physical
// line, and the same held at a point inside it; a solid's is gmsh-bracket-3d.toml above): the
// condensed answer, the outputs in pieces
TEST(CliFullSpaceMpi, AGmshFileReadInPiecesIsTheCondensedAnswer) {
  const fs::path msh = scratch("squares-24x12.msh");
  fs::create_directories(msh.parent_path());
  std::ofstream(msh) << hemivem::test::squares_msh(24, 12);
  expect_example_on_file_agrees(msh, "squares-on-file");
  // held at a vertex inside the body as well: each process's piece holds the cells around it
  expect_example_on_file_agrees(msh, "squares-held-on-file", "\n[[dirichlet]]\npoint = [0.75, 0.25]\nux = 0.0\n");
}

/// The scene of `flags` solved by `processes` ranks on the full-space route writing `kept`
/// (output.write), so that every process keeps its piece of the mesh for the results, against
/// the same scene solved on that route writing `whole` by `whole_processes` ranks, for which
/// rank 0 makes or holds the whole mesh. What the first says of the whole mesh is the second's:
/// result.json's mesh (vertices, elements, faces, h) and the summary's mesh line to the bit,
/// its stress peak the largest von Mises stress of the second's stress.csv (a cell of that
/// stress, its centroid), stress.csv when both write it (the same cells and centroids, the
/// stresses to 1e-9 of the largest), a solid's contact-surface.vtu (the same polygons, the values
/// to 1e-9), and the figures of `figures` drawn, or skipped for want of gnuplot.
void expect_pieces_make_the_results(const std::string& flags, const std::string& kept, const std::string& whole,
                                    int processes, int whole_processes, const std::string& name,
                                    const std::string& mesh_line, const std::vector<std::string>& figures = {}) {
  SCOPED_TRACE(std::to_string(processes) + " processes");
  CommandRun a, b;
  const std::string write = " --linear petsc-gamg --set 'output.write=[";
  const fs::path of_pieces = solve_across(processes, flags + write + kept + "]'", name + "-kept", &a);
  const fs::path of_whole = solve_across(whole_processes, flags + write + whole + "]'", name + "-whole", &b);
  ASSERT_EQ(a.code, 0) << a.out << a.err;
  ASSERT_EQ(b.code, 0) << b.out << b.err;
  EXPECT_EQ(count(a.out, mesh_line), 1u) << a.out;
  EXPECT_EQ(count(b.out, mesh_line), 1u) << b.out;
  nlohmann::json ra = nlohmann::json::parse(slurp(of_pieces / "result.json"));
  nlohmann::json rb = nlohmann::json::parse(slurp(of_whole / "result.json"));
  EXPECT_EQ(ra["mesh"]["pieces"], processes);
  ra["mesh"].erase("pieces"), rb["mesh"].erase("pieces");
  EXPECT_EQ(ra["mesh"], rb["mesh"]);
  // the peak: a cell whose von Mises stress in stress.csv is the largest, and its centroid
  const std::vector<std::vector<double>> stress = numbers(of_whole / "stress.csv");
  ASSERT_EQ(static_cast<int>(stress.size()), rb["mesh"]["elements"].get<int>());
  double largest = 0.0;
  for (const auto& row : stress) largest = std::max(largest, row.back());
  ASSERT_TRUE(ra["stress"].is_object()) << ra.dump();
  const double peak = ra["stress"]["max_von_mises"].get<double>();
  EXPECT_NEAR(peak, largest, 1e-9 * largest);
  const int cell = ra["stress"]["cell"].get<int>();
  ASSERT_GE(cell, 0);
  ASSERT_LT(cell, static_cast<int>(stress.size()));
  const std::vector<double>& row = stress[static_cast<std::size_t>(cell)];
  EXPECT_NEAR(row.back(), largest, 1e-9 * largest);
  const std::size_t dim = ra["stress"]["centroid"].size();
  for (std::size_t i = 0; i < dim; ++i) EXPECT_NEAR(ra["stress"]["centroid"][i].get<double>(), row[1 + i], 1e-12) << i;
  if (fs::exists(of_pieces / "stress.csv")) {  // gathered from the pieces
    const std::vector<std::vector<double>> mine = numbers(of_pieces / "stress.csv");
    ASSERT_EQ(mine.size(), stress.size());
    for (std::size_t c = 0; c < stress.size(); ++c) {
      ASSERT_EQ(mine[c].size(), stress[c].size());
      for (std::size_t k = 0; k <= dim; ++k) EXPECT_EQ(mine[c][k], stress[c][k]) << "cell " << c << " column " << k;
      for (std::size_t k = dim + 1; k < stress[c].size(); ++k)
        EXPECT_NEAR(mine[c][k], stress[c][k], 1e-9 * largest) << "cell " << c << " column " << k;
    }
  }
  if (dim == 3) {  // the contact faces gathered from the pieces
    const fs::path sa = of_pieces / "contact-surface.vtu", sb = of_whole / "contact-surface.vtu";
    ASSERT_TRUE(fs::exists(sa));
    EXPECT_GT(vtu_cells(sb), 0);
    EXPECT_EQ(vtu_cells(sa), vtu_cells(sb));
    for (const char* array : {"displacement", "u_nu", "pressure"}) {
      const std::vector<double> va = vtu_doubles(sa, array), vb = vtu_doubles(sb, array);
      ASSERT_EQ(va.size(), vb.size()) << array;
      ASSERT_FALSE(vb.empty()) << array;
      double scale = 0.0;
      for (const double v : vb) scale = std::max(scale, std::abs(v));
      for (std::size_t i = 0; i < va.size(); ++i) EXPECT_NEAR(va[i], vb[i], 1e-9 * scale) << array << " " << i;
    }
    const auto connectivity = [](const std::string& text) {
      const std::size_t at = text.find("Name=\"connectivity\"");
      return at == std::string::npos ? std::string() : text.substr(at, text.find("</DataArray>", at) - at);
    };
    EXPECT_FALSE(connectivity(slurp(sb)).empty());
    EXPECT_EQ(connectivity(slurp(sa)), connectivity(slurp(sb)));
  }
  for (const std::string& figure : figures) {  // drawn from the gathered faces, or skipped without gnuplot
    const bool drawn = fs::exists(of_pieces / figure);
    EXPECT_TRUE(drawn || a.out.find("skipped") != std::string::npos) << figure << "\n" << a.out;
    if (drawn) {
      EXPECT_GT(fs::file_size(of_pieces / figure), 1000u) << figure;
    }
  }
}

// where every file the scene writes is made from the pieces, rank 0 keeps its piece too, and
// the results say what the whole mesh's say
TEST(CliFullSpaceMpi, WhereThePiecesMakeEveryFileTheResultsOfPiecesAreTheWholeMeshs) {
  {
    SCOPED_TRACE("a solid, every file of its default against one process's");
    const std::string flags = scene("example-4.1-3d.toml") + " --set 'mesh.n=[6, 6, 6]' --tol 1e-11";
    const std::string all = R"("vtu", "contact-csv", "displacement-csv", "stress-csv", "history-csv", "result-json", "deformed-png", "pressure-png")";
    expect_pieces_make_the_results(flags, all, all, 2, 1, "solid-results", "343 vertices, 216 cells, 756 faces, h = 0.25,",
                                   {"deformed.png", "pressure.png"});
  }
  {
    SCOPED_TRACE("a plane, every file of its default against one process's");
    const std::string flags = scene("paper-example-4.1.toml") + " --set 'mesh.n=24'";
    const std::string all = R"("result-json", "contact-csv", "displacement-csv", "stress-csv", "history-csv", "vtu", "u-nu-png", "deformed-png", "error-png")";
    expect_pieces_make_the_results(flags, all, all, 3, 1, "plane-results", "625 vertices, 576 elements, h = 0.0589256,",
                                   {"u_nu.png", "deformed.png", "error.png"});
  }
  {
    SCOPED_TRACE("two plane bodies, every file of their default against one process's");
    const std::string all = R"("result-json", "contact-csv", "displacement-csv", "stress-csv", "history-csv", "vtu", "u-nu-png", "deformed-png", "error-png")";
    expect_pieces_make_the_results(scene("two-blocks.toml"), all, all, 2, 1, "bodies-results",
                                   "74 vertices, 36 elements, h = 0.261811,", {"u_nu.png", "deformed.png", "error.png"});
  }
  {
    SCOPED_TRACE("two solids, every file of their default against one process's");
    const std::string all = R"("vtu", "contact-csv", "displacement-csv", "stress-csv", "history-csv", "result-json", "deformed-png", "pressure-png")";
    expect_pieces_make_the_results(scene("two-boxes-3d.toml"), all, all, 2, 1, "solid-bodies-results",
                                   "108 vertices, 116 cells, 332 faces, h = 0.75,", {"deformed.png", "pressure.png"});
  }
}

/// `solve` of `flags` refused in one process with a message from `said` on, and on 2 and 3
/// processes on the full-space route: exit code 2, the message told once, nothing written.
void expect_every_process_refuses_as_one(const std::string& flags, const std::string& said, const std::string& name) {
  const CommandRun one = run(binary() + " solve " + flags + " -q --out " + scratch(name + "-one").string());
  ASSERT_EQ(one.code, 2) << one.err;
  const auto at = one.err.find(said);
  ASSERT_NE(at, std::string::npos) << one.err;
  const std::string message = one.err.substr(at, one.err.find('\n', at) - at);
  for (const int processes : {2, 3}) {
    SCOPED_TRACE(std::to_string(processes) + " processes");
    const fs::path out = scratch(name + "-np" + std::to_string(processes));
    const CommandRun m = run(mpiexec() + " " + np(processes) + " " + binary() + " solve " + flags +
                             " --linear petsc-gamg -q --out " + out.string());
    EXPECT_EQ(m.code, 2) << m.err;
    EXPECT_EQ(count(m.err, "hemivem: error:"), 1u) << m.err;
    EXPECT_EQ(count(m.err, message), 1u) << m.err;
    EXPECT_FALSE(fs::exists(out));
  }
}

// a file with a defect in one cell inside the mesh, which only the processes whose pieces hold
// it find: every process ends with the error, the first tells it once, and nothing is written
TEST(CliFullSpaceMpi, ADefectInTheFileThatOneProcessFindsEndsEveryProcess) {
  const fs::path msh = scratch("defect.msh");
  fs::create_directories(msh.parent_path());
  std::ofstream(msh) << hemivem::test::squares_msh_repeating_a_vertex(24);
  expect_every_process_refuses_as_one(example_on_file(msh, "defect.toml").string(), "Gmsh element", "defect");
}

// region boxes on a generated box (scenes/extreme/bimaterial-1e6.toml) and on a Gmsh file, made or
// read in pieces: each process puts its cells into the whole mesh's regions; a box that holds no
// element's centroid is refused by every process alike, as in one process, and nothing is written
TEST(CliFullSpaceMpi, RegionBoxesOnPiecesAreTheCondensedAnswer) {
  const std::string boxes = scene("extreme/bimaterial-1e6.toml") +
                            " --n 24 --tol 1e-11 --set 'output.write=[\"vtu\", \"contact-csv\", \"displacement-csv\", \"stress-csv\", \"result-json\"]'";
  const fs::path ref = solve_condensed(boxes, "condensed-bimaterial");
  if (ref.empty()) return;
  for (const int processes : {2, 3}) expect_processes_agree(boxes, ref, processes, "bimaterial", false, processes);

  const fs::path msh = scratch("regions.msh");
  fs::create_directories(msh.parent_path());
  std::ofstream(msh) << hemivem::test::squares_msh(24, 12);
  expect_example_on_file_agrees(msh, "regions", "\n[[material.region]]\nid = 3\nE = 130.0\nnu = 0.3\nbox = [0.1, 0.2, 0.6, 0.8]\n");

  expect_every_process_refuses_as_one(boxes + " --set 'material.region[0].box=[0.3, 0.31, 0.3, 0.31]'",
                                      "material.region[0].id: region 1 matches no element", "empty-box");
}

// region boxes inside two bodies made in pieces (the blocks of two-blocks.toml, Voronoi cells on
// squares or on a .poly2d file's triangles): each process puts its cells into the whole meshes' regions, and a piece without a
// cell of the upper block's region shifts the lower's past it, as the whole does; a box that
// holds no cell of its body is refused by every process alike, as in one process
TEST(CliFullSpaceMpi, RegionBoxesInBodiesOnPiecesAreTheCondensedAnswer) {
  const std::string blocks =
      scene("two-blocks.toml") + " --set 'body[0].mesh.n=[12, 6]' --set 'body[1].mesh.n=[14, 6]'" +
      " --set 'body[0].loads.body_force=[0.0, -1.0]' --set 'body[1].loads.body_force=[0.0, -1.0]'" +
      " --set 'body[1].material.region[+]={id = 2, E = 1.0, nu = 0.2, box = [0.4, 0.6, 0.15, 0.35]}' --tol 1e-11";
  const std::string regions = blocks + " --set 'body[0].material.region[+]={id = 3, E = 30.0, nu = 0.3, box = [0.4, 0.6, 0.65, 0.85]}'";
  const fs::path ref = solve_condensed(regions, "condensed-body-regions");
  if (ref.empty()) return;
  for (const int processes : {2, 3}) expect_processes_agree(regions, ref, processes, "body-regions", false, processes);
  // the lower block read from a .poly2d file of triangles, its region box inside it
  const fs::path poly = scratch("lower-block-regions.poly2d");
  fs::create_directories(poly.parent_path());
  hemivem::write_poly2d(poly, hemivem::make_mesh("triangles", hemivem::GridSize(14, 6), hemivem::Rectangle{0.0, 1.0, 0.0, 0.5}));
  const std::string file = regions + " --set 'body[1].mesh.file=\"" + poly.string() + "\"'";
  const fs::path file_ref = solve_condensed(file, "condensed-file-regions");
  if (file_ref.empty()) return;
  for (const int processes : {2, 3}) expect_processes_agree(file, file_ref, processes, "file-regions", false, processes);
  expect_every_process_refuses_as_one(
      blocks + " --set 'body[0].material.region[+]={id = 3, E = 30.0, nu = 0.3, box = [0.401, 0.402, 0.701, 0.702]}'",
      "material.region[0].id: region 3 matches no element", "body-empty-box");
}

/// The applied load of a plane path's step `a` (path.json) is that of `b` to 1e-12 of its size.
void expect_applied_load_agrees(const nlohmann::json& a, const nlohmann::json& b) {
  const auto &fa = a["applied_load"], &fb = b["applied_load"];
  const double load = std::hypot(fb[0].get<double>(), fb[1].get<double>());
  EXPECT_GT(load, 0.0);
  for (int c = 0; c < 2; ++c) EXPECT_NEAR(fa[c].get<double>(), fb[c].get<double>(), 1e-12 * load);
}

/// Every step of path.json `pa` is `pb`'s: as many steps, each's fixed point converged, its energy
/// to 1e-8, its friction counts, and its applied load summed over the processes' vertices.
void expect_path_steps_agree(const nlohmann::json& pa, const nlohmann::json& pb) {
  ASSERT_EQ(pa["steps"].size(), pb["steps"].size());
  for (std::size_t k = 0; k < pb["steps"].size(); ++k) {
    SCOPED_TRACE("step " + std::to_string(k + 1));
    EXPECT_TRUE(pa["steps"][k]["fixed_point"]["converged"].get<bool>());
    const double ea = pa["steps"][k]["energy"].get<double>(), eb = pb["steps"][k]["energy"].get<double>();
    EXPECT_NEAR(ea, eb, 1e-8 * std::abs(eb));
    EXPECT_EQ(pa["steps"][k]["friction"], pb["steps"][k]["friction"]);
    expect_applied_load_agrees(pa["steps"][k], pb["steps"][k]);
  }
}

/// A plane Coulomb path's files in folder `out` are those in `ref`: every step's displacement (ux,
/// uy), and every step's contact node's u_nu, law force and reaction, u_tau and friction force
/// (these two not all zero).
void expect_plane_path_columns_agree(const fs::path& out, const fs::path& ref) {
  const fs::path contact_a = out / "path-contact.csv", contact_b = ref / "path-contact.csv";
  const double u = expect_columns_agree(out / "path-displacement.csv", ref / "path-displacement.csv", 5, 7);
  expect_columns_agree(contact_a, contact_b, 5, 6, u);
  const double f = expect_columns_agree(contact_a, contact_b, 6, 8);
  EXPECT_GT(expect_columns_agree(contact_a, contact_b, 10, 11, u), 0.0);
  EXPECT_GT(expect_columns_agree(contact_a, contact_b, 12, 13, f), 0.0);
}

// a .poly2d file that each process reads its piece of (sutton-voronoi.toml), and one whose
// contact is a segment of its top, along a loading path with Coulomb friction
// (cattaneo-mindlin.toml): the condensed answer, every step of the path the condensed route's
TEST(CliFullSpaceMpi, APoly2dFileReadInPiecesIsTheCondensedAnswer) {
  const std::string flags = scene("sutton-voronoi.toml") + " --tol 1e-11";
  const fs::path ref = solve_condensed(flags, "condensed-sutton");
  if (ref.empty()) return;
  for (const int processes : {2, 3}) expect_processes_agree(flags, ref, processes, "sutton", false, processes);
  const std::string path = scene("cattaneo-mindlin.toml");
  const fs::path path_ref = solve_condensed(path, "condensed-cattaneo");
  if (path_ref.empty()) return;
  CommandRun m;
  const fs::path out = solve_across(2, path + " --linear petsc-gamg", "cattaneo-np2", &m);
  ASSERT_EQ(m.code, 0) << m.out << m.err;
  const nlohmann::json a = nlohmann::json::parse(slurp(out / "result.json"));
  const nlohmann::json b = nlohmann::json::parse(slurp(path_ref / "result.json"));
  EXPECT_EQ(a["mesh"]["pieces"], 2);
  EXPECT_TRUE(a["converged"].get<bool>());
  for (const char* key : {"vertices", "elements", "h"}) EXPECT_EQ(a["mesh"][key], b["mesh"][key]) << key;
  const nlohmann::json pa = nlohmann::json::parse(slurp(out / "path.json"));
  const nlohmann::json pb = nlohmann::json::parse(slurp(path_ref / "path.json"));
  ASSERT_EQ(pa["steps"].size(), 20u);
  ASSERT_EQ(pb["steps"].size(), 20u);
  for (std::size_t k = 0; k < 20; ++k) {  // moved by its support alone: no load applied
    SCOPED_TRACE("step " + std::to_string(k + 1));
    EXPECT_TRUE(pa["steps"][k]["fixed_point"]["converged"].get<bool>());
    const double ea = pa["steps"][k]["energy"].get<double>(), eb = pb["steps"][k]["energy"].get<double>();
    EXPECT_NE(eb, 0.0);
    EXPECT_NEAR(ea, eb, 1e-8 * std::abs(eb));
    EXPECT_EQ(pa["steps"][k]["friction"], pb["steps"][k]["friction"]);
    EXPECT_EQ(pa["steps"][k]["applied_load"], pb["steps"][k]["applied_load"]);
  }
  // the same contact nodes of the segment at every step
  EXPECT_EQ(count(slurp(out / "path-contact.csv"), "\n"), count(slurp(path_ref / "path-contact.csv"), "\n"));
}

// a loading path with Coulomb friction (friction-coulomb.toml, with a body force): every step on
// 2 processes is the condensed route's in one, and rank 0 alone writes the path's files but the
// frames, which each process writes its piece of, from its piece of the mesh, as the steps come,
// and the last step's solution.vtu, which each process writes its piece of after the path.
TEST(CliFullSpaceMpi, ACoulombPathAcrossProcessesIsTheCondensedRoutes) {
  const std::string flags = scene("friction-coulomb.toml") + " --n 16 --set 'loads.body_force=[0.5, -2.0]'";
  const fs::path ref = solve_condensed(flags, "condensed-path");
  if (ref.empty()) return;
  CommandRun m;
  const fs::path out = solve_across(2, flags + " --linear petsc-gamg", "path-np2", &m);
  ASSERT_EQ(m.code, 0) << m.out << m.err;
  EXPECT_EQ(count(m.out, "hemivem solve:"), 1u) << m.out;
  EXPECT_EQ(count(m.err, "step 8/8"), 1u) << "rank 0 alone tells the steps: " << m.err;
  EXPECT_FALSE(fs::exists(out.parent_path() / "path-np2-rank1")) << "rank 1 wrote outputs";
  const nlohmann::json a = nlohmann::json::parse(slurp(out / "result.json"));
  EXPECT_EQ(a["processes"], 2);
  EXPECT_TRUE(a["converged"].get<bool>());
  EXPECT_EQ(a["stages"], (nlohmann::json{"assembly", "posing", "path", "estimate"}));
  const nlohmann::json b = nlohmann::json::parse(slurp(ref / "result.json"));
  EXPECT_EQ(a["mesh"]["pieces"], 2);
  for (const char* key : {"vertices", "elements", "h"}) EXPECT_EQ(a["mesh"][key], b["mesh"][key]) << key;
  const double eta_a = a["error_estimate"]["energy"].get<double>(), eta_b = b["error_estimate"]["energy"].get<double>();
  EXPECT_NEAR(eta_a, eta_b, 1e-8 * eta_b);
  const nlohmann::json pa = nlohmann::json::parse(slurp(out / "path.json"));
  const nlohmann::json pb = nlohmann::json::parse(slurp(ref / "path.json"));
  ASSERT_EQ(pa["steps"].size(), 8u);
  int newton = 0;  // the route's Newton iterations are the steps' (each summed over its fixed point)
  for (const auto& step : pa["steps"]) newton += step["iterations"].get<int>();
  ASSERT_TRUE(a["full_space"].is_object()) << a.dump();
  EXPECT_EQ(a["full_space"]["newton_iterations"].get<int>(), newton);
  expect_path_steps_agree(pa, pb);
  for (std::size_t k = 0; k < pb["steps"].size(); ++k) {
    SCOPED_TRACE("step " + std::to_string(k + 1));
    // a frame's balance of forces
    EXPECT_EQ(pa["steps"][k]["frame"], pb["steps"][k]["frame"]);
    if (pb["steps"][k]["frame"].get<bool>()) {
      EXPECT_LE(pa["steps"][k]["balance"].get<double>(), 1e-8);
    }
  }
  expect_plane_path_columns_agree(out, ref);
  // each frame in pieces, named by solution.pvd; the path's last step in pieces too
  const std::string pvd = slurp(out / "solution.pvd");
  int frames = 0;
  for (std::size_t k = 0; k < pb["steps"].size(); ++k) {
    if (!pb["steps"][k]["frame"].get<bool>()) continue;
    char stem[32];
    std::snprintf(stem, sizeof stem, "solution-%04d", static_cast<int>(k + 1));
    EXPECT_NE(pvd.find(std::string("file=\"") + stem + ".pvtu\""), std::string::npos) << pvd;
    expect_pieces_make_the_whole(out, stem, ref / (std::string(stem) + ".vtu"), 2, {"von_mises", "stress"}, a["files"]);
    ++frames;
  }
  EXPECT_EQ(frames, 8);
  expect_pieces_make_the_whole(out, "solution", ref / "solution.vtu", 2, {"von_mises", "error_indicator"}, a["files"]);
}

// the plate of the friction benchmark (plate-friction-benchmark.toml): a Coulomb path whose
// corner is held at a point, which every process's piece holds with the cells around it (a
// piece of the generated squares, no whole mesh made); on 2 and 3 processes every step is the
// condensed route's in one
TEST(CliFullSpaceMpi, APlateHeldAtAPointAcrossProcessesIsTheCondensedRoutesPath) {
  const std::string flags = scene("plate-friction-benchmark.toml") + " --n 12 --set 'output.write=[\"result-json\", \"displacement-csv\"]'";
  const fs::path ref = solve_condensed(flags, "condensed-plate");
  if (ref.empty()) return;
  const nlohmann::json pb = nlohmann::json::parse(slurp(ref / "path.json"));
  ASSERT_EQ(pb["steps"].size(), 10u);
  for (const int processes : {2, 3}) {
    SCOPED_TRACE(std::to_string(processes) + " processes");
    CommandRun m;
    const fs::path out = solve_across(processes, flags + " --linear petsc-gamg", "plate-np" + std::to_string(processes), &m);
    ASSERT_EQ(m.code, 0) << m.out << m.err;
    const nlohmann::json a = nlohmann::json::parse(slurp(out / "result.json"));
    EXPECT_TRUE(a["converged"].get<bool>());
    EXPECT_EQ(a["mesh"]["pieces"], processes);
    const nlohmann::json pa = nlohmann::json::parse(slurp(out / "path.json"));
    expect_path_steps_agree(pa, pb);
    expect_plane_path_columns_agree(out, ref);
  }
}

// a loading path of one body whose every file the pieces make (each default output, a plane's on
// 3 processes, a solid's on 2): rank 0 keeps its piece after the path too and writes the last
// step's files from it and what the processes gather of theirs, as a static solve's, each
// process its piece of the last step's solution.vtu; they say what one process's say
TEST(CliFullSpaceMpi, APathWhosePiecesMakeEveryFileIsWrittenFromThePieces) {
  struct Case {
    std::string flags, name, mesh_line, write;
    int processes, dim;
    std::vector<std::string> figures;
  } cases[] = {
      {scene("friction-coulomb.toml") + " --n 16 --set 'loads.body_force=[0.5, -2.0]'", "plane-path-results",
       "289 vertices, 256 elements, h = 0.0883883,",
       R"("result-json", "contact-csv", "displacement-csv", "stress-csv", "history-csv", "vtu", "u-nu-png", "deformed-png", "error-png")",
       3, 2, {"u_nu.png", "deformed.png", "error.png", "path.png"}},
      {scene("coulomb-block-3d.toml") + " --set 'mesh.n=[4, 4, 2]'", "solid-path-results",
       "75 vertices, 32 cells, 128 faces, h = 0.433013,",
       R"("vtu", "contact-csv", "displacement-csv", "stress-csv", "history-csv", "result-json", "deformed-png", "pressure-png")",
       2, 3, {"deformed.png", "pressure.png", "path.png"}}};
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    expect_pieces_make_the_results(c.flags, c.write, c.write, c.processes, 1, c.name, c.mesh_line, c.figures);
    const fs::path kept = scratch(c.name + "-kept-rank0"), whole = scratch(c.name + "-whole-rank0");
    if (!fs::exists(kept / "result.json") || !fs::exists(whole / "solution.vtu")) continue;  // failed above
    const nlohmann::json a = nlohmann::json::parse(slurp(kept / "result.json"));
    EXPECT_TRUE(a["converged"].get<bool>());
    expect_pieces_make_the_whole(kept, "solution", whole / "solution.vtu", c.processes, {"von_mises", "error_indicator"},
                                 a["files"]);
    // the steps' files, made from the pieces as the steps came
    const nlohmann::json pa = nlohmann::json::parse(slurp(kept / "path.json"));
    const nlohmann::json pb = nlohmann::json::parse(slurp(whole / "path.json"));
    ASSERT_EQ(pa["steps"].size(), pb["steps"].size());
    for (std::size_t k = 0; k < pb["steps"].size(); ++k) {
      const double ea = pa["steps"][k]["energy"].get<double>(), eb = pb["steps"][k]["energy"].get<double>();
      EXPECT_NEAR(ea, eb, 1e-8 * std::abs(eb)) << "step " << k + 1;
    }
    // every frame's displacement: path-displacement.csv's columns after step, t, vertex and its coordinates
    const std::size_t from = 3 + static_cast<std::size_t>(c.dim), to = from + static_cast<std::size_t>(c.dim);
    EXPECT_GT(expect_columns_agree(kept / "path-displacement.csv", whole / "path-displacement.csv", from, to), 0.0);
  }
}

// the same path writing no VTU frame: rank 0 too makes only its piece, writes path.json and the
// steps' tables from it, and the results' files from the whole mesh made after the path
TEST(CliFullSpaceMpi, APathWithoutVtuFramesRunsOnEveryProcesssPiece) {
  const std::string flags = scene("friction-coulomb.toml") +
                            " --n 16 --set 'loads.body_force=[0.5, -2.0]' --set 'output.write=[\"result-json\", "
                            "\"displacement-csv\", \"contact-csv\"]'";
  const fs::path ref = solve_condensed(flags, "condensed-path-tables");
  if (ref.empty()) return;
  CommandRun m;
  const fs::path out = solve_across(2, flags + " --linear petsc-gamg -q", "path-tables-np2", &m);
  ASSERT_EQ(m.code, 0) << m.out << m.err;
  const nlohmann::json a = nlohmann::json::parse(slurp(out / "result.json"));
  const nlohmann::json b = nlohmann::json::parse(slurp(ref / "result.json"));
  EXPECT_TRUE(a["converged"].get<bool>());
  EXPECT_EQ(a["mesh"]["pieces"], 2);
  for (const char* key : {"vertices", "elements", "h"}) EXPECT_EQ(a["mesh"][key], b["mesh"][key]) << key;
  EXPECT_FALSE(fs::exists(out / "solution.pvd"));
  EXPECT_FALSE(fs::exists(out / "solution.vtu"));
  const nlohmann::json pa = nlohmann::json::parse(slurp(out / "path.json"));
  const nlohmann::json pb = nlohmann::json::parse(slurp(ref / "path.json"));
  ASSERT_EQ(pa["steps"].size(), pb["steps"].size());
  for (std::size_t k = 0; k < pb["steps"].size(); ++k) {
    SCOPED_TRACE("step " + std::to_string(k + 1));
    expect_applied_load_agrees(pa["steps"][k], pb["steps"][k]);
  }
  // the frames' displacements (ux, uy) at every vertex, and the last step's
  const double u = expect_columns_agree(out / "path-displacement.csv", ref / "path-displacement.csv", 5, 7);
  EXPECT_GT(u, 0.0);
  expect_columns_agree(out / "displacement.csv", ref / "displacement.csv", 3, 5);
}

// an adaptive solve: every process holds each step's whole solution and error indicators, marks
// and refines the same mesh, and keeps only its piece of each step's mesh for the solve (a
// refined mesh made again from the scene's after the solve); the meshes, estimates and energies
// are the one-process run's, in a plane and in a solid
TEST(CliFullSpaceMpi, AnAdaptiveSolveAcrossProcessesRefinesAsOneProcessDoes) {
  struct Case {
    int dim;
    std::string flags;
  };
  const std::vector<Case> cases{
      {2, "--n 8 --adapt --set adapt.max_steps=4 --linear petsc-gamg"},
      {3, scene("example-4.1-3d.toml") + " --set 'mesh.n=[4, 4, 4]' --adapt --set adapt.max_steps=4 --linear petsc-gamg"},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(k.flags);
    const std::string name = "adapt" + std::to_string(k.dim) + "d";
    const fs::path ref = scratch(name + "-np1");
    const CommandRun c = run(binary() + " solve " + k.flags + " -q --out " + ref.string());
    ASSERT_EQ(c.code, 0) << c.err;
    CommandRun m;
    const fs::path out = solve_across(2, k.flags, name + "-np2", &m);
    ASSERT_EQ(m.code, 0) << m.out << m.err;
    EXPECT_EQ(count(m.err, "adapt step 3:"), 1u) << "rank 0 alone tells the steps: " << m.err;
    EXPECT_FALSE(fs::exists(out.parent_path() / (name + "-np2-rank1"))) << "rank 1 wrote outputs";
    const nlohmann::json a = nlohmann::json::parse(slurp(out / "result.json"));
    const nlohmann::json b = nlohmann::json::parse(slurp(ref / "result.json"));
    EXPECT_EQ(a["processes"], 2);
    // the last step, on a refined mesh, was solved on the processes' pieces of it
    EXPECT_EQ(a["mesh"]["pieces"], 2);
    EXPECT_EQ(a["mesh"]["elements"], b["mesh"]["elements"]);
    EXPECT_EQ(a["mesh"]["vertices"], b["mesh"]["vertices"]);
    EXPECT_EQ(a["adapt"]["stopped"], "max_steps");
    ASSERT_EQ(a["adapt"]["steps"].size(), 4u);
    ASSERT_EQ(a["adapt"]["steps"].size(), b["adapt"]["steps"].size());
    for (std::size_t s = 0; s < b["adapt"]["steps"].size(); ++s) {
      SCOPED_TRACE("step " + std::to_string(s));
      const auto &x = a["adapt"]["steps"][s], &y = b["adapt"]["steps"][s];
      EXPECT_EQ(x["elements"], y["elements"]);
      EXPECT_EQ(x["unknowns"], y["unknowns"]);
      EXPECT_EQ(x["marked"], y["marked"]);
      EXPECT_NEAR(x["estimate"].get<double>(), y["estimate"].get<double>(), 1e-8 * y["estimate"].get<double>());
      const double ex = x["potential_energy"].get<double>(), ey = y["potential_energy"].get<double>();
      EXPECT_NEAR(ex, ey, 1e-9 * std::abs(ey));
    }
    EXPECT_GT(a["adapt"]["steps"][3]["elements"].get<int>(), a["adapt"]["steps"][0]["elements"].get<int>());
    expect_columns_agree(out / "displacement.csv", ref / "displacement.csv", static_cast<std::size_t>(k.dim + 1),
                         static_cast<std::size_t>(2 * k.dim + 1));
    if (k.dim == 2) {
      EXPECT_TRUE(fs::exists(out / "adapt.pvd"));
    }
  }
}

TEST(CliFullSpaceMpi, WhatTheRouteRunsInOneProcessIsRefusedOnSeveral) {
  struct Case {
    std::string flags, expected;
  };
  const std::vector<Case> cases{
      {"--n 8 --linear eigen-cg", "the linear engine 'eigen-cg' runs in one process"},
      // "auto" takes the route across processes only where the route takes the scene
      {"--n 8 --minimizer bundle-dca", "the linear engine 'auto' runs in one process here (\"auto\" runs across "
                                       "processes on the full-space route"},
  };
  for (const Case& k : cases) {
    SCOPED_TRACE(k.flags);
    const fs::path out = scratch("refused");
    const CommandRun m = run(mpiexec() + " " + np(2) + " " + binary() + " solve " + k.flags + " --out " + out.string());
    EXPECT_EQ(m.code, 2) << m.err;
    EXPECT_EQ(count(m.err, "hemivem: error:"), 1u) << m.err;
    EXPECT_EQ(count(m.err, k.expected), 1u) << m.err;
    EXPECT_FALSE(fs::exists(out));
  }
}

// "auto" under a launcher takes the route that runs across the processes, and says so: the
// condensed route's answer in one process, rank 0 alone writing
TEST(CliFullSpaceMpi, AutoUnderALauncherSolvesAcrossTheProcesses) {
  const std::string flags = scene("example-4.1-3d.toml") + " --set 'mesh.n=[6, 6, 6]' --tol 1e-11";
  const fs::path ref = solve_condensed(flags, "auto-one");
  if (ref.empty()) return;
  CommandRun m;
  const fs::path out = solve_across(2, flags, "auto-np2", &m);
  ASSERT_EQ(m.code, 0) << m.out << m.err;
  const std::string why = "solver.linear = \"auto\": started as 2 processes by an MPI launcher; solved across them "
                          "on the full-space route with petsc-gamg";
  EXPECT_EQ(count(m.err, why), 1u) << m.err;
  EXPECT_EQ(count(m.out, "linear petsc-gamg (2 processes)"), 1u) << m.out;
  EXPECT_FALSE(fs::exists(scratch("auto-np2-rank1"))) << "rank 1 wrote outputs";
  const nlohmann::json a = nlohmann::json::parse(slurp(out / "result.json"));
  const nlohmann::json b = nlohmann::json::parse(slurp(ref / "result.json"));
  EXPECT_EQ(a["processes"], 2);
  EXPECT_EQ(a["backends"]["linear"], "petsc-gamg");
  ASSERT_FALSE(a["warnings"].empty()) << a.dump();
  EXPECT_NE(a["warnings"][0].get<std::string>().find(why), std::string::npos) << a["warnings"].dump();
  const double ea = a["potential_energy"].get<double>(), eb = b["potential_energy"].get<double>();
  EXPECT_NEAR(ea, eb, 1e-9 * std::abs(eb));
  expect_columns_agree(out / "displacement.csv", ref / "displacement.csv", 4, 7);
}

// the memory check counts every process of a run (each its share of the problem, besides its
// libraries and what every process holds): a limit above one process's estimate (122 MiB) and
// below what two take together (181 MiB) lets one process run and refuses two alike, before
// anything is made or written
TEST(CliFullSpaceMpi, TheMemoryCheckCountsEveryProcess) {
  const std::string flags = scene("example-4.1-3d.toml") + " --set 'mesh.n=[16, 16, 16]' --linear petsc-gamg -q";
  const std::string limit = "env HEMIVEM_MEMORY_LIMIT=150M ";
  const fs::path one = scratch("memory-one"), two = scratch("memory-two");
  const CommandRun a = run(limit + binary() + " solve " + flags + " --out " + one.string());
  EXPECT_EQ(a.code, 0) << a.err;
  const CommandRun m = run(limit + mpiexec() + " " + np(2) + " " + binary() + " solve " + flags + " --out " + two.string());
  EXPECT_EQ(m.code, 2) << m.err;
  EXPECT_EQ(count(m.err, "hemivem: error:"), 1u) << m.err;
  EXPECT_EQ(count(m.err, "of memory across 2 processes (122 MiB in one process)"), 1u) << m.err;
  EXPECT_FALSE(fs::exists(two));
}

/// The scene `name` (a block between rollers on a linear foundation) on a rigid plane at the gap
/// 0.02 instead, written to a scratch file: a body that its contact alone holds, by a constraint.
fs::path block_on_a_plane(const std::string& name) {
  std::string text = slurp(scene(name));
  const std::string foundation = "[contact.parameters]\nstiffness = 50.0\n";
  const auto at = text.find(foundation);
  EXPECT_NE(at, std::string::npos) << name;
  if (at != std::string::npos) text.erase(at, foundation.size());
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"law = \"linear\"", "law = \"zero\""}, {"constraint = \"none\"", "constraint = \"one-sided\"\ngap = 0.02"}}) {
    const auto k = text.find(from);
    EXPECT_NE(k, std::string::npos) << from;
    if (k != std::string::npos) text.replace(k, from.size(), to);
  }
  const fs::path toml = scratch("plane-" + name);
  fs::create_directories(toml.parent_path());
  std::ofstream(toml) << text;
  return toml;
}

// bodies that their contact alone holds (their free translation proved bounded from the whole
// contact surface, gathered on every process; the proximal term of the Newton systems where the
// active set leaves it free), on a foundation, on a rigid plane, and two boxes: the condensed answer
TEST(CliFullSpaceMpi, ABodyHeldByItsContactAloneAcrossProcessesIsTheCondensedAnswer) {
  const std::vector<std::string> flags{
      scene("block-between-rollers.toml") + " --set 'mesh.n=[16, 4]' --set 'loads.body_force=[0.0, -1.0]'",
      scene("block-between-rollers-3d.toml") + " --set 'mesh.n=[4, 3, 4]' --set 'loads.body_force=[0.0, 0.0, -1.0]'",
      block_on_a_plane("block-between-rollers.toml").string() + " --set 'mesh.n=[16, 4]' --set 'loads.body_force=[0.0, -1.0]'",
      block_on_a_plane("block-between-rollers-3d.toml").string() +
          " --set 'mesh.n=[4, 3, 4]' --set 'loads.body_force=[0.0, 0.0, -1.0]'",
      scene("two-boxes-3d.toml") + " --set 'body[0].loads.body_force=[0.0, 0.0, -1.0]'" +
          " --set 'body[1].loads.body_force=[0.0, 0.0, -1.0]'" + " --set 'body[0].mesh.n=[8, 8, 6]'" +
          " --set 'body[1].mesh.n=[7, 7, 6]'"};
  for (std::size_t k = 0; k < flags.size(); ++k) {
    SCOPED_TRACE(flags[k]);
    const std::string f = flags[k] + " --tol 1e-11";
    const std::string name = "held-" + std::to_string(k);
    const fs::path ref = solve_condensed(f, "condensed-" + name);
    if (ref.empty()) continue;
    const nlohmann::json one = nlohmann::json::parse(slurp(ref / "result.json"));
    for (const int processes : {2, 3}) {
      nlohmann::json a;
      expect_processes_agree(f, ref, processes, name, false, processes, &a);
      EXPECT_EQ(a["held_by_contact"].size(), 1u) << a["held_by_contact"].dump();
      // the motion named as one process names it (of two bodies: the moving body's whole cells)
      EXPECT_EQ(a["held_by_contact"], one["held_by_contact"]);
      EXPECT_TRUE(a["may_be_nonunique"].get<bool>());
    }
  }
}

// the block pulled off the plane: every process finds E unbounded below along its translation at
// the rate of the load's work (2 on a top of 4), before iterating; every rank exits 3
TEST(CliFullSpaceMpi, ABodyPulledOffItsOnlySupportIsUnboundedOnEveryProcess) {
  const fs::path dir = scratch("pulled-off");
  fs::create_directories(dir);
  const std::string solve = binary() + " solve " + block_on_a_plane("block-between-rollers.toml").string() +
                            " --set \"loads.traction[0].value=[0.0, 2.0]\" --linear petsc-gamg -q --out " + (dir / "out").string();
  const auto ranked = [&](int r) {
    return np(1) + " sh -c '" + solve + "; echo $? > " + (dir / ("code" + std::to_string(r))).string() + "'";
  };
  const CommandRun m = run(mpiexec() + " " + ranked(0) + " : " + ranked(1));
  ASSERT_EQ(m.code, 0) << m.err;
  EXPECT_EQ(slurp(dir / "code0"), "3\n");
  EXPECT_EQ(slurp(dir / "code1"), "3\n");
  const nlohmann::json a = nlohmann::json::parse(slurp(dir / "out" / "result.json"));
  EXPECT_EQ(a["status"], "unbounded");
  EXPECT_EQ(a["processes"], 2);
  EXPECT_EQ(a["iterations"], 0);
  const std::string message = a["message"].get<std::string>();
  EXPECT_NE(message.find("at the rate -8 per unit of motion"), std::string::npos) << message;
  EXPECT_NE(message.find("there is no solution"), std::string::npos) << message;
}

}  // namespace
