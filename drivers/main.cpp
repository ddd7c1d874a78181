// The hemivem command.
//
//   hemivem solve [SCENE.toml] [flags]   a contact problem (default: the paper's Example 4.1)
//   hemivem minimize DIR [flags]         a reduced problem from files
//   hemivem mesh KIND --n N -o FILE      a generated mesh as .poly2d
//   hemivem study [SCENE.toml] [flags]   the convergence study of Table 1 (squares, reference N)
//   hemivem backends                     the engines that were built
//   hemivem check [SCENE.toml] [flags]   every pair of engines on one scene, compared
//   hemivem bench [SCENE.toml] [flags]   time against error for every pair of engines
#include <CLI/CLI.hpp>

#include <hemivem/engine_names.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh_generators.hpp>
#include <hemivem/mesh_io.hpp>
#include <hemivem/resources.hpp>
#include <hemivem/scene.hpp>
#include <hemivem/nonsmooth_backends.hpp>

#include <algorithm>
#include <cctype>
#include <cmath>
#include <chrono>
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

}  // namespace

int run_command(int argc, char** argv) {
  using namespace hemivem;
  CLI::App app{"hemivem: virtual element method for contact problems with nonmonotone laws"};
  app.set_version_flag("--version", std::string("hemivem ") + HEMIVEM_VERSION + "\n" + engines_text());
  app.require_subcommand(1);

  cli::SolveOptions solve;
  bool solve_quiet = false, solve_verbose = false;
  std::string mesh_flag, linear_flag, minimizer_flag;
  int n_flag = 0;
  double tol_flag = 0.0;
  auto* cmd_solve = app.add_subcommand("solve", "Solve a contact scene (no scene: the paper's Example 4.1, squares N = 64)");
  cmd_solve->add_option("scene", solve.scene, "Scene file (TOML, see scenes/README.md)")->check(CLI::ExistingFile);
  auto* o_mesh = cmd_solve->add_option("--mesh", mesh_flag, "squares|triangles|voronoi|nonconvex|distorted|PATH.poly2d|PATH.msh");
  auto* o_n = cmd_solve->add_option("--n", n_flag, "Elements (or Voronoi seeds) per side")->check(CLI::Range(1, 10000000));
  auto* o_linear = cmd_solve->add_option("--linear", linear_flag,
                                         join_engine_names(known_linear_engines(), "|") + "|auto (the fastest built; default)");
  auto* o_min = cmd_solve->add_option("--minimizer", minimizer_flag, join_engine_names(known_minimizers(), "|"));
  auto* o_tol = cmd_solve->add_option("--tol", tol_flag, "Certificate tolerance")->check(kPositive);
  cmd_solve->add_option("--set", solve.set, "Override a scene key: key=value (repeatable), e.g. contact.gap=0.01");
  cmd_solve->add_option("--out", solve.out, "Output folder")->capture_default_str();
  cmd_solve->add_option("--export-reduced", solve.export_reduced, "Also write the reduced problem to this folder");
  cmd_solve->add_flag("--json", solve.json, "Print result.json on stdout instead of the summary");
  cmd_solve->add_flag("-q,--quiet", solve_quiet, "Print nothing on success");
  cmd_solve->add_flag("-v,--verbose", solve_verbose, "Also print every minimizer iteration (stderr)");

  cli::MinimizeOptions minimize;
  bool min_quiet = false;
  auto* cmd_min = app.add_subcommand("minimize", "Solve a reduced problem read from files (see --export-reduced)");
  cmd_min->add_option("dir", minimize.folder, "Folder with S.mtx, c.txt, w.txt, g.txt[, law.txt, problem.txt]")
      ->required()
      ->check(CLI::ExistingDirectory);
  cmd_min->add_option("--minimizer", minimize.minimizer, join_engine_names(known_minimizers(), "|"))->capture_default_str();
  cmd_min->add_option("--law", minimize.law, "A shipped law replacing law.txt: paper|linear|kinked|sawtooth|zero");
  cmd_min->add_option("--tol", minimize.tolerance, "Certificate tolerance")->capture_default_str()->check(kPositive);
  cmd_min->add_flag("--json", minimize.json, "Print the result as JSON");
  cmd_min->add_flag("-q,--quiet", min_quiet, "Print nothing on success");

  std::string gen_kind, gen_output;
  int gen_n = 8;
  std::uint64_t gen_seed = 1;
  std::vector<double> gen_domain{0.0, 1.0, 0.0, 1.0};
  auto* cmd_mesh = app.add_subcommand("mesh", "Write a generated mesh as .poly2d");
  cmd_mesh->add_option("kind", gen_kind, "squares|triangles|voronoi|nonconvex|distorted")->required();
  cmd_mesh->add_option("--n", gen_n, "Elements (or seeds) per side")->capture_default_str()->check(CLI::Range(1, 10000000));
  cmd_mesh->add_option("--seed", gen_seed, "Seed of random meshes")->capture_default_str();
  auto* o_domain = cmd_mesh->add_option("--domain", gen_domain, "x0 x1 y0 y1")->expected(4)->capture_default_str();
  std::vector<double> gen_polygon;
  cmd_mesh->add_option("--polygon", gen_polygon, "A simple polygon's corners x0 y0 x1 y1 ... (triangles, voronoi)")
      ->expected(6, 2000000)
      ->excludes(o_domain);
  cmd_mesh->add_option("-o,--output", gen_output, "Output .poly2d file")->required();

  // ---- study ------------------------------------------------------------------------------
  cli::StudyOptions study;
  bool study_quiet = false;
  auto* cmd_study = app.add_subcommand(
      "study", "Convergence study on nested squares: relative energy error against a reference N (Table 1)");
  cmd_study->add_option("scene", study.scene, "Scene file (TOML, see scenes/README.md); mesh.generator must be squares")
      ->check(CLI::ExistingFile);
  cmd_study->add_option("--n", study.n, "Elements per side of the studied meshes, e.g. 4,8,16,32,64")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Range(1, 10000000));
  cmd_study->add_option("--ref", study.ref, "Elements per side of the reference mesh (a multiple of every N)")
      ->capture_default_str()
      ->check(CLI::Range(1, 10000000));
  cmd_study->add_option("--set", study.set, "Override a scene key for every solve: key=value (repeatable)");
  cmd_study->add_option("--out", study.out, "Output folder (study.csv, study.json, study.png)")->capture_default_str();
  cmd_study->add_flag("--json", study.json, "Print study.json on stdout instead of the table");
  cmd_study->add_flag("-q,--quiet", study_quiet, "Print nothing on success (no progress lines)");
  // ---- end study --------------------------------------------------------------------------

  auto* cmd_backends = app.add_subcommand("backends", "List the engines that were built");

  // ---- check and bench (drivers/check.hpp, drivers/bench.hpp, drivers/CHECK_BENCH.md) ----
  cli::CheckOptions check;
  bool check_quiet = false;
  int check_n = 0;
  double check_tol = 0.0;
  auto* cmd_check = app.add_subcommand("check", "Solve a scene with every built pair of engines and compare the results");
  cmd_check->add_option("scene", check.scene, "Scene file (TOML); none: the paper's Example 4.1")->check(CLI::ExistingFile);
  auto* o_check_n = cmd_check->add_option("--n", check_n, "Elements per side")->check(CLI::Range(1, 10000000));
  auto* o_check_tol = cmd_check->add_option("--tol", check_tol, "Certificate tolerance for every pair")->check(kPositive);
  cmd_check->add_option("--set", check.set, "Override a scene key: key=value (repeatable)");
  cmd_check->add_option("--agree", check.agree, "Largest accepted max|u_a - u_b| / max|u_ref| between converged pairs")
      ->capture_default_str()
      ->check(kPositive);
  cmd_check->add_flag("--json", check.json, "Print the report as JSON on stdout instead of the table");
  cmd_check->add_flag("-q,--quiet", check_quiet, "Print nothing (the exit code tells)");
  cli::ExtremeOptions extreme;
  bool extreme_flag = false;
  auto* o_extreme = cmd_check->add_flag(
      "--extreme", extreme_flag, "Run the stiff and extreme scenes (scenes/extreme/) with every pair and print the stability table");
  auto* o_scenes = cmd_check->add_option("--scenes", extreme.scenes, "With --extreme: the folder of scenes")
                       ->check(CLI::ExistingDirectory)
                       ->needs(o_extreme);
  cmd_check->add_option("--only", extreme.only, "With --extreme: scene names to run, comma-separated")
      ->delimiter(',')
      ->needs(o_extreme);
  (void)o_scenes;

  cli::BenchOptions bench;
  bool bench_quiet = false;
  double bench_tol = 0.0;
  auto* cmd_bench = app.add_subcommand("bench", "Wall time by stage and error against a fine reference, for every pair of engines");
  cmd_bench->add_option("scene", bench.scene, "Scene file (TOML); none: the paper's Example 4.1")->check(CLI::ExistingFile);
  bool bench_limit = false;
  auto* o_bench_n = cmd_bench->add_option("--n", bench.n, "Mesh sizes, comma-separated (with --limit: default 128,256,512)")
      ->delimiter(',')
      ->capture_default_str()
      ->check(CLI::Range(1, 10000000));
  cmd_bench->add_option("--ref", bench.ref, "Mesh size of the reference solution")->capture_default_str()->check(CLI::Range(1, 10000000));
  auto* o_bench_tol = cmd_bench->add_option("--tol", bench_tol, "Certificate tolerance for every pair")->check(kPositive);
  cmd_bench->add_option("--set", bench.set, "Override a scene key: key=value (repeatable)");
  cmd_bench->add_option("--out", bench.out, "Output folder (bench.csv, bench.json, bench.png; with --limit: limit.json)")->capture_default_str();
  cmd_bench->add_flag("--json", bench.json, "Print bench.json on stdout instead of the table");
  cmd_bench->add_flag("-q,--quiet", bench_quiet, "Print nothing on stdout or stderr");
  auto* o_bench_limit = cmd_bench->add_flag("--limit", bench_limit,
                      "Every stage of a cholmod solve against the machine's limit (a plain assembly and one CHOLMOD "
                      "factorization of the same matrix), measured in this run; writes limit.json");
  cmd_bench->add_option("--repeat", bench.repeat, "With --limit: measurements per size, the fastest of each kept")
      ->capture_default_str()
      ->check(CLI::Range(1, 100))
      ->needs(o_bench_limit);
  // ---- end check and bench ----

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
  if (const auto launched = cli::launched_processes(); launched.size > 1 && !*cmd_solve) {
    if (launched.rank == 0)
      std::cerr << "hemivem: error: started as " << launched.size
                << " processes by an MPI launcher; only 'hemivem solve --linear mumps-mpi' runs across processes, "
                   "run this command without mpirun\n";
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
    if (*cmd_solve) {
      if (*o_mesh) solve.mesh = mesh_flag;
      if (*o_n) solve.n = n_flag;
      if (*o_linear) solve.linear = linear_flag;
      if (*o_min) solve.minimizer = minimizer_flag;
      if (*o_tol) solve.tolerance = tol_flag;
      solve.verbosity = solve_quiet ? 0 : (solve_verbose ? 2 : 1);
      return cli::run_solve(solve, std::cout, std::cerr);
    }
    if (*cmd_min) {
      minimize.verbosity = min_quiet ? 0 : 1;
      return cli::run_minimize(minimize, std::cout, std::cerr);
    }
    if (*cmd_study) {  // study
      study.verbosity = study_quiet ? 0 : 1;
      return cli::run_study(study, std::cout, std::cerr);
    }
    if (*cmd_mesh) {
      const Rectangle r{gen_domain[0], gen_domain[1], gen_domain[2], gen_domain[3]};
      const auto& kinds = mesh_generator_names();
      if (std::find(kinds.begin(), kinds.end(), gen_kind) == kinds.end()) {
        std::string list;
        for (const auto& k : kinds) list += (list.empty() ? "" : ", ") + k;
        throw InputError("unknown mesh generator '" + gen_kind + "'" + did_you_mean(gen_kind, kinds) +
                             " (expected one of: " + list + ")",
                         "mesh");
      }
      const MemoryEstimate need = estimate_memory(gen_kind, gen_n);
      require_memory(need.mesh_bytes, gen_kind + " n = " + std::to_string(gen_n), "--n");
      Mesh m;
      if (gen_polygon.empty()) {
        m = make_mesh(gen_kind, gen_n, r, gen_seed);
      } else {
        if (gen_polygon.size() % 2 != 0)
          throw InputError("--polygon takes pairs of coordinates x y; got " + std::to_string(gen_polygon.size()) +
                           " numbers", "mesh --polygon");
        PolygonDomain poly;
        for (std::size_t i = 0; i < gen_polygon.size(); i += 2) poly.corners.emplace_back(gen_polygon[i], gen_polygon[i + 1]);
        m = make_mesh(gen_kind, gen_n, poly, gen_seed);
      }
      write_poly2d(gen_output, m, {gen_kind + " n=" + std::to_string(gen_n) + " seed=" + std::to_string(gen_seed)});
      std::cout << "hemivem mesh: wrote " << gen_output << " (" << m.num_vertices() << " vertices, " << m.num_elements()
                << " elements)\n";
      return cli::kSuccess;
    }
    // ---- check and bench ----
    if (*cmd_check && *o_extreme) {
      if (!check.scene.empty() || *o_check_n || !check.set.empty())
        throw InputError("--extreme runs the scenes of its folder; it takes no scene, --n or --set", "check --extreme");
      if (*o_check_tol) extreme.tolerance = check_tol;
      extreme.agree = check.agree;
      extreme.json = check.json;
      extreme.verbosity = check_quiet ? 0 : 1;
      return cli::run_check_extreme(extreme, std::cout, std::cerr);
    }
    if (*cmd_check) {
      if (*o_check_n) check.n = check_n;
      if (*o_check_tol) check.tolerance = check_tol;
      check.verbosity = check_quiet ? 0 : 1;
      return cli::run_check(check, std::cout, std::cerr);
    }
    if (*cmd_bench) {
      if (*o_bench_tol) bench.tolerance = bench_tol;
      bench.verbosity = bench_quiet ? 0 : 1;
      if (bench_limit)
        return cli::run_bench_limit(bench, *o_bench_n ? bench.n : std::vector<int>{128, 256, 512}, std::cout, std::cerr);
      return cli::run_bench(bench, std::cout, std::cerr);
    }
    // ---- end check and bench ----
    if (*cmd_backends) {
      std::cout << engines_text() << "\n";
      return cli::kSuccess;
    }
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
