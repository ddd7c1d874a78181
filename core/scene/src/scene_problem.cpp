// A scene's contact problem on a mesh, written once for plane (dim = 2) and solid (dim = 3)
// bodies: the materials by region, the boundary parts the selectors pick, the prescribed
// displacements, the loads and the contact parts (make_contact_problem). Per dimension only the
// facets differ: boundary edges picked by segments, or boundary faces by the box's sides.
#include <hemivem/engine_names.hpp>
#include <hemivem/krylov_solver.hpp>
#include <hemivem/row_distribution.hpp>
#include <hemivem/scene/scene.hpp>

#include <algorithm>
#include <map>
#include <iomanip>
#include <limits>
#include <set>
#include <span>
#include <sstream>

#include <hemivem/contact/supports.hpp>
#include <hemivem/mesh/boundary.hpp>

#include "scene_fields.hpp"
#include "scene_problem.hpp"
#include "scene_reader.hpp"

namespace hemivem {

using detail::fmt;

namespace {

/// The boundary facets of the mesh a selector of the scene picks (sorted, distinct); an error
/// naming the selector's key when it picks none (unless told it may: a process's piece,
/// SupportsAcross) or names a group the mesh lacks. Plane bodies:
/// boundary edges on the sides of the mesh's bounding rectangle, on segments and in edge
/// groups; solids: boundary faces on the sides of its bounding box and in face groups.
template <int dim>
class FacetSelection {
 public:
  /// `cut`: the boundary facets of a process's piece of the mesh that lie inside the whole mesh
  /// (increasing), which no selector picks.
  FacetSelection(const Scene& scene, const MeshOf<dim>& mesh, std::span<const int> cut = {})
      : scene_(scene), mesh_(mesh), cut_(cut), box_(mesh.bounding_box()) {}

  std::vector<int> operator()(const BoundarySelector& b, const std::string& key, bool may_pick_none = false) const {
    if (!b.has_facets() && !b.points.empty()) return {};  // a support at single vertices only
    std::vector<int> facets = by_place(b);
    for (const auto& g : b.groups) {
      try {
        const auto f = by_group(g);
        facets.insert(facets.end(), f.begin(), f.end());
      } catch (const InputError& e) {
        throw InputError(key + ".group: " + e.detail(), scene_.where(key + ".group"));
      }
    }
    std::sort(facets.begin(), facets.end());
    facets.erase(std::unique(facets.begin(), facets.end()), facets.end());
    std::erase_if(facets, [&](int f) { return std::binary_search(cut_.begin(), cut_.end(), f); });
    if (facets.empty() && !may_pick_none) throw picks_none(scene_, key);
    return facets;
  }

  /// The error of a selector, the scene's `key`, that picks no facet of the mesh.
  static InputError picks_none(const Scene& scene, const std::string& key) {
    return InputError(key + ": selects no boundary " + (dim == 2 ? "edge" : "face") + " of the mesh", scene.where(key));
  }

  /// The vertex at each of the selector's points: the nearest one, within `tolerance` times the
  /// mesh's size (the longest side of its bounding box); an error naming `key`.point otherwise.
  std::vector<int> vertices(const BoundarySelector& b, const std::string& key) const {
    double size = 0.0;
    for (int c = 0; c < dim; ++c) size = std::max(size, extent(c));
    std::vector<int> found;
    for (const auto& q : b.points) {
      const PointOf<dim> x = Eigen::Map<const Eigen::Vector3d>(q.data()).head<dim>();
      const auto [best, distance] = nearest_point<dim>(mesh_.vertices(), x);
      if (best < 0 || !(distance <= b.tolerance * size))
        throw InputError(key + ".point: no vertex of the mesh at " + detail::point_text<dim>(x) +
                             (best < 0 ? std::string()
                                       : " (the nearest, vertex " + std::to_string(best) + " at " +
                                             detail::point_text<dim>(mesh_.vertex(best)) + ", is " + fmt(distance) +
                                             " away; the tolerance is " + fmt(b.tolerance) + " x the mesh size " +
                                             fmt(size) + ")") +
                             "; a point support holds a vertex of the mesh",
                         scene_.where(key + ".point"));
      found.push_back(best);
    }
    return found;
  }

