// The hemivem command.
//
//   hemivem solve [SCENE.toml] [flags]   a contact problem (default: the paper's Example 4.1)
//   hemivem minimize DIR [flags]         a reduced problem from files
//   hemivem mesh KIND --n N -o FILE      a generated mesh as .poly2d (--ny: cells along y); a 3D
//                                        one (cubes, tetrahedra, a box --domain of six numbers) as .msh
//   hemivem study [SCENE.toml] [flags]   the convergence study of Table 1 (squares, reference N)
//   hemivem backends                     the engines that were built
//   hemivem check [SCENE.toml] [flags]   every pair of engines on one scene, compared
//   hemivem bench [SCENE.toml] [flags]   time against error for every pair of engines
#include <CLI/CLI.hpp>

#include <hemivem/krylov_solver.hpp>
#include <hemivem/certificate.hpp>
#include <hemivem/engine_names.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/poly2d.hpp>
#include <hemivem/mesh/gmsh3d.hpp>
#include <hemivem/support/atomic_file.hpp>
#include <hemivem/scene/resources.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/nonsmooth_backends.hpp>

#include <algorithm>
#include <cctype>
#include <charconv>
#include <system_error>
#include <cmath>
#include <chrono>
#include <functional>
#include <memory>
#include <iostream>
#include <thread>

#include <malloc.h>

#include "bench.hpp"
#include "check.hpp"
#include "extreme.hpp"
#include "limit.hpp"
#include "commands.hpp"
#include "common.hpp"
#include "study.hpp"

