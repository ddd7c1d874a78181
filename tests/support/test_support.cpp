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
