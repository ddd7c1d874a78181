#include <hemivem/vem/assembly.hpp>
#include <hemivem/error.hpp>
#include <hemivem/vem/quadrature.hpp>
#include <hemivem/sparse_factorization.hpp>

#include "element_loop.hpp"

#include <algorithm>
#include <exception>
#include <map>

namespace hemivem {

namespace {

void gather(const Mesh& mesh, int e, std::vector<Vec2>& poly) {
  poly.clear();
  for (int v : mesh.element(e)) poly.push_back(mesh.vertex(v));
}

}  // namespace

namespace {

// element matrices of the mesh, in element order (detail::for_each_element_matrix)
template <class Visit>
void for_each_element_matrix(const Mesh& mesh, const MaterialTable& materials, Stabilization stabilization,
                             Visit&& visit) {
  std::map<int, Lame> lame_by_region;
  for (int region : mesh.regions())
    if (!lame_by_region.count(region)) lame_by_region.emplace(region, materials.lame(region));
  detail::for_each_element_matrix<2>(
      mesh.num_elements(), [&](int e) { return mesh.element(e); },
      [&](int e, Eigen::MatrixXd& K) {
        thread_local std::vector<Vec2> poly;
        gather(mesh, e, poly);
        element_stiffness(poly, lame_by_region.at(mesh.region(e)), stabilization, K);
      },
      visit);
}

SparseMatrix stiffness_pattern(const Mesh& mesh, const std::vector<int>& index, int size) {
  return detail::stiffness_pattern<2>(mesh.num_vertices(), mesh.num_elements(), [&](int e) { return mesh.element(e); },
                                      index, size);
}

}  // namespace

SparseMatrix assemble_stiffness(const Mesh& mesh, const MaterialTable& materials, Stabilization stabilization) {
  const int n = 2 * mesh.num_vertices();
  std::vector<int> index(static_cast<std::size_t>(n));
  for (int d = 0; d < n; ++d) index[static_cast<std::size_t>(d)] = d;
  SparseMatrix K = stiffness_pattern(mesh, index, n);
  detail::PatternScatter scatter(K);
  for_each_element_matrix(mesh, materials, stabilization, [&](const std::vector<int>& dof, const Eigen::Map<const Eigen::MatrixXd>& Ke) {
    scatter.element(dof.data(), dof.size());
    double* values = scatter.values();
    for (std::size_t j = 0; j < dof.size(); ++j) {
      const std::vector<int>& position = scatter.locate(dof[j]);
      for (std::size_t i = 0; i < dof.size(); ++i)
        values[position[i]] += Ke(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
    }
  });
  return K;
}

Eigen::VectorXd assemble_load(const Mesh& mesh, const VectorField& body_force, const std::vector<TractionLoad>& tractions) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(2 * mesh.num_vertices());
  if (body_force) {
    std::vector<Vec2> poly;
    std::vector<LinearField> basis;
    Eigen::VectorXd unit;
    for (int e = 0; e < mesh.num_elements(); ++e) {
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
        f(2 * verts[static_cast<std::size_t>(k / 2)] + k % 2) += F0.dot(phi.value) + M.cwiseProduct(phi.gradient).sum();
      }
    }
  }
  for (const auto& load : tractions) {
    if (!load.traction && !load.pressure) throw InputError("a traction load has neither a traction nor a pressure");
    for (int id : load.edges) {
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
        f.segment<2>(2 * e.v0) += q.weight * len * (1.0 - q.t) * t;
        f.segment<2>(2 * e.v1) += q.weight * len * q.t * t;
      }
    }
  }
  return f;
}

DofMap detail::dof_map_of(std::vector<char> fixed, Eigen::VectorXd prescribed) {
  DofMap map;
  map.prescribed = std::move(prescribed);
  const int ndof = static_cast<int>(fixed.size());
  map.free_index.assign(static_cast<std::size_t>(ndof), -1);
  for (int d = 0; d < ndof; ++d) {
    if (fixed[static_cast<std::size_t>(d)]) continue;
    map.free_index[static_cast<std::size_t>(d)] = static_cast<int>(map.free_dofs.size());
    map.free_dofs.push_back(d);
  }
  return map;
}

