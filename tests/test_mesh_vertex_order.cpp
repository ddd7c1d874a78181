// A compact order of a mesh's vertices (hilbert_vertex_order, hemivem/mesh/vertex_order.hpp): a
// permutation, independent of the mesh's own numbering, whose ranges cut about as few cells as a
// generated box's slabs do, where the ranges of a scrambled numbering cut nearly every cell.
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/vertex_order.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <span>
#include <vector>

#include "scrambled_mesh.hpp"

using namespace hemivem;

namespace {

template <class MeshType>
void expect_permutation(const MeshType& mesh, const std::vector<int>& order) {
  std::vector<int> sorted = order;
  std::sort(sorted.begin(), sorted.end());
  std::vector<int> all(static_cast<std::size_t>(mesh.num_vertices()));
  std::iota(all.begin(), all.end(), 0);
  EXPECT_EQ(sorted, all);
}

std::span<const int> vertices_of(const Mesh& mesh, int c) { return mesh.element(c); }
const std::vector<int>& vertices_of(const Mesh3D& mesh, int c) { return mesh.cell_vertices(c); }

/// The cells holding vertices of more than one of `parts` even ranges of `order`'s positions.
template <class MeshType>
int cut_cells(const MeshType& mesh, const std::vector<int>& order, int parts) {
  const auto n = static_cast<long>(order.size());
  std::vector<int> part(order.size());
  for (long p = 0; p < n; ++p)
    part[static_cast<std::size_t>(order[static_cast<std::size_t>(p)])] = static_cast<int>(p * parts / n);
  int cut = 0;
  for (int c = 0; c < mesh.num_cells(); ++c) {
    const auto vertices = vertices_of(mesh, c);
    const auto [lo, hi] = std::minmax_element(vertices.begin(), vertices.end(), [&](int a, int b) {
      return part[static_cast<std::size_t>(a)] < part[static_cast<std::size_t>(b)];
    });
    cut += part[static_cast<std::size_t>(*lo)] != part[static_cast<std::size_t>(*hi)] ? 1 : 0;
  }
  return cut;
}

std::vector<int> own_order(int n) {
  std::vector<int> order(static_cast<std::size_t>(n));
  std::iota(order.begin(), order.end(), 0);
  return order;
}

/// The points of the mesh in `order`.
template <class MeshType>
auto points_in(const MeshType& mesh, const std::vector<int>& order) {
  std::vector<std::decay_t<decltype(mesh.vertex(0))>> points;
  for (const int v : order) points.push_back(mesh.vertex(v));
  return points;
}

/// The Hilbert order of `mesh` numbered at random is a permutation, puts the points in the order
/// it puts them in `mesh` (the numbers do not matter), and its halves and quarters cut about as
/// few cells as `mesh`'s own slabs, where the random numbering's cut nearly every cell.
template <class MeshType>
void expect_compact_order(const MeshType& mesh) {
  const MeshType scrambled = test::scrambled(mesh);
  const std::vector<int> order = hilbert_vertex_order(scrambled);
  expect_permutation(scrambled, order);
  EXPECT_EQ(points_in(scrambled, order), points_in(mesh, hilbert_vertex_order(mesh)));
  for (const int parts : {2, 4}) {
    SCOPED_TRACE(parts);
    const int slabs = cut_cells(mesh, own_order(mesh.num_vertices()), parts);
    // two halves of the curve meet on a plane as two slabs do, but the even split ends inside
    // that plane's layer of vertices along the curve (12^3 cubes: 202 cells against 157; 32^2
    // squares: 42 against 33); four quarters cut fewer than four slabs (361 against 471, 72
    // against 99)
    EXPECT_LE(cut_cells(scrambled, order, parts), parts == 2 ? 3 * slabs / 2 : slabs);
    EXPECT_GT(cut_cells(scrambled, own_order(mesh.num_vertices()), parts), 0.9 * mesh.num_cells());
  }
}

}  // namespace

TEST(VertexOrder, ASolidsHilbertOrderCutsAboutAsFewCellsAsItsSlabs) { expect_compact_order(make_cubes({12, 12, 12})); }

TEST(VertexOrder, APlaneMeshsHilbertOrderCutsAboutAsFewCellsAsItsSlabs) { expect_compact_order(make_squares(32)); }

TEST(VertexOrder, AFlatOrEmptyMeshHasAnOrder) {
  EXPECT_TRUE(hilbert_vertex_order(Mesh()).empty());
  const Mesh one = make_squares(1);
  expect_permutation(one, hilbert_vertex_order(one));
}
