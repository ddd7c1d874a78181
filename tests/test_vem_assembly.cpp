// The global stiffness against the element matrices it is made of: each cell's matrix is computed
// from its vertices less its first, and a cell that is a translate of the one before it reuses
// that matrix; neither may change what is assembled.
#include <hemivem/vem/assembly.hpp>
#include <hemivem/vem/element.hpp>
#include <hemivem/mesh/generators.hpp>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

using namespace hemivem;

namespace {

// sum over the cells, in cell order, of each cell's K_E computed on its own from its vertices
// less its first and its region's material: the sums of assemble_stiffness(), in its order
Eigen::MatrixXd cell_by_cell(const Mesh& mesh, const MaterialTable& materials, Stabilization stabilization) {
  const Eigen::Index n = 2 * static_cast<Eigen::Index>(mesh.num_vertices());
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(n, n);
  Eigen::MatrixXd K;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto vertices = mesh.element(e);
    std::vector<Vec2> z;
    for (int v : vertices) z.push_back(mesh.vertex(v) - mesh.vertex(vertices.front()));
    element_stiffness(z, materials.lame(mesh.region(e)), stabilization, K);
    for (std::size_t j = 0; j < vertices.size(); ++j)
      for (std::size_t i = 0; i < vertices.size(); ++i)
        A.block<2, 2>(2 * vertices[i], 2 * vertices[j]) +=
            K.block<2, 2>(2 * static_cast<Eigen::Index>(i), 2 * static_cast<Eigen::Index>(j));
  }
  return A;
}

// A grid of n x n cells, the x-coordinates graded (consecutive cells of a row differ) when
// `graded`, the cells' regions a checkerboard of 0 and 1.
Mesh checkerboard(int n, bool graded) {
  std::vector<Vec2> vertices;
  for (int j = 0; j <= n; ++j)
    for (int i = 0; i <= n; ++i) {
      const double x = static_cast<double>(i) / n;
      vertices.emplace_back(graded ? x * x : x, static_cast<double>(j) / n);
    }
  std::vector<std::vector<int>> cells;
  std::vector<int> regions;
  for (int j = 0; j < n; ++j)
    for (int i = 0; i < n; ++i) {
      const int a = j * (n + 1) + i;
      cells.push_back({a, a + 1, a + n + 2, a + n + 1});
      regions.push_back((i + j) % 2);
    }
  return Mesh(std::move(vertices), std::move(cells), std::move(regions));
}

}  // namespace

TEST(VemAssembly, EqualsTheSumOfEachCellsOwnMatrixBitForBit) {
  // a row of translated cells of two materials in turn, then a graded grid (no cell a translate
  // of the one before it), then one material: a matrix reused for a cell of another material,
  // or computed from absolute coordinates, would differ
  const MaterialTable two({Material{100.0, 0.3}, Material{1.0, 0.45}}, PlaneModel::strain);
  const MaterialTable one(Material{100.0, 0.3}, PlaneModel::stress);
  for (const bool graded : {false, true})
    for (const MaterialTable* materials : {&two, &one})
      for (const Stabilization stabilization : {Stabilization::two_mu, Stabilization::trace_scaled}) {
        const Mesh mesh = checkerboard(8, graded);
        const Eigen::MatrixXd A(assemble_stiffness(mesh, *materials, stabilization));
        const Eigen::MatrixXd expected = cell_by_cell(mesh, *materials, stabilization);
        EXPECT_EQ((A - expected).cwiseAbs().maxCoeff(), 0.0) << "graded " << graded;
      }
}

TEST(VemAssembly, ATranslatedCellHasTheMatrixOfItsOwnVertices) {
  // dyadic coordinates: each cell of make_squares(16) is an exact translate of its neighbours,
  // and the matrix of a translate, computed from the vertices less the first, is the same bits
  const Mesh mesh = make_squares(16);
  const MaterialTable materials(Material{3.0, 0.25});
  const Eigen::MatrixXd A(assemble_stiffness(mesh, materials));
  EXPECT_EQ((A - cell_by_cell(mesh, materials, Stabilization::two_mu)).cwiseAbs().maxCoeff(), 0.0);
  // the same square far from the origin: the same element matrix to the bit
  Eigen::MatrixXd K0, K1;
  const std::vector<Vec2> near{{0, 0}, {0.0625, 0}, {0.0625, 0.0625}, {0, 0.0625}};
  element_stiffness(near, materials.lame(0), Stabilization::two_mu, K0);
  std::vector<Vec2> far = near;
  for (Vec2& z : far) z += Vec2(1024.0, -512.0);
  const Vec2 origin = far.front();
  for (Vec2& z : far) z -= origin;
  element_stiffness(far, materials.lame(0), Stabilization::two_mu, K1);
  EXPECT_EQ((K0 - K1).cwiseAbs().maxCoeff(), 0.0);
}