Eigen::VectorXd DofMap::expand(const Eigen::VectorXd& free_values) const {
  if (free_values.size() != num_free())
    throw InputError("expected " + std::to_string(num_free()) + " free values, got " + std::to_string(free_values.size()));
  Eigen::VectorXd u = prescribed;
  for (int i = 0; i < num_free(); ++i) u(free_dofs[static_cast<std::size_t>(i)]) = free_values(i);
  return u;
}

Eigen::VectorXd apply_stiffness(const Mesh& mesh, const MaterialTable& materials, Stabilization stabilization,
                                const Eigen::VectorXd& u, const std::vector<char>& rows) {
  if (u.size() != 2 * mesh.num_vertices() || rows.size() != static_cast<std::size_t>(u.size()))
    throw InputError("displacement vector has " + std::to_string(u.size()) + " entries and " +
                     std::to_string(rows.size()) + " rows are selected, expected " +
                     std::to_string(2 * mesh.num_vertices()));
  Eigen::VectorXd Ku = Eigen::VectorXd::Zero(u.size());
  std::vector<Vec2> poly;
  Eigen::MatrixXd K;
  Eigen::VectorXd local;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto verts = mesh.element(e);
    if (std::none_of(verts.begin(), verts.end(), [&](int v) {
          return rows[static_cast<std::size_t>(2 * v)] || rows[static_cast<std::size_t>(2 * v + 1)];
        }))
      continue;
    gather(mesh, e, poly);
    element_stiffness(poly, materials.lame(mesh.region(e)), stabilization, K);
    local.resize(static_cast<Eigen::Index>(2 * verts.size()));
    for (std::size_t k = 0; k < verts.size(); ++k)
      local.segment<2>(static_cast<Eigen::Index>(2 * k)) = u.segment<2>(2 * verts[k]);
    const Eigen::VectorXd Kl = K * local;
    for (std::size_t k = 0; k < verts.size(); ++k)
      for (int c = 0; c < 2; ++c)
        if (rows[static_cast<std::size_t>(2 * verts[k] + c)]) Ku(2 * verts[k] + c) += Kl(static_cast<Eigen::Index>(2 * k + c));
  }
  return Ku;
}

DofMap make_dof_map(const Mesh& mesh, const std::vector<DirichletCondition>& dirichlet) {
  const int ndof = 2 * mesh.num_vertices();
  DofMap map;
  map.prescribed = Eigen::VectorXd::Zero(ndof);
  std::vector<char> fixed(static_cast<std::size_t>(ndof), 0);
  for (const auto& bc : dirichlet) {
    for (int id : bc.edges) {
      if (id < 0 || id >= mesh.num_edges()) throw InputError("Dirichlet edge id " + std::to_string(id) + " out of range");
      const auto& e = mesh.edge(id);
      for (int v : {e.v0, e.v1}) {
        const Vec2 value = bc.value ? bc.value(mesh.vertex(v)) : Vec2::Zero();
        for (int c = 0; c < 2; ++c) {
          if (!bc.fix[static_cast<std::size_t>(c)]) continue;
          fixed[static_cast<std::size_t>(2 * v + c)] = 1;
          map.prescribed(2 * v + c) = value(c);
        }
      }
    }
  }
  return detail::dof_map_of(std::move(fixed), std::move(map.prescribed));
}

