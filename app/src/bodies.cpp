// result.json's "bodies" of a scene of several bodies (docs/two-bodies.md): each body's part of
// the mesh and the balance of the forces on it.
#include "bodies.hpp"

#include <hemivem/vem/assembly.hpp>
#include <hemivem/vem/assembly3d.hpp>

#include <hemivem/app/format.hpp>
#include <hemivem/error.hpp>

namespace hemivem::app::detail {

namespace {

int body_of(const std::vector<BodyRange>& bodies, int vertex) {
  for (std::size_t b = 0; b < bodies.size(); ++b)
    if (bodies[b].has_vertex(vertex)) return static_cast<int>(b);
  return -1;
}

}  // namespace

template <int dim>
std::vector<double> body_loads(const BasicContactProblem<dim>& problem, const std::vector<BodyRange>& bodies,
                               const std::vector<char>* vertices) {
  std::vector<double> out(dim * bodies.size(), 0.0);
  if (bodies.empty()) return out;
  const Eigen::VectorXd f =
      assemble_load(*problem.elasticity.mesh, problem.elasticity.body_force, problem.elasticity.tractions);
  for (std::size_t b = 0; b < bodies.size(); ++b)
    for (int v = bodies[b].first_vertex; v < bodies[b].first_vertex + bodies[b].vertices; ++v)
      if (!vertices || (*vertices)[static_cast<std::size_t>(v)])
        for (int i = 0; i < dim; ++i) out[dim * b + static_cast<std::size_t>(i)] += f(dim * v + i);
  return out;
}

template <int dim>
nlohmann::json bodies_json(const std::vector<double>& applied, const BasicContactSolution<dim>& s,
                           const std::vector<BodyRange>& bodies) {
  using Point = Eigen::Matrix<double, dim, 1>;
  if (bodies.empty()) return nullptr;
  if (applied.size() != dim * bodies.size())
    throw InternalError(std::to_string(applied.size()) + " load values for " + std::to_string(bodies.size()) + " bodies");
  std::vector<BasicForceBalance<Point>> balance(bodies.size());
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    balance[b].applied = Eigen::Map<const Point>(applied.data() + dim * b);
    for (const auto& r : s.forces.reactions)
      if (r.name.rfind(bodies[b].name + ".", 0) == 0) balance[b].reactions.push_back(r);
  }
  for (const auto& n : s.contact) {
    const Point on = n.force_on_body();
    if (const int b = body_of(bodies, n.vertex); b >= 0) balance[static_cast<std::size_t>(b)].contact += on;
    if (const int b = n.partner >= 0 ? body_of(bodies, n.partner) : -1; b >= 0)
      balance[static_cast<std::size_t>(b)].contact -= on;
  }
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t b = 0; b < bodies.size(); ++b) {
    nlohmann::json reactions = nlohmann::json::object();
    for (const auto& r : balance[b].reactions) reactions[r.name] = vector_json(r.force);
    out.push_back({{"name", bodies[b].name},
                   {"first_vertex", bodies[b].first_vertex},
                   {"vertices", bodies[b].vertices},
                   {"first_cell", bodies[b].first_cell},
                   {"cells", bodies[b].cells},
                   {"forces",
                    {{"applied", vector_json(balance[b].applied)},
                     {"reactions", std::move(reactions)},
                     {"contact", vector_json(balance[b].contact)},
                     {"balance_residual", number(balance[b].residual())}}}});
  }
  return out;
}

template std::vector<double> body_loads(const BasicContactProblem<2>&, const std::vector<BodyRange>&, const std::vector<char>*);
template std::vector<double> body_loads(const BasicContactProblem<3>&, const std::vector<BodyRange>&, const std::vector<char>*);
template nlohmann::json bodies_json(const std::vector<double>&, const BasicContactSolution<2>&, const std::vector<BodyRange>&);
template nlohmann::json bodies_json(const std::vector<double>&, const BasicContactSolution<3>&, const std::vector<BodyRange>&);

}  // namespace hemivem::app::detail
