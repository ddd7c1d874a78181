// The hemivem command.
//
//   hemivem demo [--mesh KIND|FILE.poly2d] [--n N] [--out DIR] ...
//       a clamped block under a traction (Example 4.1 without the contact boundary),
//       solved with a sparse factorization engine (--linear); displacements written as CSV.
//   hemivem backends
//       lists the engines that were built.
//   hemivem mesh KIND --n N --output FILE.poly2d
//       writes a generated mesh.
#include <CLI/CLI.hpp>

#include <hemivem/assembly.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh_generators.hpp>
#include <hemivem/mesh_io.hpp>

#include <chrono>
#include <cstdio>
#include <iomanip>
#include <iostream>
#include <sstream>

#include "common.hpp"

namespace {

using namespace hemivem;
using Clock = std::chrono::steady_clock;

double seconds_since(Clock::time_point t0) { return std::chrono::duration<double>(Clock::now() - t0).count(); }

std::string mesh_help() {
  std::string s;
  for (const auto& n : mesh_generator_names()) s += n + "|";
  return s + "FILE.poly2d";
}

struct DemoOptions {
  std::string mesh = "squares";
  int n = 64;
  std::uint64_t seed = 1;
  double young = 65.0;
  double poisson = 0.29;
  std::string plane = "strain";
  std::string stabilization = "2mu";
  std::string linear = "eigen";
  std::vector<double> traction{0.0, -8.0};
  std::string out = "out/demo";
  bool quiet = false;
};

int run_demo(const DemoOptions& o) {
  const auto t_start = Clock::now();
  auto t0 = Clock::now();
  const Mesh mesh = cli::load_mesh(o.mesh, o.n, Rectangle{}, o.seed);
  const double t_mesh = seconds_since(t0);
  const Rectangle box = mesh.bounding_box();
  const double tol = 1e-8 * std::max(box.width(), box.height());

  ElasticityProblem problem;
  problem.mesh = &mesh;
  problem.materials = MaterialTable(Material{o.young, o.poisson}, plane_model_from_string(o.plane));
  problem.stabilization = stabilization_from_string(o.stabilization);
  const std::vector<Segment> clamped{rectangle_side(box, "left", tol), rectangle_side(box, "right", tol)};
  problem.dirichlet.push_back({select_boundary_edges(mesh, clamped), {}, {true, true}});
  const Vec2 traction(o.traction[0], o.traction[1]);
  problem.tractions.push_back({select_boundary_edges(mesh, std::vector<Segment>{rectangle_side(box, "top", tol)}),
                               [traction](const Vec2&) { return traction; }});
  if (problem.dirichlet[0].edges.empty())
    throw InputError("no boundary edge lies on the left or right side of the mesh: the block is not held", "--mesh");

  t0 = Clock::now();
  const LinearSystem sys = assemble(problem);
  const double t_assembly = seconds_since(t0);

  t0 = Clock::now();
  FactorizationOptions fopt;
  fopt.engine = o.linear;
  auto engine = make_factorization(fopt);
  if (auto r = engine->factorize(sys.A); !r.ok())
    throw NumericalError("factorization with " + engine->name() + " failed (" + to_string(r.status) + "): " + r.message);
  Eigen::MatrixXd X;
  if (auto r = engine->solve(sys.b, &X); !r.ok())
    throw NumericalError("solve with " + engine->name() + " failed (" + to_string(r.status) + "): " + r.message);
  const Eigen::VectorXd uf = X.col(0);
  const double t_solve = seconds_since(t0);
  const double residual = (sys.A * uf - sys.b).norm() / std::max(sys.b.norm(), 1e-300);
  const Eigen::VectorXd u = sys.dofs.expand(uf);

  const std::filesystem::path out(o.out);
  cli::write_atomically(out / "displacement.csv", [&](std::ostream& s) {
    s << "vertex,x,y,ux,uy\n" << std::setprecision(17);
    for (int v = 0; v < mesh.num_vertices(); ++v)
      s << v << ',' << mesh.vertex(v).x() << ',' << mesh.vertex(v).y() << ',' << u(2 * v) << ',' << u(2 * v + 1) << '\n';
  });

  if (!o.quiet) {
    int vmax = 0;
    for (int v = 0; v < mesh.num_vertices(); ++v)
      if (u.segment<2>(2 * v).norm() > u.segment<2>(2 * vmax).norm()) vmax = v;
    std::cout << std::setprecision(6);
    std::cout << "hemivem demo: clamped block (x = x0 and x = x1 clamped), traction (" << traction.x() << ", "
              << traction.y() << ") on the top side\n"
              << "  mesh          " << o.mesh << (std::filesystem::path(o.mesh).extension() == ".poly2d" ? "" : " n = " + std::to_string(o.n))
              << ": " << mesh.num_vertices() << " vertices, " << mesh.num_elements() << " elements, h = " << mesh.h() << "\n"
              << "  material      E = " << o.young << ", nu = " << o.poisson << ", " << to_string(problem.materials.model())
              << ", stabilization " << to_string(problem.stabilization) << "\n"
              << "  unknowns      " << sys.dofs.num_free() << " (of " << sys.dofs.num_dofs() << " dofs)\n"
              << "  linear engine " << engine->name() << ", relative residual " << residual << "\n"
              << "  energy        " << 0.5 * uf.dot(sys.A * uf) - uf.dot(sys.b) << " (potential), compliance "
              << uf.dot(sys.b) << "\n"
              << "  max |u|       " << u.segment<2>(2 * vmax).norm() << " at vertex " << vmax << " ("
              << mesh.vertex(vmax).x() << ", " << mesh.vertex(vmax).y() << ")\n"
              << "  time [s]      mesh " << t_mesh << ", assembly " << t_assembly << ", solve " << t_solve << ", total "
              << seconds_since(t_start) << "\n"
              << "  wrote         " << (out / "displacement.csv").string() << "\n";
  }
  return cli::kSuccess;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"hemivem: virtual element method for contact problems with nonmonotone laws"};
  std::string version = std::string("hemivem ") + HEMIVEM_VERSION + "\nlinear engines:";
  for (const auto& n : available_factorizations()) version += " " + n;
  app.set_version_flag("--version", version);
  app.require_subcommand(1);