LinearSystem assemble(const ElasticityProblem& problem) {
  if (!problem.mesh) throw InputError("the elasticity problem has no mesh");
  const Mesh& mesh = *problem.mesh;
  // The body must be held: Gamma_1 (edges with prescribed displacement) of positive length.
  double held = 0.0;
  std::size_t held_edges = 0;
  for (const auto& bc : problem.dirichlet) {
    held_edges += bc.edges.size();
    for (int id : bc.edges)
      if (id >= 0 && id < mesh.num_edges()) held += mesh.edge_length(id);
  }
  if (held_edges == 0)
    throw InputError("the body is not held: no boundary edge has a prescribed displacement (Gamma_1 is empty)");
  if (!(held > 0.0))
    throw InputError("the body is not held: the boundary with prescribed displacement (Gamma_1) has zero length");
  LinearSystem sys;
  sys.dofs = make_dof_map(mesh, problem.dirichlet);
  const Eigen::VectorXd f = assemble_load(mesh, problem.body_force, problem.tractions);
  // A = K restricted to the free dofs and b = (f - K u_prescribed) on them, added element by
  // element into A's pattern (from the mesh) in the numbering of the free dofs: no global K,
  // no selection products, no triplets
  const std::vector<int>& free_index = sys.dofs.free_index;
  sys.b.resize(sys.dofs.num_free());
  for (int i = 0; i < sys.dofs.num_free(); ++i) sys.b(i) = f(sys.dofs.free_dofs[static_cast<std::size_t>(i)]);
  {
    SparseMatrix A = stiffness_pattern(mesh, free_index, sys.dofs.num_free());
    sys.A.swap(A);  // no copy (SparseMatrix has no move assignment)
  }
  for_each_element_matrix(mesh, problem.materials, problem.stabilization, detail::FreeSystemAssembler{sys});
  return sys;
}

Eigen::VectorXd assemble_rhs(const ElasticityProblem& problem, const DofMap& dofs) {
  if (!problem.mesh) throw InputError("the elasticity problem has no mesh");
  const Mesh& mesh = *problem.mesh;
  if (dofs.num_dofs() != 2 * mesh.num_vertices())
    throw InputError("a dof map of " + std::to_string(dofs.num_dofs()) + " dofs for a mesh of " +
                     std::to_string(2 * mesh.num_vertices()));
  const Eigen::VectorXd f = assemble_load(mesh, problem.body_force, problem.tractions);
  Eigen::VectorXd b(dofs.num_free());
  for (int i = 0; i < dofs.num_free(); ++i) b(i) = f(dofs.free_dofs[static_cast<std::size_t>(i)]);
  std::vector<Vec2> poly;
  Eigen::MatrixXd K;
  Eigen::VectorXd local;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto verts = mesh.element(e);
    const bool lifted = std::any_of(verts.begin(), verts.end(), [&](int v) {
      return dofs.prescribed(2 * v) != 0.0 || dofs.prescribed(2 * v + 1) != 0.0;
    });
    if (!lifted) continue;
    gather(mesh, e, poly);
    element_stiffness(poly, problem.materials.lame(mesh.region(e)), problem.stabilization, K);
    local.resize(static_cast<Eigen::Index>(2 * verts.size()));
    for (std::size_t k = 0; k < verts.size(); ++k)
      for (int c = 0; c < 2; ++c) {
        const int d = 2 * verts[k] + c;
        local(static_cast<Eigen::Index>(2 * k + c)) = dofs.free_index[static_cast<std::size_t>(d)] < 0 ? dofs.prescribed(d) : 0.0;
      }
    const Eigen::VectorXd Kl = K * local;
    for (std::size_t k = 0; k < verts.size(); ++k)
      for (int c = 0; c < 2; ++c)
        if (const int fi = dofs.free_index[static_cast<std::size_t>(2 * verts[k] + c)]; fi >= 0)
          b(fi) -= Kl(static_cast<Eigen::Index>(2 * k + c));
  }
  return b;
}

std::vector<LinearField> project_solution(const Mesh& mesh, const Eigen::VectorXd& u) {
  if (u.size() != 2 * mesh.num_vertices())
    throw InputError("displacement vector has " + std::to_string(u.size()) + " entries, expected " +
                     std::to_string(2 * mesh.num_vertices()));
  std::vector<LinearField> out(static_cast<std::size_t>(mesh.num_elements()));
  std::vector<Vec2> poly;
  Eigen::VectorXd local;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    gather(mesh, e, poly);
    const auto verts = mesh.element(e);
    local.resize(2 * static_cast<Eigen::Index>(verts.size()));
    for (std::size_t i = 0; i < verts.size(); ++i) local.segment<2>(2 * static_cast<Eigen::Index>(i)) = u.segment<2>(2 * verts[i]);
    out[static_cast<std::size_t>(e)] = project_p1(poly, local);
  }
  return out;
}

}  // namespace hemivem
