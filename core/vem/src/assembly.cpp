#include <hemivem/vem/assembly.hpp>
#include <hemivem/error.hpp>
#include <hemivem/vem/quadrature.hpp>
#include <hemivem/sparse_factorization.hpp>

#include "cell_values.hpp"
#include "element_loop.hpp"
#include "load_kernels.hpp"

#include <algorithm>
#include <exception>
#include <map>
#include <utility>

namespace hemivem {

namespace {

void gather(const Mesh& mesh, int e, std::vector<Vec2>& poly) {
  poly.clear();
  for (int v : mesh.element(e)) poly.push_back(mesh.vertex(v));
}

}  // namespace

void detail::cell_body_load(const Mesh& mesh, int e, const VectorField& body_force, const LoadTerms& add) {
  thread_local std::vector<Vec2> poly;
  thread_local std::vector<LinearField> basis;
  thread_local Eigen::VectorXd unit;
  gather(mesh, e, poly);
  // (3.13): the load of local basis function k is int f0 . Pi^nabla_1 phi_k, with
  // Pi^nabla_1 phi_k (x) = value + gradient (x - center).
  const auto n2 = static_cast<Eigen::Index>(2 * poly.size());
  basis.clear();
  unit.setZero(n2);
  for (Eigen::Index k = 0; k < n2; ++k) {
    unit(k) = 1.0;
    basis.push_back(project_gradient(poly, unit));
    unit(k) = 0.0;
  }
  const Vec2 center = basis.front().center;
  // F0 = int f0, M(c, d) = int f0_c (x - center)_d
  const Vec2 F0 = quadrature::integrate_polygon(poly, [&](const Vec2& x) { return body_force(x); });
  const Eigen::Matrix2d M = quadrature::integrate_polygon(
      poly, [&](const Vec2& x) -> Eigen::Matrix2d { return body_force(x) * (x - center).transpose(); });
  const auto verts = mesh.element(e);
  for (Eigen::Index k = 0; k < n2; ++k) {
    const LinearField& phi = basis[static_cast<std::size_t>(k)];
    add(2 * verts[static_cast<std::size_t>(k / 2)] + static_cast<int>(k % 2),
        F0.dot(phi.value) + M.cwiseProduct(phi.gradient).sum());
  }
}

void detail::facet_traction_load(const Mesh& mesh, const TractionLoad& load, int id, const LoadTerms& add) {
  if (id < 0 || id >= mesh.num_edges()) throw InputError("traction edge id " + std::to_string(id) + " out of range");
  const auto& e = mesh.edge(id);
  if (load.pressure && !e.on_boundary())
    throw InputError("pressure edge " + std::to_string(id) + " is not on the boundary (it has no outward normal)");
  const Vec2 a = mesh.vertex(e.v0), b = mesh.vertex(e.v1);
  const double len = (b - a).norm();
  // outward unit normal: a boundary edge runs counter-clockwise in its element
  const Vec2 normal = len > 0.0 ? Vec2((b - a).y() / len, -(b - a).x() / len) : Vec2::Zero();
  for (const auto& q : quadrature::segment_rule()) {
    const Vec2 x = (1.0 - q.t) * a + q.t * b;
    Vec2 t = load.traction ? load.traction(x) : Vec2::Zero();
    if (load.pressure) t -= load.pressure(x) * normal;
    const Vec2 t0 = q.weight * len * (1.0 - q.t) * t, t1 = q.weight * len * q.t * t;
    for (int c = 0; c < 2; ++c) add(2 * e.v0 + c, t0(c));
    for (int c = 0; c < 2; ++c) add(2 * e.v1 + c, t1(c));
  }
}

DofMap detail::dof_map_of(int ndof, std::vector<std::pair<int, double>> prescribed,
                          const std::vector<int>* vertex_order, int dim) {
  // the last value given to a dof is its value
  std::stable_sort(prescribed.begin(), prescribed.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  std::vector<int> dofs;
  std::vector<double> values;
  for (std::size_t k = 0; k < prescribed.size(); ++k) {
    if (k + 1 < prescribed.size() && prescribed[k + 1].first == prescribed[k].first) continue;
    dofs.push_back(prescribed[k].first);
    values.push_back(prescribed[k].second);
  }
  std::vector<std::pair<int, double>>().swap(prescribed);
  Eigen::VectorXd value = Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size()));
  if (!vertex_order) return DofMap(ndof, dim, std::move(dofs), std::move(value));
  const int nv = ndof / dim;
  std::vector<char> seen(static_cast<std::size_t>(nv), 0);
  const auto once = [&](int v) {
    return v >= 0 && v < nv && !std::exchange(seen[static_cast<std::size_t>(v)], char{1});
  };
  const bool permutation = static_cast<int>(vertex_order->size()) == nv &&
                           std::all_of(vertex_order->begin(), vertex_order->end(), once);
  if (!permutation)
    throw InputError("a vertex order of " + std::to_string(vertex_order->size()) +
                     " entries that is not a permutation of the mesh's " + std::to_string(nv) + " vertices");
  return DofMap(ndof, dim, std::move(dofs), std::move(value), *vertex_order);
}

std::vector<LinearField> project_solution(const Mesh& mesh, const Eigen::VectorXd& u) {
  std::vector<LinearField> out(static_cast<std::size_t>(mesh.num_elements()));
  detail::for_each_cell_values(mesh, u, [&](int e, const std::vector<Vec2>& polygon, const Eigen::VectorXd& local) {
    out[static_cast<std::size_t>(e)] = project_p1(polygon, local);
  });
  return out;
}

}  // namespace hemivem
