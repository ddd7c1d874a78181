#include <hemivem/contact/condensation.hpp>
#include <hemivem/error.hpp>

#include <algorithm>
#include <cmath>
#include <set>
#include <sstream>

namespace hemivem {

namespace {

template <int dim>
std::string point_text(const PointOf<dim>& x) {
  std::ostringstream out;
  out << "(";
  for (int c = 0; c < dim; ++c) out << (c ? ", " : "") << x(c);
  out << ")";
  return out.str();
}

/// The largest extent of the mesh's vertices along an axis.
template <int dim>
double mesh_size(const MeshOf<dim>& mesh) {
  PointOf<dim> lo = mesh.vertex(0), hi = mesh.vertex(0);
  for (int v = 1; v < mesh.num_vertices(); ++v) {
    lo = lo.cwiseMin(mesh.vertex(v));
    hi = hi.cwiseMax(mesh.vertex(v));
  }
  return (hi - lo).maxCoeff();
}

}  // namespace

template <int dim>
void pair_with_other_body(const MeshOf<dim>& mesh, const std::vector<BasicContactPart<dim>>& parts,
                          ContactBoundary& boundary) {
  const bool any = std::any_of(parts.begin(), parts.end(), [](const auto& p) { return !p.against.empty(); });
  if (!any || boundary.size() == 0) return;
  const double tolerance = 1e-9 * mesh_size<dim>(mesh);
  std::set<int> nodes(boundary.nodes.begin(), boundary.nodes.end()), taken;
  boundary.partner.assign(boundary.nodes.size(), -1);
  // per part meeting another body: the vertices of its `against` facets, by their x
  std::vector<std::vector<std::pair<double, int>>> by_x(parts.size());
  for (std::size_t k = 0; k < parts.size(); ++k) {
    std::set<int> vertices;
    for (int f : parts[k].against) {
      if (f < 0 || f >= mesh.num_facets())
        throw InputError("contact part '" + parts[k].name + "': facet " + std::to_string(f) +
                         " of the other body is out of range");
      for (int q : mesh.facet_vertices(f)) vertices.insert(q);
    }
    for (int q : vertices) by_x[k].emplace_back(mesh.vertex(q)(0), q);
    std::sort(by_x[k].begin(), by_x[k].end());
  }
  for (int i = 0; i < boundary.size(); ++i) {
    const auto k = static_cast<std::size_t>(boundary.part_of(i));
    const auto& part = parts[k];
    if (part.against.empty()) continue;
    const int p = boundary.nodes[static_cast<std::size_t>(i)];
    const PointOf<dim>& x = mesh.vertex(p);
    int best = -1;
    double distance = tolerance;
    const auto& candidates = by_x[k];
    for (auto it = std::lower_bound(candidates.begin(), candidates.end(), std::make_pair(x(0) - tolerance, -1));
         it != candidates.end() && it->first <= x(0) + tolerance; ++it)
      if (const double d = (mesh.vertex(it->second) - x).norm(); d <= distance && it->second != p) {
        best = it->second;
        distance = d;
      }
    if (best < 0)
      throw InputError("contact part '" + part.name + "': its node " + std::to_string(p) + " at " + point_text<dim>(x) +
                       " has no vertex of the other body's surface at its point; the two bodies' meshes must match along "
                       "their contact (a scene with [[body]] tables matches them)");
    if (nodes.count(best))
      throw InputError("contact part '" + part.name + "': the vertex " + std::to_string(best) + " at " +
                       point_text<dim>(x) + " across from node " + std::to_string(p) +
                       " is itself a contact node; a surface meets another body from one side only");
    if (!taken.insert(best).second)
      throw InputError("contact part '" + part.name + "': two nodes meet the vertex " + std::to_string(best) + " at " +
                       point_text<dim>(x));
    boundary.partner[static_cast<std::size_t>(i)] = best;
  }
}

template void pair_with_other_body<2>(const Mesh&, const std::vector<BasicContactPart<2>>&, ContactBoundary&);
template void pair_with_other_body<3>(const Mesh3D&, const std::vector<BasicContactPart<3>>&, ContactBoundary&);

}  // namespace hemivem