  DemoOptions demo;
  auto* cmd_demo = app.add_subcommand("demo", "Clamped block under a traction on the top side (Example 4.1 without contact)");
  cmd_demo->add_option("--mesh", demo.mesh, mesh_help())->capture_default_str();
  cmd_demo->add_option("--n", demo.n, "Elements per side for generated meshes")->capture_default_str()->check(CLI::Range(1, 1 << 14));
  cmd_demo->add_option("--seed", demo.seed, "Seed of random meshes")->capture_default_str();
  cmd_demo->add_option("--E", demo.young, "Young's modulus")->capture_default_str();
  cmd_demo->add_option("--nu", demo.poisson, "Poisson's ratio")->capture_default_str();
  cmd_demo->add_option("--plane", demo.plane, "plane-strain|plane-stress")->capture_default_str();
  cmd_demo->add_option("--stabilization", demo.stabilization, "2mu|trace")->capture_default_str();
  cmd_demo->add_option("--traction", demo.traction, "Traction on the top side: two numbers")->expected(2)->capture_default_str();
  cmd_demo->add_option("--linear", demo.linear, "Sparse factorization engine (see 'hemivem backends')")->capture_default_str();
  cmd_demo->add_option("--out", demo.out, "Output folder")->capture_default_str();
  cmd_demo->add_flag("-q,--quiet", demo.quiet, "Print nothing on success");

  std::string gen_kind, gen_output;
  int gen_n = 8;
  std::uint64_t gen_seed = 1;
  std::vector<double> gen_domain{0.0, 1.0, 0.0, 1.0};
  auto* cmd_mesh = app.add_subcommand("mesh", "Write a generated mesh as .poly2d");
  cmd_mesh->add_option("kind", gen_kind, "squares|triangles|voronoi|nonconvex|distorted")->required();
  cmd_mesh->add_option("--n", gen_n, "Elements (or seeds) per side")->capture_default_str()->check(CLI::Range(1, 1 << 14));
  cmd_mesh->add_option("--seed", gen_seed, "Seed of random meshes")->capture_default_str();
  cmd_mesh->add_option("--domain", gen_domain, "x0 x1 y0 y1")->expected(4)->capture_default_str();
  cmd_mesh->add_option("-o,--output", gen_output, "Output .poly2d file")->required();

  auto* cmd_backends = app.add_subcommand("backends", "List the engines that were built");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? cli::kSuccess : cli::kInputError;
  }

  try {
    if (*cmd_demo) return run_demo(demo);
    if (*cmd_backends) {
      std::cout << "linear:";
      for (const auto& n : available_factorizations()) std::cout << " " << n;
      std::cout << "\n";
      return cli::kSuccess;
    }
    if (*cmd_mesh) {
      const Rectangle r{gen_domain[0], gen_domain[1], gen_domain[2], gen_domain[3]};
      const Mesh m = make_mesh(gen_kind, gen_n, r, gen_seed);
      write_poly2d(gen_output, m, {gen_kind + " n=" + std::to_string(gen_n) + " seed=" + std::to_string(gen_seed)});
      return cli::kSuccess;
    }
  } catch (const InputError& e) {
    std::cerr << "hemivem: error: " << e.what() << "\n";
    return cli::kInputError;
  } catch (const NumericalError& e) {
    std::cerr << "hemivem: backend failure: " << e.what() << "\n";
    return cli::kBackendFailure;
  } catch (const std::exception& e) {
    std::cerr << "hemivem: internal error: " << e.what() << "\n";
    return cli::kInternalError;
  }
  return cli::kSuccess;
}
