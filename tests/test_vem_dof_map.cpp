// DofMap (hemivem/vem/assembly.hpp): the free numbering kept as the prescribed dofs alone, against
// the numbering written out dof by dof.
#include <hemivem/error.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/vem/assembly.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <numeric>
#include <random>
#include <string>
#include <vector>

using namespace hemivem;

namespace {

/// The numbering written out: each dof's free index along the slots (dof order, or vertex by
/// vertex along `order`), -1 where prescribed.
std::vector<int> written_out(int num_dofs, int dim, const std::vector<char>& fixed, const std::vector<int>& order) {
  std::vector<int> index(static_cast<std::size_t>(num_dofs), -1);
  int f = 0;
  for (int slot = 0; slot < num_dofs; ++slot) {
    const int d = order.empty() ? slot : dim * order[static_cast<std::size_t>(slot / dim)] + slot % dim;
    if (!fixed[static_cast<std::size_t>(d)]) index[static_cast<std::size_t>(d)] = f++;
  }
  return index;
}

void expect_map_is(const DofMap& map, const std::vector<char>& fixed, const Eigen::VectorXd& values,
                   const std::vector<int>& index) {
  const int n = static_cast<int>(fixed.size());
  ASSERT_EQ(map.num_dofs(), n);
  ASSERT_EQ(map.num_free(), static_cast<int>(std::count(fixed.begin(), fixed.end(), 0)));
  EXPECT_EQ(map.free_index_table(), index);
  for (int d = 0; d < n; ++d) {
    EXPECT_EQ(map.free_index(d), index[static_cast<std::size_t>(d)]) << "dof " << d;
    EXPECT_EQ(map.is_prescribed(d), fixed[static_cast<std::size_t>(d)] != 0) << "dof " << d;
    EXPECT_EQ(map.prescribed_value(d), fixed[static_cast<std::size_t>(d)] ? values(d) : 0.0) << "dof " << d;
    if (index[static_cast<std::size_t>(d)] >= 0) EXPECT_EQ(map.free_dof(index[static_cast<std::size_t>(d)]), d);
  }
  Eigen::VectorXd prescribed = Eigen::VectorXd::Zero(n);
  for (int d = 0; d < n; ++d)
    if (fixed[static_cast<std::size_t>(d)]) prescribed(d) = values(d);
  EXPECT_EQ(map.prescribed(), prescribed);
  EXPECT_EQ(map.prescribed_part(values), map.prescribed_values());
  Eigen::VectorXd free_values(map.num_free());
  for (int f = 0; f < map.num_free(); ++f) free_values(f) = 1000.0 + f;
  Eigen::VectorXd u = prescribed;
  for (int d = 0; d < n; ++d)
    if (const int f = index[static_cast<std::size_t>(d)]; f >= 0) u(d) = free_values(f);
  EXPECT_EQ(map.expand(free_values), u);
  EXPECT_EQ(map.free_part(u), free_values);
}

}  // namespace

TEST(DofMap, TheFreeNumberingOfThePrescribedDofsAloneIsTheNumberingWrittenOut) {
  std::mt19937 random(7);
  for (const int dim : {2, 3})
    for (const int vertices : {1, 2, 5, 40})
      for (const double share : {0.0, 0.1, 0.5, 0.9, 1.0})
        for (const bool ordered : {false, true}) {
          SCOPED_TRACE(std::to_string(dim) + "D, " + std::to_string(vertices) + " vertices, " + std::to_string(share) +
                       (ordered ? ", ordered" : ""));
          const int n = dim * vertices;
          std::vector<char> fixed(static_cast<std::size_t>(n));
          std::bernoulli_distribution held(share);
          for (char& f : fixed) f = held(random) ? 1 : 0;
          Eigen::VectorXd values = Eigen::VectorXd::LinSpaced(n, 0.5, 0.5 + n);
          std::vector<int> dofs;
          Eigen::VectorXd given(n);
          for (int d = 0; d < n; ++d)
            if (fixed[static_cast<std::size_t>(d)]) {
              given(static_cast<Eigen::Index>(dofs.size())) = values(d);
              dofs.push_back(d);
            }
          given.conservativeResize(static_cast<Eigen::Index>(dofs.size()));
          std::vector<int> order;
          if (ordered) {
            order.resize(static_cast<std::size_t>(vertices));
            std::iota(order.begin(), order.end(), 0);
            std::shuffle(order.begin(), order.end(), random);
          }
          const DofMap map(n, dim, dofs, given, order);
          expect_map_is(map, fixed, values, written_out(n, dim, fixed, order));
          // new values, in the prescribed dofs' order
          DofMap moved = map;
          moved.set_prescribed_values(2.0 * given);
          for (int d : dofs) EXPECT_EQ(moved.prescribed_value(d), 2.0 * values(d));
          EXPECT_THROW(moved.set_prescribed_values(Eigen::VectorXd::Zero(given.size() + 1)), InternalError);
        }
}

TEST(DofMap, MakeDofMapHoldsTheSupportsAndTheLastValueGivenToADof) {
  const Mesh mesh = make_squares(GridSize(3, 2), Rectangle{0.0, 3.0, 0.0, 2.0});
  std::vector<DirichletCondition> dirichlet(2);
  dirichlet[0].vertices = {0, 4};
  dirichlet[0].value = [](const Vec2&) { return Vec2(1.0, 2.0); };
  dirichlet[1].vertices = {4};
  dirichlet[1].fix = {false, true};
  dirichlet[1].value = [](const Vec2&) { return Vec2(5.0, 6.0); };
  const DofMap map = make_dof_map(mesh, dirichlet);
  EXPECT_EQ(map.prescribed_dofs(), (std::vector<int>{0, 1, 8, 9}));
  EXPECT_EQ(map.prescribed_values(), Eigen::Vector4d(1.0, 2.0, 1.0, 6.0));
  EXPECT_EQ(map.num_free(), 2 * mesh.num_vertices() - 4);
  EXPECT_EQ(map.free_index(2), 0);
  EXPECT_EQ(map.free_index(10), 6);
  EXPECT_EQ(map.free_dof(6), 10);
  // along an order: the reversed vertices number the free dofs from the last vertex
  std::vector<int> order(static_cast<std::size_t>(mesh.num_vertices()));
  std::iota(order.rbegin(), order.rend(), 0);
  const DofMap reversed = make_dof_map(mesh, dirichlet, order);
  EXPECT_EQ(reversed.free_index(2 * mesh.num_vertices() - 2), 0);
  EXPECT_EQ(reversed.free_index(2 * mesh.num_vertices() - 1), 1);
  EXPECT_EQ(reversed.free_dof(reversed.num_free() - 1), 3);
  EXPECT_EQ(reversed.prescribed_values(), map.prescribed_values());
  order[0] = order[1];
  EXPECT_THROW(make_dof_map(mesh, dirichlet, order), InputError);
  // given directly, such an order is refused before it is read
  EXPECT_THROW(DofMap(2 * mesh.num_vertices(), 2, {}, Eigen::VectorXd(), order), InternalError);
  order[0] = mesh.num_vertices();
  EXPECT_THROW(DofMap(2 * mesh.num_vertices(), 2, {}, Eigen::VectorXd(), order), InternalError);
}