namespace {

std::string engines_text() {
  std::string s = "linear engines:";
  for (const auto& n : hemivem::available_factorizations()) s += " " + n;
  s += "\nkrylov engines (the full-space route):";
  for (const auto& n : hemivem::available_krylov_solvers()) s += " " + n;
  s += "\nminimizers:";
  for (const auto& n : hemivem::available_minimizers()) s += " " + n;
  return s;
}

/// A number > 0 (CLI11's PositiveNumber prints the largest double in full).
const CLI::Validator kPositive(
    [](std::string& text) -> std::string {
      try {
        std::size_t used = 0;
        const double v = std::stod(text, &used);
        if (used == text.size() && v > 0.0 && std::isfinite(v)) return {};
      } catch (const std::exception&) {
      }
      return "expected a number > 0, got '" + text + "'";
    },
    "NUMBER > 0");

/// A certificate tolerance: a number in [min_tolerance, max_tolerance] (hemivem/certificate.hpp).
const CLI::Validator kTolerance(
    [](std::string& text) -> std::string {
      try {
        std::size_t used = 0;
        const double v = std::stod(text, &used);
        if (used == text.size()) return hemivem::tolerance_problem(v);
      } catch (const std::exception&) {
      }
      return "expected a number, got '" + text + "'";
    },
    "TOLERANCE");

/// A cell count: an integer in [1, 10000000] (CLI::Range says "not in range" of a word too).
const CLI::Validator kCellCount(
    [](std::string& text) -> std::string {
      long long v = 0;
      const auto [end, ec] = std::from_chars(text.data(), text.data() + text.size(), v);
      if (ec == std::errc::result_out_of_range || (ec == std::errc() && end == text.data() + text.size()))
        return ec == std::errc() && v >= 1 && v <= 10000000 ? std::string()
                                                            : "must be in [1, 10000000], got " + text;
      return "expected an integer, got '" + text + "'";
    },
    "INT in [1 - 10000000]");

std::vector<std::string> names_of(const std::vector<CLI::App*>& apps) {
  std::vector<std::string> v;
  for (const auto* a : apps) v.push_back(a->get_name());
  return v;
}

/// What CLI11 would say less clearly: an unknown command (with the nearest name when close),
/// and an option the chosen command does not take (before a value of it is read as a scene
/// file). Empty when the command line passes these checks.
std::string precheck(CLI::App& app, int argc, char** argv) {
  if (argc < 2) return {};
  const std::string first = argv[1];
  if (first.empty() || first[0] == '-') return {};
  const auto commands = names_of(app.get_subcommands([](CLI::App*) { return true; }));
  if (std::find(commands.begin(), commands.end(), first) == commands.end()) {
    std::string list;
    for (const auto& c : commands) list += (list.empty() ? "" : ", ") + c;
    return "unknown command '" + first + "'" + hemivem::did_you_mean(first, commands) + " (commands: " + list + ")";
  }
  CLI::App* sub = app.get_subcommand(first);
  for (int i = 2; i < argc; ++i) {
    const std::string a = argv[i];
    if (a == "--") break;
    if (a.size() < 2 || a[0] != '-' || std::isdigit(static_cast<unsigned char>(a[1])) || a[1] == '.') continue;
    const std::string name = a.substr(0, a.find('='));
    if (sub->get_option_no_throw(name) != nullptr || app.get_option_no_throw(name) != nullptr) continue;
    std::vector<std::string> options;
    for (const auto* o : sub->get_options())
      for (const auto& l : o->get_lnames()) options.push_back("--" + l);
    return "'" + first + "' takes no option " + name + hemivem::did_you_mean(name, options) + " (hemivem " + first +
           " --help lists its options)";
  }
  return {};
}

/// A subcommand: its definition in CLI11 and what runs it once the command line is parsed.
struct Command {
  CLI::App* app = nullptr;
  std::function<int()> run;
};

// Each register_* function defines one subcommand; its flags live in an object the returned
// Command owns (CLI11 writes into them while parsing).

Command register_solve(CLI::App& app) {
  struct Flags {
    hemivem::cli::SolveOptions options;
    bool quiet = false, verbose = false;
    std::string mesh, linear, minimizer, figures;
    int n = 0;
    double tol = 0.0;
    CLI::Option *o_mesh = nullptr, *o_n = nullptr, *o_linear = nullptr, *o_min = nullptr, *o_tol = nullptr;
  };
  using namespace hemivem;
  auto f = std::make_shared<Flags>();
  auto* cmd = app.add_subcommand("solve", "Solve a contact scene (no scene: the paper's Example 4.1, squares N = 64)");
  cmd->add_option("scene", f->options.scene, "Scene file (TOML, see docs/reference/scenes.md)")->check(CLI::ExistingFile);
  f->o_mesh = cmd->add_option("--mesh", f->mesh, "squares|triangles|voronoi|nonconvex|distorted|PATH.poly2d|PATH.msh");
  f->o_n = cmd->add_option("--n", f->n, "Elements (or Voronoi seeds) per side")->check(kCellCount);
  f->o_linear = cmd->add_option("--linear", f->linear,
                                join_engine_names(known_linear_engines(), "|") + "|auto (the fastest built; default); the full-space route: " +
                                    join_engine_names(known_krylov_solvers(), "|"));
  f->o_min = cmd->add_option("--minimizer", f->minimizer, join_engine_names(known_minimizers(), "|"));
  f->o_tol = cmd->add_option("--tol", f->tol, "Certificate tolerance")->check(kPositive)->check(kTolerance);
  cmd->add_option("--set", f->options.set, "Override a scene key: key=value (repeatable), e.g. contact.gap=0.01");
  cmd->add_option("--out", f->options.out, "Output folder")->capture_default_str();
  cmd->add_option("--export-reduced", f->options.export_reduced, "Also write the reduced problem to this folder");
  cmd->add_flag("--json", f->options.json, "Print result.json on stdout instead of the summary");
  cmd->add_flag("-q,--quiet", f->quiet, "Print nothing on success");
  cmd->add_flag("-v,--verbose", f->verbose, "Also print every minimizer iteration (stderr)");
  cmd->add_flag("--global", f->options.global,
                "Search for the lowest critical point: several starts with every built minimizer (solver.search = "
                "\"global\"; budget: solver.max_starts, solver.time_budget, solver.seed)");
  cmd->add_flag("--adapt", f->options.adapt,
                "Refine adaptively until the error estimate reaches adapt.target (the scene's [adapt], or target 1 %, "
                "fraction 0.5, max_steps 30, max_unknowns 1000000; change them with --set adapt.KEY=VALUE)");
  auto* o_figures = cmd->add_option("--figures", f->figures,
                                    "The figures' formats, comma-separated: png, pdf, svg (output.figure_format; default png)");
  return {cmd, [f, o_figures] {
            cli::SolveOptions& o = f->options;
            if (*o_figures) o.figures = f->figures;
            if (*f->o_mesh) o.mesh = f->mesh;
            if (*f->o_n) o.n = f->n;
            if (*f->o_linear) o.linear = f->linear;
            if (*f->o_min) o.minimizer = f->minimizer;
            if (*f->o_tol) o.tolerance = f->tol;
            o.verbosity = f->quiet ? 0 : (f->verbose ? 2 : 1);
            return cli::run_solve(o, std::cout, std::cerr);
          }};
}

Command register_minimize(CLI::App& app) {
  struct Flags {
    hemivem::cli::MinimizeOptions options;
    bool quiet = false;
  };
  using namespace hemivem;
  auto f = std::make_shared<Flags>();
  auto* cmd = app.add_subcommand("minimize", "Solve a reduced problem read from files (see --export-reduced)");
  cmd->add_option("dir", f->options.folder, "Folder with S.mtx, c.txt, w.txt, g.txt[, law.txt, problem.txt]")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--minimizer", f->options.minimizer, join_engine_names(known_minimizers(), "|"))->capture_default_str();
  cmd->add_option("--law", f->options.law, "A shipped law replacing law.txt: paper|linear|kinked|sawtooth|zero");
  cmd->add_option("--tol", f->options.tolerance, "Certificate tolerance")->capture_default_str()->check(kPositive)->check(kTolerance);
  cmd->add_flag("--json", f->options.json, "Print the result as JSON");
  cmd->add_flag("-q,--quiet", f->quiet, "Print nothing on success");
  cmd->add_flag("--global", f->options.global,
                "Search for the lowest critical point: several starts with every built minimizer, --minimizer first");
  cmd->add_option("--max-starts", f->options.search.max_starts, "Global search: the most local runs")
      ->capture_default_str()
      ->check(CLI::Range(1, 1000000));
  cmd->add_option("--time-budget", f->options.search.time_budget, "Global search: seconds after which no run begins")
      ->capture_default_str()
      ->check(kPositive);
  cmd->add_option("--engines", f->options.engines,
                  "Global search: the engines besides --minimizer, comma-separated (default: every built one)")
      ->delimiter(',');
  cmd->add_option("--seed", f->options.search.seed, "Global search: the seed of the random starts")
      ->capture_default_str()
      ->check(CLI::Range(0, 2147483647));
  return {cmd, [f] {
            f->options.verbosity = f->quiet ? 0 : 1;
            return cli::run_minimize(f->options, std::cout, std::cerr);
          }};
}

/// `hemivem mesh` of a three-dimensional kind: the box of `domain` (six numbers, or the unit cube)
/// meshed by a generator of generators3d.hpp and written as a Gmsh file.
hemivem::cli::ExitCode write_mesh_3d(const std::string& kind, int nx, int ny, int nz, const std::vector<double>& domain, std::uint64_t seed,
                  const std::string& output) {
  using namespace hemivem;
  const auto& kinds = mesh3d_generator_names();
  if (std::find(kinds.begin(), kinds.end(), kind) == kinds.end()) {
    std::string list;
    for (const auto& k : kinds) list += (list.empty() ? "" : ", ") + k;
    throw InputError("unknown three-dimensional mesh generator '" + kind + "'" + did_you_mean(kind, kinds) +
                         " (expected one of: " + list + ")",
                     "mesh");
  }
  if (std::filesystem::path(output).extension() != ".msh")
    throw InputError("a three-dimensional mesh is written as a Gmsh file: give an output ending in .msh", "mesh -o");
  const GridSize3 cells(nx, ny, nz);
  require_memory(estimate_memory_3d(kind, nx, ny, nz).mesh_bytes, kind + " n = " + cells.text(), "--n");
  const Box box = domain.size() == 6 ? Box{domain[0], domain[1], domain[2], domain[3], domain[4], domain[5]} : Box{};
  const Mesh3D m = make_mesh3d(kind, cells, box, seed);
  try {
    write_gmsh3d(m, std::filesystem::path(output));  // atomically: a failure leaves no half-written file
  } catch (const WriteError&) {
    throw;
  } catch (const InputError& e) {  // a cell Gmsh has no element for (a Voronoi polyhedron)
    throw InputError("the " + kind + " mesh cannot be written as a Gmsh file: " + e.detail(), output);
  }
  std::cout << "hemivem mesh: wrote " << output << " (" << m.num_vertices() << " vertices, " << m.num_cells()
            << " cells)\n";
  return cli::kSuccess;
}

Command register_mesh(CLI::App& app) {
  struct Flags {
    std::string kind, output;
    int n = 8, ny = 0, nz = 0;
    std::uint64_t seed = 1;
    std::vector<double> domain{0.0, 1.0, 0.0, 1.0};
    std::vector<double> polygon;
  };
  using namespace hemivem;
  auto f = std::make_shared<Flags>();
  auto* cmd = app.add_subcommand("mesh", "Write a generated mesh as .poly2d (a three-dimensional one as .msh)");
  cmd->add_option("kind", f->kind, "squares|triangles|voronoi|nonconvex|distorted; in 3D cubes|tetrahedra|voronoi")
      ->required();
  cmd->add_option("--n", f->n, "Elements (or seeds) per side; along x with --ny")->capture_default_str()->check(kCellCount);
  auto* o_ny = cmd->add_option("--ny", f->ny, "Elements along y (a rectangle domain; default: --n)")->check(kCellCount);
  auto* o_nz = cmd->add_option("--nz", f->nz, "Elements along z (a box: three-dimensional; default: --n)")
                   ->check(CLI::Range(1, 1000));
  cmd->add_option("--seed", f->seed, "Seed of random meshes")->capture_default_str();
  auto* o_domain = cmd->add_option("--domain", f->domain, "x0 x1 y0 y1, or x0 x1 y0 y1 z0 z1 (a box: three-dimensional)")
                       ->expected(4, 6)
                       ->capture_default_str();
  cmd->add_option("--polygon", f->polygon, "A simple polygon's corners x0 y0 x1 y1 ... (triangles, voronoi)")
      ->type_name("X Y")
      ->expected(6, CLI::detail::expected_max_vector_size)
      ->excludes(o_domain)
      ->excludes(o_ny)
      ->excludes(o_nz);
  cmd->add_option("-o,--output", f->output, "Output .poly2d file (.msh for a three-dimensional mesh)")->required();
  return {cmd, [f, o_nz] {
            if (f->domain.size() != 4 && f->domain.size() != 6)
              throw InputError("--domain takes 4 numbers (a rectangle x0 x1 y0 y1) or 6 (a box x0 x1 y0 y1 z0 z1); got " +
                                   std::to_string(f->domain.size()),
                               "mesh --domain");
            const auto& solid = mesh3d_generator_names();
            const auto& plane = mesh_generator_names();
            const bool solid_only = std::find(solid.begin(), solid.end(), f->kind) != solid.end() &&
                                    std::find(plane.begin(), plane.end(), f->kind) == plane.end();
            if (f->domain.size() == 6 || *o_nz || solid_only) {
              if (f->n > 1000)
                throw InputError("a three-dimensional mesh takes at most 1000 cells per axis; got --n " + std::to_string(f->n),
                                 "mesh --n");
              const int ny = f->ny > 0 ? f->ny : f->n, nz = f->nz > 0 ? f->nz : f->n;
              if (ny > 1000) throw InputError("a three-dimensional mesh takes at most 1000 cells per axis", "mesh --ny");
              return write_mesh_3d(f->kind, f->n, ny, nz, f->domain, f->seed, f->output);
            }
            const auto& kinds = mesh_generator_names();
            if (std::find(kinds.begin(), kinds.end(), f->kind) == kinds.end()) {
              std::string list;
              for (const auto& k : kinds) list += (list.empty() ? "" : ", ") + k;
              throw InputError("unknown mesh generator '" + f->kind + "'" + did_you_mean(f->kind, kinds) +
                                   " (expected one of: " + list + ")",
                               "mesh");
            }
            const GridSize cells(f->n, f->ny > 0 ? f->ny : f->n);
            const MemoryEstimate need = estimate_memory(f->kind, cells.nx, cells.ny);
            require_memory(need.mesh_bytes, f->kind + " n = " + cells.text(), "--n");
            Mesh m;
            if (f->polygon.empty()) {
              m = make_mesh(f->kind, cells, Rectangle{f->domain[0], f->domain[1], f->domain[2], f->domain[3]}, f->seed);
            } else {
              if (f->polygon.size() > 2000000)
                throw InputError("--polygon takes at most 1000000 corners; got " + std::to_string(f->polygon.size() / 2),
                                 "mesh --polygon");
              if (f->polygon.size() % 2 != 0)
                throw InputError("--polygon takes pairs of coordinates x y; got " + std::to_string(f->polygon.size()) +
                                     " numbers",
                                 "mesh --polygon");
              PolygonDomain poly;
              for (std::size_t i = 0; i < f->polygon.size(); i += 2) poly.corners.emplace_back(f->polygon[i], f->polygon[i + 1]);
              m = make_mesh(f->kind, f->n, poly, f->seed);
            }
            write_poly2d(f->output, m, {f->kind + " n=" + cells.text() + " seed=" + std::to_string(f->seed)});
            std::cout << "hemivem mesh: wrote " << f->output << " (" << m.num_vertices() << " vertices, "
                      << m.num_elements() << " elements)\n";
            return cli::kSuccess;
          }};
}

Command register_study(CLI::App& app) {
  struct Flags {
    hemivem::cli::StudyOptions options;
    bool quiet = false;
    std::string n = "4,8,16,32,64";  ///< --n as given: parsed by parse_sizes, which names a bad entry
    std::string figures;             ///< --figures as given
  };
  auto f = std::make_shared<Flags>();
  auto* cmd = app.add_subcommand(
      "study", "Convergence study on nested squares: relative energy error against a reference N (Table 1)");
  cmd->add_option("scene", f->options.scene, "Scene file (TOML, see docs/reference/scenes.md); mesh.generator must be squares")
      ->check(CLI::ExistingFile);
  cmd->add_option("--n", f->n, "Elements per side of the studied meshes, comma-separated")->capture_default_str();
  cmd->add_option("--ref", f->options.ref, "Elements per side of the reference mesh (a multiple of every N)")
      ->capture_default_str()
      ->check(kCellCount);
  cmd->add_option("--set", f->options.set, "Override a scene key for every solve: key=value (repeatable)");
  cmd->add_option("--out", f->options.out, "Output folder (study.csv, study.json, study.png)")->capture_default_str();
  auto* o_figures = cmd->add_option("--figures", f->figures,
                                    "The figure's formats, comma-separated: png, pdf, svg (output.figure_format; default png)");
  cmd->add_flag("--json", f->options.json, "Print study.json on stdout instead of the table");
  cmd->add_flag("-q,--quiet", f->quiet, "Print nothing on success (no progress lines)");
  return {cmd, [f, o_figures] {
            // before every --set, so that an explicit --set output.figure_format wins
            if (*o_figures) f->options.set.insert(f->options.set.begin(), hemivem::cli::figure_format_override(f->figures));
            f->options.verbosity = f->quiet ? 0 : 1;
            f->options.n = hemivem::cli::parse_sizes(f->n, "--n");
            return hemivem::cli::run_study(f->options, std::cout, std::cerr);
          }};
}

Command register_backends(CLI::App& app) {
  auto* cmd = app.add_subcommand("backends", "List the engines that were built");
  return {cmd, [] {
            std::cout << engines_text() << "\n";
            return hemivem::cli::kSuccess;
          }};
}

// check and check --extreme (drivers/check.hpp, drivers/extreme.hpp, docs/reference/check-bench.md)
Command register_check(CLI::App& app) {
  struct Flags {
    hemivem::cli::CheckOptions options;
    hemivem::cli::ExtremeOptions extreme;
    bool quiet = false, extreme_flag = false;
    int n = 0;
    double tol = 0.0;
    CLI::Option *o_n = nullptr, *o_tol = nullptr, *o_extreme = nullptr;
  };
  using namespace hemivem;
  auto f = std::make_shared<Flags>();
  auto* cmd = app.add_subcommand("check", "Solve a scene with every built pair of engines and compare the results");
  cmd->add_option("scene", f->options.scene, "Scene file (TOML); none: the paper's Example 4.1")->check(CLI::ExistingFile);
  f->o_n = cmd->add_option("--n", f->n, "Elements per side")->check(kCellCount);
  f->o_tol = cmd->add_option("--tol", f->tol, "Certificate tolerance for every pair")->check(kPositive)->check(kTolerance);
  cmd->add_option("--set", f->options.set, "Override a scene key: key=value (repeatable)");
  cmd->add_option("--agree", f->options.agree, "Largest accepted max|u_a - u_b| / max|u_ref| between converged pairs")
      ->capture_default_str()
      ->check(kPositive);
  cmd->add_flag("--json", f->options.json, "Print the report as JSON on stdout instead of the table");
  cmd->add_flag("-q,--quiet", f->quiet, "Print nothing (the exit code tells)");
  f->o_extreme = cmd->add_flag(
      "--extreme", f->extreme_flag, "Run the stiff and extreme scenes (scenes/extreme/) with every pair and print the stability table");
  cmd->add_option("--scenes", f->extreme.scenes, "With --extreme: the folder of scenes")
      ->check(CLI::ExistingDirectory)
      ->needs(f->o_extreme);
  cmd->add_option("--only", f->extreme.only, "With --extreme: scene names to run, comma-separated")
      ->delimiter(',')
      ->needs(f->o_extreme);
  return {cmd, [f] {
            cli::CheckOptions& o = f->options;
            if (*f->o_extreme) {
              if (!o.scene.empty() || *f->o_n || !o.set.empty())
                throw InputError("--extreme runs the scenes of its folder; it takes no scene, --n or --set", "check --extreme");
              if (*f->o_tol) f->extreme.tolerance = f->tol;
              f->extreme.agree = o.agree;
              f->extreme.json = o.json;
              f->extreme.verbosity = f->quiet ? 0 : 1;
              return cli::run_check_extreme(f->extreme, std::cout, std::cerr);
            }
            if (*f->o_n) o.n = f->n;
            if (*f->o_tol) o.tolerance = f->tol;
            o.verbosity = f->quiet ? 0 : 1;
            return cli::run_check(o, std::cout, std::cerr);
          }};
}

// bench and bench --limit (drivers/bench.hpp, drivers/limit.hpp, docs/reference/check-bench.md)
Command register_bench(CLI::App& app) {
  struct Flags {
    hemivem::cli::BenchOptions options;
    bool quiet = false, limit = false;
    double tol = 0.0, reference_energy = 0.0;
    int ref = 0, levels = 0;
    std::string n;  ///< --n as given: parsed by parse_sizes, which names a bad entry
    std::string figures;  ///< --figures as given
    CLI::Option *o_n = nullptr, *o_tol = nullptr, *o_reference_energy = nullptr, *o_ref = nullptr, *o_levels = nullptr;
  };
  using namespace hemivem;
  auto f = std::make_shared<Flags>();
  auto* cmd = app.add_subcommand("bench", "Wall time by stage and error against a fine reference, for every pair of engines");
  cmd->add_option("scene", f->options.scene, "Scene file (TOML); none: the paper's Example 4.1")->check(CLI::ExistingFile);
  f->o_n = cmd->add_option("--n", f->n,
                           "Mesh sizes, comma-separated (default 16,32,64,128; a three-dimensional scene: 4,8,16, "
                           "N x N x N cells; with --limit: 128,256,512, and 16,24,32 for a three-dimensional scene)");
  f->o_ref = cmd->add_option("--ref", f->ref,
                             "Mesh size of the reference solution (default 256; a three-dimensional scene: 32, a "
                             "multiple of every N)")
                 ->check(kCellCount);
  f->o_tol = cmd->add_option("--tol", f->tol, "Certificate tolerance for every pair")->check(kPositive)->check(kTolerance);
  cmd->add_option("--set", f->options.set, "Override a scene key: key=value (repeatable)");
  cmd->add_option("--out", f->options.out, "Output folder (bench.csv, bench.json, bench.png; with --limit: limit.json)")
      ->capture_default_str();
  auto* o_figures = cmd->add_option("--figures", f->figures,
                                    "The plots' formats, comma-separated: png, pdf, svg (output.figure_format; default png)");
  cmd->add_flag("--json", f->options.json, "Print bench.json on stdout instead of the table");
  cmd->add_flag("-q,--quiet", f->quiet, "Print nothing on stdout or stderr");
  f->o_levels = cmd->add_option("--levels", f->levels,
                                "Refinement study: uniform refinements of the scene's mesh (>= 1, default 3; the "
                                "adaptive run aims at the finest's estimate); a three-dimensional scene: its cell "
                                "counts doubled, default 2");
  f->o_reference_energy = cmd->add_option("--reference-energy", f->reference_energy,
                                          "Refinement study: the exact potential energy, for true errors (default: "
                                          "Aitken's extrapolation of the last three uniform levels)");
  auto* o_limit = cmd->add_flag("--limit", f->limit,
                                "Every stage of a cholmod solve against the machine's limit (a plain assembly and one CHOLMOD "
                                "factorization of the same matrix), measured in this run; writes limit.json");
  cmd->add_option("--repeat", f->options.repeat, "With --limit: measurements per size, the fastest of each kept")
      ->capture_default_str()
      ->check(CLI::Range(1, 100))
      ->needs(o_limit);
  return {cmd, [f, o_figures] {
            cli::BenchOptions& o = f->options;
            if (*o_figures) o.set.insert(o.set.begin(), cli::figure_format_override(f->figures));
            if (*f->o_n) o.n = cli::parse_sizes(f->n, "--n");
            if (*f->o_tol) o.tolerance = f->tol;
            if (*f->o_reference_energy) o.reference_energy = f->reference_energy;
            if (*f->o_ref) o.ref = f->ref;
            if (*f->o_levels) o.levels = f->levels;
            o.verbosity = f->quiet ? 0 : 1;
            if (f->limit) return cli::run_bench_limit(o, *f->o_n ? o.n : std::vector<int>{}, std::cout, std::cerr);
            return cli::run_bench(o, std::cout, std::cerr);
          }};
}

}  // namespace

