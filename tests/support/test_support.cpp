#include "test_support.hpp"

#include <algorithm>

namespace hemivem::test {

std::filesystem::path shared_dir() {
  std::filesystem::path p = HEMIVEM_SHARED_DIR;
  std::error_code ec;
  if (std::filesystem::is_directory(p / "meshes", ec)) return std::filesystem::canonical(p);
  return {};
}

std::vector<std::filesystem::path> shared_meshes() {
  std::vector<std::filesystem::path> out;
  const auto dir = shared_dir();
  if (dir.empty()) return out;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "meshes"))
    if (entry.path().extension() == ".poly2d") out.push_back(entry.path());
  std::sort(out.begin(), out.end());
  return out;
}

std::filesystem::path data_dir() { return HEMIVEM_TEST_DATA_DIR; }

std::filesystem::path scenes_dir() { return data_dir().parent_path().parent_path() / "scenes"; }

}  // namespace hemivem::test

#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>

namespace hemivem::test {

Eigen::VectorXd solve(const LinearSystem& system) {
  Eigen::SimplicialLLT<SparseMatrix> llt(system.A);
  EXPECT_EQ(llt.info(), Eigen::Success) << "sparse Cholesky failed";
  const Eigen::VectorXd uf = llt.solve(system.b);
  return system.dofs.expand(uf);
}

DirichletCondition dirichlet_everywhere(const Mesh& mesh, VectorField u) {
  return {mesh.boundary_edges(), std::move(u), {true, true}};
}

bool identical(const Mesh& a, const Mesh& b) {
  if (a.num_vertices() != b.num_vertices() || a.elements() != b.elements()) return false;
  for (int v = 0; v < a.num_vertices(); ++v)
    if (!(a.vertex(v).x() == b.vertex(v).x() && a.vertex(v).y() == b.vertex(v).y())) return false;
  return true;
}

std::string input_error_of(const std::function<void()>& f) {
  try {
    f();
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace hemivem::test

#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/scene/example.hpp>

namespace hemivem::test {

std::unique_ptr<Example> example(const std::string& kind, int n, const std::function<void(ContactProblem&)>& change) {
  auto ex = std::make_unique<Example>();
  ex->mesh = make_mesh(kind, n, Rectangle{}, 5);
  ex->problem = example_4_1(ex->mesh);
  if (change) change(ex->problem);
  ex->system = assemble(ex->problem.elasticity);
  ex->boundary = make_contact_boundary(ex->mesh, ex->problem.contact_edges, ex->system.dofs, ex->problem.gap);
  FactorizationOptions fo;
  fo.engine = "eigen";
  ex->condensation = std::make_unique<Condensation>(ex->system, ex->boundary, make_factorization(fo), ex->problem.law,
                                                    ex->problem.constraint, ex->problem.friction);
  return ex;
}

}  // namespace hemivem::test

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace hemivem::test {

std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::filesystem::path scratch(const std::string& name) {
  const auto p = std::filesystem::temp_directory_path() / ("hemivem-test-" + std::to_string(::getpid()) + "-" + name);
  std::filesystem::remove_all(p);
  return p;
}

CommandRun run_command(const std::string& command) {
  const auto err = std::filesystem::temp_directory_path() / ("hemivem-test-stderr-" + std::to_string(::getpid()) + ".txt");
  CommandRun r;
  FILE* p = popen((command + " 2>" + err.string()).c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (std::size_t n = std::fread(buf.data(), 1, buf.size(), p)) r.out.append(buf.data(), n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = slurp(err);
  std::filesystem::remove(err);
  return r;
}

CommandRun run_hemivem(const std::string& args) { return run_command(std::string(HEMIVEM_BINARY) + " " + args); }

}  // namespace hemivem::test
