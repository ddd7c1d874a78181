#include <hemivem/contact_problem.hpp>
#include <hemivem/piecewise_law.hpp>

namespace hemivem {

ContactProblem example_4_1(const Mesh& mesh) {
  const Rectangle unit{0.0, 1.0, 0.0, 1.0};
  const double tol = 1e-8;
  ContactProblem p;
  p.elasticity.mesh = &mesh;
  p.elasticity.materials = MaterialTable(Material{65.0, 0.29}, PlaneModel::strain);
  p.elasticity.dirichlet.push_back(
      {select_boundary_edges(mesh, std::vector<Segment>{rectangle_side(unit, "left", tol), rectangle_side(unit, "right", tol)}),
       {},
       {true, true}});
  p.elasticity.tractions.push_back({select_boundary_edges(mesh, std::vector<Segment>{rectangle_side(unit, "top", tol)}),
                                    [](const Vec2&) { return Vec2(0.0, -8.0); }});
  p.contact_edges = select_boundary_edges(mesh, std::vector<Segment>{rectangle_side(unit, "bottom", tol)});
  p.gap = [](const Vec2&) { return 0.02; };
  p.law = paper_law();
  p.constraint = ConstraintKind::box;
  return p;
}

}  // namespace hemivem