int run_command(int argc, char** argv) {
  using namespace hemivem;
  CLI::App app{"hemivem: virtual element method for contact problems with nonmonotone laws"};
  app.set_version_flag("--version", std::string("hemivem ") + HEMIVEM_VERSION + "\n" + engines_text());
  app.require_subcommand(1);
  const std::vector<Command> commands{register_solve(app), register_minimize(app), register_mesh(app),
                                      register_study(app), register_backends(app), register_check(app),
                                      register_bench(app)};
  const Command& solve = commands.front();

  // ---- runs across processes (docs/cluster.md): only rank 0 prints; only solve runs on several ----
  try {
    if (const std::string problem = precheck(app, argc, argv); !problem.empty()) {
      if (cli::reporting_process()) std::cerr << "hemivem: error: " << problem << "\n";
      return cli::kInputError;
    }
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) {  // --help, --version
      if (cli::reporting_process()) app.exit(e);
      return cli::kSuccess;
    }
    if (cli::reporting_process()) {
      std::string what = e.what();
      if (what == "A subcommand is required")
        what = "a command is required: hemivem solve|minimize|mesh|study|check|bench|backends (hemivem --help)";
      std::cerr << "hemivem: error: " << what << "\n";
    }
    return cli::kInputError;
  }
  if (const auto launched = cli::launched_processes(); launched.size > 1 && !*solve.app) {
    if (launched.rank == 0)
      std::cerr << "hemivem: error: started as " << launched.size
                << " processes by an MPI launcher; only 'hemivem solve' runs across processes (with --linear "
                   "mumps-mpi, petsc-gamg or petsc-hypre): run this command without mpirun\n";
    return cli::kInputError;
  }
  // Errors every process meets alike (input, engine statuses) are reported by rank 0 alone;
  // any other failure by the process it happened on, with its rank.
  const auto report = [](const char* kind, const std::exception& e, bool shared) {
    if (cli::reporting_process())
      std::cerr << "hemivem: " << kind << e.what() << "\n";
    else if (!shared)
      std::cerr << "hemivem [rank " << std::max(cli::launched_processes().rank, factorization_process_rank())
                << "]: " << kind << e.what() << "\n";
  };
  // ---- end runs across processes ----

  try {
    for (const auto& c : commands)
      if (*c.app) return c.run();
  } catch (const InputError& e) {
    report("error: ", e, true);
    return cli::kInputError;
  } catch (const NumericalError& e) {
    report("backend failure: ", e, true);
    return cli::kBackendFailure;
  } catch (const hemivem::Error& e) {
    report("internal error: ", e, true);
    return cli::kInternalError;
  } catch (const std::exception& e) {
    report("internal error: ", e, false);
    return cli::kInternalError;
  }
  return cli::kSuccess;
}

int main(int argc, char** argv) {
  // Large blocks from the heap instead of fresh mappings: a solve allocates and frees matrices
  // of hundreds of megabytes, and every fresh page costs a page fault that zeroes it (a quarter
  // of the run time at N = 256-512, docs/performance.md); freed heap memory is reused instead.
  mallopt(M_MMAP_THRESHOLD, 1 << 30);
  const int code = run_command(argc, argv);
  // mpirun ends the whole job as soon as one process exits with an error. A rank > 0 has no
  // message of its own: it leaves rank 0 the time to print the error both met.
  if (code != hemivem::cli::kSuccess && !hemivem::cli::reporting_process())
    std::this_thread::sleep_for(std::chrono::milliseconds(500));
  return code;
}
