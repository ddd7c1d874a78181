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

}  // namespace hemivem::test

#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh_generators.hpp>

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
                                                    ex->problem.constraint);
  return ex;
}

}  // namespace hemivem::test