 private:
  double extent(int axis) const {
    if constexpr (dim == 2)
      return axis == 0 ? box_.width() : box_.height();
    else
      return box_.size(axis);
  }

  std::vector<int> by_place(const BoundarySelector& b) const {
    if constexpr (dim == 2) {
      std::vector<Segment> segs;
      for (const auto& side : b.sides) segs.push_back(rectangle_side(box_, side, b.tolerance));
      const double size = std::max(box_.width(), box_.height());
      for (const auto& s : b.segments) segs.push_back(Segment{Vec2(s[0], s[1]), Vec2(s[2], s[3]), b.tolerance * size});
      return segs.empty() ? std::vector<int>{} : select_boundary_edges(mesh_, segs);
    } else {
      std::vector<int> faces;
      for (const auto& side : b.sides) {
        const auto f = select_box_side(mesh_, box_, side, b.tolerance);
        faces.insert(faces.end(), f.begin(), f.end());
      }
      return faces;
    }
  }

  std::vector<int> by_group(const std::string& group) const {
    if constexpr (dim == 2)
      return select_boundary_edges(mesh_, group);
    else
      return select_boundary_faces(mesh_, group);
  }

  const Scene& scene_;
  const MeshOf<dim>& mesh_;
  std::span<const int> cut_;
  const decltype(std::declval<const MeshOf<dim>&>().bounding_box()) box_;
};

/// The vertices of boundary facet f.
void insert_facet_vertices(std::set<int>& into, const Mesh& mesh, int f) { into.insert({mesh.edge(f).v0, mesh.edge(f).v1}); }
void insert_facet_vertices(std::set<int>& into, const Mesh3D& mesh, int f) {
  into.insert(mesh.face(f).vertices.begin(), mesh.face(f).vertices.end());
}

/// Where boundary facet f is, for messages.
std::string facet_text(const Mesh& mesh, int f) {
  const Vec2 a = mesh.vertex(mesh.edge(f).v0), b = mesh.vertex(mesh.edge(f).v1);
  return "the boundary edge from (" + fmt(a.x()) + ", " + fmt(a.y()) + ") to (" + fmt(b.x()) + ", " + fmt(b.y()) + ")";
}
std::string facet_text(const Mesh3D& mesh, int f) {
  return "the boundary face at " + detail::point_text<3>(mesh.face_centroid(f));
}

/// The material of each region: the scene's E and nu, but for the regions [[material.region]]
/// names. A solid's Lame constants are plane strain's.
template <int dim>
MaterialTable scene_materials(const Scene& scene, const MeshOf<dim>& mesh) {
  int regions = 1;
  for (int r : mesh.regions()) regions = std::max(regions, r + 1);
  for (const auto& r : scene.material.regions) regions = std::max(regions, r.region + 1);
  std::vector<Material> by_region(static_cast<std::size_t>(regions), Material{scene.material.young, scene.material.poisson});
  for (const auto& r : scene.material.regions) by_region[static_cast<std::size_t>(r.region)] = Material{r.young, r.poisson};
  return MaterialTable(by_region, dim == 3 ? PlaneModel::strain : scene.material.model);
}

/// The scene's supports ([clamped], then each [[dirichlet]]) and loads (each [[loads.traction]])
/// with their keys, in the order the problem holds them.
std::vector<std::pair<const BoundarySelector*, std::string>> supports_and_loads(const Scene& scene) {
  std::vector<std::pair<const BoundarySelector*, std::string>> out;
  if (!scene.clamped.empty()) out.emplace_back(&scene.clamped, "clamped");
  for (std::size_t i = 0; i < scene.dirichlet.size(); ++i)
    out.emplace_back(&scene.dirichlet[i].boundary, "dirichlet[" + std::to_string(i) + "]");
  for (std::size_t i = 0; i < scene.tractions.size(); ++i)
    out.emplace_back(&scene.tractions[i].boundary, "loads.traction[" + std::to_string(i) + "]");
  return out;
}

/// [clamped] and each [[dirichlet]]: the prescribed displacements; on a piece (`piece`) each may
/// pick no facet of it.
template <int dim>
void add_dirichlet(BasicElasticityProblem<dim>& e, const Scene& scene, const FacetSelection<dim>& select, bool piece) {
  if (!scene.clamped.empty())
    e.dirichlet.push_back({select(scene.clamped, "clamped", piece), {}, BasicDirichletCondition<dim>::all_components(),
                           "clamped", select.vertices(scene.clamped, "clamped")});
  for (std::size_t i = 0; i < scene.dirichlet.size(); ++i) {
    const auto& d = scene.dirichlet[i];
    const std::string key = "dirichlet[" + std::to_string(i) + "]";
    const std::array<bool, 3> given{d.ux.has_value(), d.uy.has_value(), d.uz.has_value()};
    std::array<bool, dim> fix{};
    std::copy_n(given.begin(), dim, fix.begin());
    e.dirichlet.push_back({select(d.boundary, key, piece), detail::dirichlet_value_at<dim>(scene, i, 1.0), fix, key,
                           select.vertices(d.boundary, key)});
  }
}

/// [loads]: the body force (when not zero) and each [[loads.traction]]; on a piece (`piece`)
/// each may pick no facet of it.
template <int dim>
void add_loads(BasicElasticityProblem<dim>& e, const Scene& scene, const FacetSelection<dim>& select, bool piece) {
  e.body_force = detail::body_force_at<dim>(scene, 1.0);
  for (std::size_t i = 0; i < scene.tractions.size(); ++i) {
    BasicTractionLoad<dim> load;
    load.facets = select(scene.tractions[i].boundary, "loads.traction[" + std::to_string(i) + "]", piece);
    detail::set_traction_at<dim>(load, scene, i, 1.0);
    e.tractions.push_back(std::move(load));
  }
}

/// On a process's piece (SupportsAcross; collective): the error of the first support or load,
/// in the order the whole mesh's selection meets them, that picks no facet of any piece though
/// it selects facets (FacetSelection's, on every process alike), and then each support's vertices
/// on the other pieces added to its `vertices`. Every vertex a support holds of the whole mesh
/// lies among the own vertices of some process, whose piece holds every cell around it and so
/// every facet of the support at it.
template <int dim>
void complete_across(BasicElasticityProblem<dim>& e, const Scene& scene, const detail::SupportsAcross& across) {
  const auto selectors = supports_and_loads(scene);
  if (selectors.size() != e.dirichlet.size() + e.tractions.size())
    throw InternalError("a piece's supports and loads are not the scene's");
  const auto facets_of = [&](std::size_t k) -> const std::vector<int>& {
    return k < e.dirichlet.size() ? e.dirichlet[k].facets : e.tractions[k - e.dirichlet.size()].facets;
  };
  Eigen::VectorXd picks(static_cast<Eigen::Index>(selectors.size()));
  for (std::size_t k = 0; k < selectors.size(); ++k) picks(static_cast<Eigen::Index>(k)) = facets_of(k).empty() ? 0.0 : 1.0;
  std::vector<double> held;  // (support, vertex) of the process's own vertices
  for (std::size_t k = 0; k < e.dirichlet.size(); ++k)
    for (int v : e.dirichlet[k].held_vertices(*e.mesh))
      if (across.owned.at(static_cast<std::size_t>(v))) held.insert(held.end(), {static_cast<double>(k), static_cast<double>(v)});
  const Eigen::VectorXd picked = across.processes->sum_in_rank_order(picks);
  const Eigen::VectorXd all =
      across.processes->all_gather(Eigen::Map<const Eigen::VectorXd>(held.data(), static_cast<Eigen::Index>(held.size())));
  for (std::size_t k = 0; k < selectors.size(); ++k)
    if ((selectors[k].first->has_facets() || selectors[k].first->points.empty()) && picked(static_cast<Eigen::Index>(k)) == 0.0)
      throw FacetSelection<dim>::picks_none(scene, selectors[k].second);
  std::vector<std::vector<int>> elsewhere(e.dirichlet.size());
  for (Eigen::Index at = 0; at + 1 < all.size(); at += 2)
    elsewhere[static_cast<std::size_t>(all(at))].push_back(static_cast<int>(all(at + 1)));
  for (std::size_t k = 0; k < e.dirichlet.size(); ++k) {
    std::vector<int>& v = elsewhere[k];
    std::sort(v.begin(), v.end());
    v.erase(std::unique(v.begin(), v.end()), v.end());
    e.dirichlet[k].vertices.insert(e.dirichlet[k].vertices.end(), v.begin(), v.end());
  }
}

/// A contact part whose every node is clamped leaves nothing to touch: an error, not a silent
/// drop.
template <int dim>
void check_contact_not_clamped(const BasicElasticityProblem<dim>& e, const std::vector<int>& facets, const Scene& scene,
                               const std::string& key) {
  std::set<int> fixed, touching;
  for (const auto& d : e.dirichlet)
    if (std::all_of(d.fix.begin(), d.fix.end(), [](bool f) { return f; })) {
      const std::vector<int> held = d.held_vertices(*e.mesh);
      fixed.insert(held.begin(), held.end());
    }
  for (int f : facets) insert_facet_vertices(touching, *e.mesh, f);
  if (std::includes(fixed.begin(), fixed.end(), touching.begin(), touching.end()))
    throw InputError(key + ": every node of the contact part is also clamped ([clamped] or a [[dirichlet]] "
                     "with every component), so nothing is left to touch; end one of the parts before the other",
                     scene.where(key));
}

/// The box constraint against an obstacle needs a gap >= 0 at every contact node: an error naming
/// the part's constraint key (the solve checks it too, without the scene). A boundary that
/// cannot be made is left to the solve to report.
template <int dim>
void check_box_gaps(const BasicElasticityProblem<dim>& e, const BasicContactPart<dim>& part, const Scene& scene,
                    const std::string& key) {
  ContactBoundary boundary;
  try {
    boundary = make_contact_boundary(*e.mesh, std::vector<BasicContactPart<dim>>{part}, make_dof_map(*e.mesh, e.dirichlet));
  } catch (const InputError&) {
    return;
  }
  const std::string at = scene.lines.count(key + ".constraint") ? key + ".constraint" : key + ".obstacle";
  try {
    for (int i = 0; i < boundary.size(); ++i) require_box_gap(boundary.gaps(i), boundary.nodes[static_cast<std::size_t>(i)]);
  } catch (const InputError& err) {
    throw InputError(at + ": " + err.detail(), scene.where(at));
  }
}

/// Contact part i ([contact] or [[contact]] i): its facets, the obstacle or gap, the laws and
/// the constraint.
template <int dim>
BasicContactPart<dim> make_contact_part(const BasicElasticityProblem<dim>& e, const SceneContact& c, std::size_t i,
                                        const Scene& scene, const FacetSelection<dim>& select) {
  const std::string key = contact_key(scene, i);
  BasicContactPart<dim> p;
  p.name = contact_part_name(scene, i);
  p.facets = select(c.boundary, key);
  check_contact_not_clamped(e, p.facets, scene, key);
  detail::set_contact_data_at<dim>(p, scene, c, i, 1.0);
  try {
    p.law = detail::make_law(c.law);
  } catch (const InputError& err) {
    throw InputError(key + ".law: " + err.detail(), scene.where(key + ".law"));
  }
  p.constraint = c.constraint;
  p.law_from_surface = c.law_origin == "surface";
  if (c.friction) {
    try {
      p.friction = detail::make_friction_law(*c.friction);
      p.friction_bound = detail::make_friction_bound(*c.friction);
    } catch (const InputError& err) {
      throw InputError(key + ".friction: " + err.detail(), scene.where(key + ".friction.law"));
    }
  }
  if (p.obstacle && p.constraint == ConstraintKind::box) check_box_gaps(e, p, scene, key);
  return p;
}

/// A facet in two contact parts: an error at the later part naming both.
template <int dim>
void check_parts_disjoint(const std::vector<BasicContactPart<dim>>& parts, const Scene& scene, const MeshOf<dim>& mesh) {
  std::map<int, std::size_t> owner;
  for (std::size_t i = 0; i < parts.size(); ++i)
    for (int id : parts[i].facets) {
      const auto [at, added] = owner.emplace(id, i);
      if (added || at->second == i) continue;
      const std::string key = contact_key(scene, i);
      const std::string facet = dim == 2 ? "edge" : "face";
      throw InputError(key + ": selects " + facet_text(mesh, id) + ", which " + contact_key(scene, at->second) + " ('" +
                           parts[at->second].name + "') selects too; each " + facet +
                           " belongs to one contact part (parts may meet at " + (dim == 2 ? "a node" : "an edge or a node") +
                           ", which then belongs to the part listed first)",
                       scene.where(key));
    }
}

template <int dim>
BasicContactProblem<dim> contact_problem_of(const Scene& scene, const MeshOf<dim>& mesh, bool whole = true,
                                            std::span<const int> cut = {}, const detail::SupportsAcross* across = nullptr) {
  detail::require_dimension<dim>(scene);
  BasicContactProblem<dim> p;
  p.elasticity.mesh = &mesh;
  if (whole) detail::check_regions_used<dim>(scene, mesh, false);
  p.elasticity.materials = scene_materials<dim>(scene, mesh);
  p.elasticity.stabilization = scene.material.stabilization;
  const FacetSelection<dim> select(scene, mesh, cut);
  add_dirichlet(p.elasticity, scene, select, across != nullptr);
  add_loads(p.elasticity, scene, select, across != nullptr);
  if (across) complete_across(p.elasticity, scene, *across);
  const std::vector<SceneContact> scene_parts = contact_parts(scene);
  for (std::size_t i = 0; i < scene_parts.size(); ++i)
    p.parts.push_back(make_contact_part(p.elasticity, scene_parts[i], i, scene, select));
  check_parts_disjoint<dim>(p.parts, scene, mesh);
  return p;
}

}  // namespace

namespace detail {

template <int dim>
void require_dimension(const Scene& scene) {
  if (scene.dimension() == dim) return;
  if constexpr (dim == 2)
    throw InputError("mesh: a three-dimensional scene is built by build_problem<3> and solved by `hemivem solve` "
                     "(build_problem<2> takes two-dimensional scenes)",
                     scene.where("mesh"));
  else
    throw InputError("mesh: a two-dimensional scene is built by build_problem<2> (build_problem<3> takes a box of six "
                     "numbers, a 3D generator or a Gmsh file of volumes)",
                     scene.where("mesh"));
}

template void require_dimension<2>(const Scene&);
template void require_dimension<3>(const Scene&);

void require_route_memory(const Scene& scene, const MemoryEstimate& condensed, const std::string& what,
                          const std::string& where) {
  auto full_space_bytes = [&](std::string_view engine) {
    return full_space_memory(condensed, full_space_cost(scene.dimension(), scene.mesh.generator, engine)).solve_bytes;
  };
  const bool full_space = is_krylov_solver(scene.solver.linear);
  const double need = full_space ? full_space_bytes(scene.solver.linear) : condensed.solve_bytes;
  std::string advice = "use a smaller mesh";
  if (!full_space && run_memory(need) > available_memory())
    for (const std::string_view engine : known_krylov_engines()) {  // in the order of preference
      if (run_processes() > 1 && engine == "eigen-cg") continue;  // it runs in one process
      // what the run's processes would take together on that route
      const double full = full_space_run_memory(
          full_space_bytes(engine), full_space_cost(scene.dimension(), scene.mesh.generator, engine).base_bytes);
      if (full > available_memory()) continue;
      const std::string name(engine);
      const std::string across = run_processes() > 1 ? " across " + std::to_string(run_processes()) + " processes" : "";
      advice = "use a smaller mesh, or the full-space route, which factorizes nothing (--linear " + name +
               ", solver.linear = \"" + name + "\": an estimated " + format_bytes(full) + across +
               "; `hemivem backends` lists the Krylov engines built; docs/full-space.md)";
      break;
    }
  require_memory(need, what, where, advice);
}

void require_generated_memory(const Scene& scene) {
  const MemoryEstimate condensed = *generated_mesh_memory(scene);
  const std::string cells = scene.dimension() == 3 ? scene.mesh.cells3().text() : scene.mesh.cells().text();
  const std::string what = scene.mesh.generator + " n = " + cells + ": " + count_text(condensed.vertices) + " vertices";
  require_route_memory(scene, condensed, what, scene.where("mesh.n"));
}

std::string count_text(double v) {
  if (v < 1e9) return std::to_string(static_cast<long long>(std::llround(v)));
  std::ostringstream o;
  o << std::setprecision(2) << std::scientific << v;
  return o.str();
}

template <int dim>
void check_regions_used(const Scene& scene, const MeshOf<dim>& mesh, bool boxes) {
  check_regions_present(scene, std::set<int>(mesh.regions().begin(), mesh.regions().end()), boxes);
}

void check_regions_present(const Scene& scene, const std::set<int>& present, bool boxes) {
  const std::string cell = scene.dimension() == 2 ? "element" : "cell";
  for (std::size_t i = 0; i < scene.material.regions.size(); ++i) {
    const auto& r = scene.material.regions[i];
    if ((r.box && !boxes) || present.count(r.region)) continue;
    std::string ids;
    for (int id : present) ids += (ids.empty() ? "" : ", ") + std::to_string(id);
    const std::string key = "material.region[" + std::to_string(i) + "]";
    throw InputError(key + ".id: region " + std::to_string(r.region) + " matches no " + cell + " of the mesh " +
                         (r.box ? "(its box holds no " + cell + " centroid, or later boxes cover them)"
                                : "(the mesh's region ids are " + ids + ")"),
                     scene.where(scene.lines.count(key + ".id") ? key + ".id" : key));
  }
}

template void check_regions_used<2>(const Scene&, const Mesh&, bool);

template <int dim>
std::vector<int> select_facets(const Scene& scene, const MeshOf<dim>& mesh, const BoundarySelector& selector,
                               const std::string& key, std::span<const int> cut) {
  return FacetSelection<dim>(scene, mesh, cut)(selector, key);
}

template std::vector<int> select_facets<2>(const Scene&, const Mesh&, const BoundarySelector&, const std::string&,
                                           std::span<const int>);
template std::vector<int> select_facets<3>(const Scene&, const Mesh3D&, const BoundarySelector&, const std::string&,
                                           std::span<const int>);
template void check_regions_used<3>(const Scene&, const Mesh3D&, bool);

template <int dim>
std::unique_ptr<BasicBuiltProblem<dim>> built_on(const Scene& scene, MeshOf<dim> mesh, bool whole, std::span<const int> cut,
                                                 const SupportsAcross* across) {
  auto out = std::make_unique<BasicBuiltProblem<dim>>();
  out->mesh = std::move(mesh);
  out->problem = contact_problem_of<dim>(scene, out->mesh, whole, cut, across);
  out->has_contact = scene.contact.has_value();
  out->warnings = scene_warnings(scene);
  return out;
}

template std::unique_ptr<BuiltProblem> built_on<2>(const Scene&, Mesh, bool, std::span<const int>, const SupportsAcross*);
template std::unique_ptr<BuiltProblem3D> built_on<3>(const Scene&, Mesh3D, bool, std::span<const int>,
                                                     const SupportsAcross*);

}  // namespace detail

template <int dim>
std::unique_ptr<BasicBuiltProblem<dim>> build_problem(const Scene& scene, const RowDistribution* processes) {
  detail::require_dimension<dim>(scene);
  if constexpr (dim == 2)
    return scene.bodies.empty() ? detail::built_plane(scene, processes) : detail::built_bodies<2>(scene, processes);
  else
    return scene.bodies.empty() ? detail::built_solid(scene, processes) : detail::built_bodies<3>(scene, processes);
}

template std::unique_ptr<BuiltProblem> build_problem<2>(const Scene&, const RowDistribution*);
template std::unique_ptr<BuiltProblem3D> build_problem<3>(const Scene&, const RowDistribution*);

ContactProblem make_contact_problem(const Scene& scene, const Mesh& mesh) { return contact_problem_of<2>(scene, mesh); }

ContactProblem3D make_contact_problem(const Scene& scene, const Mesh3D& mesh) { return contact_problem_of<3>(scene, mesh); }

}  // namespace hemivem
