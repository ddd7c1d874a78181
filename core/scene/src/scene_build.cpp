// A scene made concrete: the mesh, the materials, the boundary parts, loads and contact data.
#include <hemivem/scene/scene.hpp>

#include <cmath>
#include <iomanip>
#include <map>
#include <set>
#include <sstream>

#include <hemivem/mesh/gmsh.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/poly2d.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/scene/resources.hpp>

#include "scene_fields.hpp"
#include "scene_reader.hpp"

namespace hemivem {

using detail::fmt;
using detail::lower;

namespace {

// A vertex count as an integer when small enough to read, else in scientific notation.
std::string count_text(double v) {
  if (v < 1e9) return std::to_string(static_cast<long long>(std::llround(v)));
  std::ostringstream o;
  o << std::setprecision(2) << std::scientific << v;
  return o.str();
}

double param(const SceneLaw& law, const std::string& name, double fallback) {
  auto it = law.parameters.find(name);
  return it == law.parameters.end() ? fallback : it->second;
}


}  // namespace

namespace detail {

std::shared_ptr<const ContactLaw> make_law(const SceneLaw& law) {
  const std::string n = lower(law.name);
  if (n == "piecewise") {
    if (!law.j.empty())
      return std::make_shared<PiecewisePolynomialLaw>(PiecewisePolynomialLaw::from_j(
          "piecewise", law.breakpoints, std::vector<Polynomial>(law.j.begin(), law.j.end())));
    std::vector<Polynomial> j1(law.j1.begin(), law.j1.end()), j2(law.j2.begin(), law.j2.end());
    return std::make_shared<PiecewisePolynomialLaw>("piecewise", law.breakpoints, j1, j2);
  }
  if (n == "linear") return linear_law(param(law, "stiffness", 100.0));
  if (n == "kinked") return kinked_law(param(law, "sigma", 0.3), param(law, "stiffness", 100.0));
  if (n == "sawtooth")
    return sawtooth_law(param(law, "stiffness", 100.0), param(law, "r1", 0.01), param(law, "residual", 0.2),
                        param(law, "r2", 0.02));
  return make_contact_law(n);
}


std::shared_ptr<const ContactLaw> make_friction_law(const SceneLaw& law) {
  const std::string n = lower(law.name);
  // a bound that depends on the normal contact scales a unit Tresca law (make_friction_bound)
  if (n == "coulomb" || (n == "tresca" && !law.bound_table.empty())) return tresca_law(1.0);
  if (n == "tresca") return tresca_law(param(law, "bound", 0.1));
  if (n == "slip-weakening")
    return slip_weakening_law(param(law, "static", 0.1), param(law, "kinetic", 0.05), param(law, "distance", 0.01));
  if (n != "piecewise") throw InputError("unknown friction law '" + law.name + "'");
  auto j = make_law(law);
  // a friction law acts on u_tau and -u_tau alike: j even, checked at the breakpoints mirrored,
  // between them and beyond them
  std::vector<double> points{0.0, 1.0};
  for (double b : law.breakpoints) points.insert(points.end(), {b, 2.0 * b, 0.5 * b});
  for (std::size_t k = 0; k + 1 < law.breakpoints.size(); ++k)
    points.push_back(0.5 * (law.breakpoints[k] + law.breakpoints[k + 1]));
  for (double r : points) {
    const double a = j->value(LawPart::j, r), b = j->value(LawPart::j, -r);
    if (!(std::abs(a - b) <= 1e-9 * (1.0 + std::abs(a) + std::abs(b))))
      throw InputError("a friction law must be even, j(r) = j(-r); this one has j(" + fmt(r) + ") = " + fmt(a) +
                       " and j(" + fmt(-r) + ") = " + fmt(b));
  }
  return j;
}

std::optional<FrictionBound> make_friction_bound(const SceneLaw& law) {
  const std::string n = lower(law.name);
  if (n == "coulomb") return FrictionBound{FrictionBound::Kind::coulomb, param(law, "coefficient", 0.3), {}};
  if (n == "tresca" && !law.bound_table.empty())
    return FrictionBound{FrictionBound::Kind::normal_displacement, 0.0, law.bound_table};
  return std::nullopt;
}

Obstacle make_obstacle(const SceneObstacle& o) {
  Obstacle b;
  b.shape = obstacle_shape_from_string(o.shape);
  b.point = Vec2(o.point[0], o.point[1]);
  b.normal = Vec2(o.normal[0], o.normal[1]);
  b.center = Vec2(o.center[0], o.center[1]);
  b.radius = o.radius;
  for (const auto& q : o.points) b.points.emplace_back(q[0], q[1]);
  return b;
}

}  // namespace detail

using detail::make_friction_bound;
using detail::make_friction_law;
using detail::make_law;
using detail::make_obstacle;

std::vector<std::string> scene_warnings(const Scene& scene) {
  auto zero = [](const SceneScalar& v) { return !v.is_expression() && v.value == 0.0; };
  auto nonzero = [&](const std::array<SceneScalar, 3>& v) { return !zero(v[0]) || !zero(v[1]) || !zero(v[2]); };
  auto prescribes = [&](const SceneDirichlet& d) {
    return (d.ux && !zero(*d.ux)) || (d.uy && !zero(*d.uy)) || (d.uz && !zero(*d.uz));
  };
  bool driven = nonzero(scene.body_force);
  for (const auto& t : scene.tractions) driven = driven || (t.pressure ? !zero(*t.pressure) : nonzero(t.value));
  for (const auto& d : scene.dirichlet) driven = driven || prescribes(d);
  const std::vector<SceneContact> parts = contact_parts(scene);
  for (const SceneContact& c : parts)
    driven = driven || c.obstacle.has_value() || c.gap.is_expression() || c.gap.value < 0.0;
  std::vector<std::string> out;
  if (scene.clamped.empty() && scene.dirichlet.empty() && scene.dimension() != 3)  // 3D: refused when solved
    out.push_back("the scene has no [clamped] and no [[dirichlet]]: no part of the boundary is held, only what the "
                  "contact provides (the paper's supports are [clamped] side = [\"left\", \"right\"])");
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const std::string key = contact_key(scene, i) + ".gap";
    if (parts[i].constraint == ConstraintKind::bilateral && scene.lines.count(key))
      out.push_back(scene.where(key) + ": " + key + " is not used with constraint = \"bilateral\" (u_nu = 0)");
  }
  if (!driven)
    out.push_back("nothing drives this problem: no load, no prescribed displacement other than zero and no "
                  "obstacle; its solution is u = 0 unless the contact law pushes at u_nu = 0 (a missing [loads] table "
                  "means no loads)");
  // a path along which nothing changes: what t multiplies is zero and no value mentions t
  bool scaled = nonzero(scene.body_force);
  for (const auto& t : scene.tractions) scaled = scaled || (t.pressure ? !zero(*t.pressure) : nonzero(t.value));
  for (const auto& d : scene.dirichlet) scaled = scaled || prescribes(d);
  if (scene.path && scene.path->factors().size() > 1 && !scaled && scene_is_proportional(scene))
    out.push_back(scene.where("path") +
                  ": every step of the path solves the same problem: no load or prescribed displacement is multiplied "
                  "by t and no value mentions t (a gap or an obstacle that should move needs an expression in t or "
                  "contact.obstacle.motion)");
  return out;
}

namespace {

/// Every [[material.region]] (those with a box too when `boxes`) names a region some element
/// of the mesh is in; an error at the region's id otherwise.
void check_regions_used(const Scene& scene, const Mesh& mesh, bool boxes) {
  const std::set<int> present(mesh.regions().begin(), mesh.regions().end());
  for (std::size_t i = 0; i < scene.material.regions.size(); ++i) {
    const auto& r = scene.material.regions[i];
    if ((r.box && !boxes) || present.count(r.region)) continue;
    std::string ids;
    for (int id : present) ids += (ids.empty() ? "" : ", ") + std::to_string(id);
    const std::string key = "material.region[" + std::to_string(i) + "]";
    throw InputError(key + ".id: region " + std::to_string(r.region) + " matches no element of the mesh " +
                         (r.box ? "(its box holds no element centroid, or later boxes cover them)"
                                : "(the mesh's region ids are " + ids + ")"),
                     scene.where(scene.lines.count(key + ".id") ? key + ".id" : key));
  }
}

}  // namespace

std::unique_ptr<BuiltProblem> build_problem(const Scene& scene) {
  if (scene.dimension() == 3)
    throw InputError("mesh: a three-dimensional scene is built by build_problem_3d and solved by `hemivem solve` (this "
                     "solve takes two-dimensional scenes)",
                     scene.where("mesh"));
  Mesh mesh;
  if (!scene.mesh.file.empty()) {
    const std::string ext = lower(scene.mesh.file.extension().string());
    if (ext == ".msh") mesh = read_gmsh(scene.mesh.file);
    else if (ext == ".poly2d") mesh = read_poly2d(scene.mesh.file).mesh;
    else throw InputError("mesh.file: unknown mesh format; expected .poly2d or .msh", scene.where("mesh.file"));
    const MemoryEstimate need = estimate_memory(mesh);
    int largest = 0;
    for (int e = 0; e < mesh.num_elements(); ++e) largest = std::max(largest, mesh.element_size(e));
    require_memory(need.solve_bytes,
                   scene.mesh.file.string() + ": " + count_text(need.vertices) + " vertices, elements of up to " +
                       std::to_string(largest) + " vertices",
                   scene.where("mesh.file"));
  } else {
    const auto& d = scene.mesh.domain;
    const GridSize cells = scene.mesh.cells();
    const MemoryEstimate need = estimate_memory(scene.mesh.generator, cells.nx, cells.ny);
    require_memory(need.solve_bytes,
                   scene.mesh.generator + " n = " + cells.text() + ": " + count_text(need.vertices) + " vertices",
                   scene.where("mesh.n"));
    try {
      if (scene.mesh.polygon.empty()) {
        mesh = make_mesh(scene.mesh.generator, cells, Rectangle{d[0], d[1], d[2], d[3]},
                         static_cast<std::uint64_t>(scene.mesh.seed));
      } else {
        PolygonDomain poly;
        for (const auto& p : scene.mesh.polygon) poly.corners.emplace_back(p[0], p[1]);
        mesh = make_mesh(scene.mesh.generator, scene.mesh.n, poly, static_cast<std::uint64_t>(scene.mesh.seed));
      }
    } catch (const MeshError& e) {
      throw MeshError("mesh: the generated mesh is invalid: " + e.detail(), e.element(), scene.where("mesh"));
    } catch (const InputError& e) {
      throw InputError("mesh: " + e.detail(), scene.where("mesh"));
    }
  }

  return build_problem(scene, std::move(mesh));
}

std::unique_ptr<BuiltProblem> build_problem(const Scene& scene, Mesh given, bool apply_region_boxes) {
  auto out = std::make_unique<BuiltProblem>();
  Mesh& mesh = out->mesh;
  mesh = std::move(given);
  // Regions given by boxes, then materials by region.
  if (apply_region_boxes && std::any_of(scene.material.regions.begin(), scene.material.regions.end(), [](const auto& r) { return r.box; })) {
    std::vector<int> ids = mesh.regions();
    ids.resize(static_cast<std::size_t>(mesh.num_elements()), 0);
    for (const auto& r : scene.material.regions) {
      if (!r.box) continue;
      const auto& b = *r.box;
      for (int e = 0; e < mesh.num_elements(); ++e) {
        const Vec2 c = mesh.centroid(e);
        if (c.x() >= b[0] && c.x() <= b[1] && c.y() >= b[2] && c.y() <= b[3]) ids[static_cast<std::size_t>(e)] = r.region;
      }
    }
    mesh.set_regions(std::move(ids));
  }
  check_regions_used(scene, mesh, true);
  out->problem = make_contact_problem(scene, mesh);
  out->has_contact = scene.contact.has_value();
  out->warnings = scene_warnings(scene);
  return out;
}

namespace {

/// The material of each region: the scene's E and nu, but for the regions [[material.region]]
/// names.
MaterialTable scene_materials(const Scene& scene, const Mesh& mesh) {
  int regions = 1;
  for (int r : mesh.regions()) regions = std::max(regions, r + 1);
  for (const auto& r : scene.material.regions) regions = std::max(regions, r.region + 1);
  std::vector<Material> by_region(static_cast<std::size_t>(regions), Material{scene.material.young, scene.material.poisson});
  for (const auto& r : scene.material.regions) by_region[static_cast<std::size_t>(r.region)] = Material{r.young, r.poisson};
  return MaterialTable(by_region, scene.material.model);
}

/// The boundary edges of the mesh a selector of the scene picks (sorted, distinct); an error
/// naming the selector's key when it picks none or names a group the mesh lacks.
class EdgeSelection {
 public:
  EdgeSelection(const Scene& scene, const Mesh& mesh) : scene_(scene), mesh_(mesh), box_(mesh.bounding_box()) {}

  std::vector<int> operator()(const BoundarySelector& b, const std::string& key) const {
    std::vector<Segment> segs;
    for (const auto& side : b.sides) segs.push_back(rectangle_side(box_, side, b.tolerance));
    const double size = std::max(box_.width(), box_.height());
    for (const auto& s : b.segments) segs.push_back(Segment{Vec2(s[0], s[1]), Vec2(s[2], s[3]), b.tolerance * size});
    std::vector<int> edges;
    if (!segs.empty()) edges = select_boundary_edges(mesh_, segs);
    for (const auto& g : b.groups) {
      try {
        const auto e = select_boundary_edges(mesh_, g);
        edges.insert(edges.end(), e.begin(), e.end());
      } catch (const InputError& e) {
        throw InputError(key + ".group: " + e.detail(), scene_.where(key + ".group"));
      }
    }
    std::sort(edges.begin(), edges.end());
    edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
    if (edges.empty()) throw InputError(key + ": selects no boundary edge of the mesh", scene_.where(key));
    return edges;
  }

 private:
  const Scene& scene_;
  const Mesh& mesh_;
  const Rectangle box_;
};

/// [clamped] and each [[dirichlet]]: the prescribed displacements.
void add_dirichlet(ElasticityProblem& e, const Scene& scene, const EdgeSelection& select) {
  if (!scene.clamped.empty()) e.dirichlet.push_back({select(scene.clamped, "clamped"), {}, {true, true}, "clamped"});
  for (std::size_t i = 0; i < scene.dirichlet.size(); ++i) {
    const auto& d = scene.dirichlet[i];
    const std::string key = "dirichlet[" + std::to_string(i) + "]";
    e.dirichlet.push_back({select(d.boundary, key), detail::dirichlet_value_at<2>(scene, i, 1.0),
                           {d.ux.has_value(), d.uy.has_value()}, key});
  }
}

/// [loads]: the body force (when not zero) and each [[loads.traction]].
void add_loads(ElasticityProblem& e, const Scene& scene, const EdgeSelection& select) {
  e.body_force = detail::body_force_at<2>(scene, 1.0);
  for (std::size_t i = 0; i < scene.tractions.size(); ++i) {
    TractionLoad load;
    load.edges = select(scene.tractions[i].boundary, "loads.traction[" + std::to_string(i) + "]");
    detail::set_traction_at<2>(load, scene, i, 1.0);
    e.tractions.push_back(std::move(load));
  }
}

/// A contact part whose every node is clamped leaves nothing to touch: an error, not a silent
/// drop.
void check_contact_not_clamped(const ElasticityProblem& e, const std::vector<int>& edges, const Mesh& mesh,
                               const Scene& scene, const std::string& key) {
  std::set<int> fixed, touching;
  for (const auto& d : e.dirichlet)
    if (d.fix[0] && d.fix[1])
      for (int id : d.edges) fixed.insert({mesh.edge(id).v0, mesh.edge(id).v1});
  for (int id : edges) touching.insert({mesh.edge(id).v0, mesh.edge(id).v1});
  if (std::includes(fixed.begin(), fixed.end(), touching.begin(), touching.end()))
    throw InputError(key + ": every node of the contact part is also clamped ([clamped] or a [[dirichlet]] "
                     "with both components), so nothing is left to touch; end one of the parts before the other",
                     scene.where(key));
}

/// Contact part i ([contact] or [[contact]] i): its edges, the obstacle or gap, the laws and
/// the constraint.
ContactPart make_contact_part(const ElasticityProblem& e, const SceneContact& c, std::size_t i, const Scene& scene,
                              const Mesh& mesh, const EdgeSelection& select) {
  const std::string key = contact_key(scene, i);
  ContactPart p;
  p.name = contact_part_name(scene, i);
  p.facets = select(c.boundary, key);
  check_contact_not_clamped(e, p.facets, mesh, scene, key);
  detail::set_contact_data_at<2>(p, scene, c, i, 1.0);
  try {
    p.law = make_law(c.law);
  } catch (const InputError& err) {
    throw InputError(key + ".law: " + err.detail(), scene.where(key + ".law"));
  }
  p.constraint = c.constraint;
  p.law_from_surface = c.law_origin == "surface";
  if (c.friction) {
    try {
      p.friction = make_friction_law(*c.friction);
      p.friction_bound = make_friction_bound(*c.friction);
    } catch (const InputError& err) {
      throw InputError(key + ".friction: " + err.detail(), scene.where(key + ".friction.law"));
    }
  }
  return p;
}

/// An edge in two contact parts: an error at the later part naming both.
void check_parts_disjoint(const std::vector<ContactPart>& parts, const Scene& scene, const Mesh& mesh) {
  std::map<int, std::size_t> owner;
  for (std::size_t i = 0; i < parts.size(); ++i)
    for (int id : parts[i].facets) {
      const auto [at, added] = owner.emplace(id, i);
      if (added || at->second == i) continue;
      const MeshEdge& edge = mesh.edge(id);
      const Vec2 a = mesh.vertex(edge.v0), b = mesh.vertex(edge.v1);
      const std::string key = contact_key(scene, i);
      throw InputError(key + ": selects the boundary edge from (" + fmt(a.x()) + ", " + fmt(a.y()) + ") to (" +
                           fmt(b.x()) + ", " + fmt(b.y()) + "), which " + contact_key(scene, at->second) + " ('" +
                           parts[at->second].name + "') selects too; each edge belongs to one contact part (parts "
                           "may meet at a node, which then belongs to the part listed first)",
                       scene.where(key));
    }
}

}  // namespace

ContactProblem make_contact_problem(const Scene& scene, const Mesh& mesh) {
  if (scene.dimension() == 3)
    throw InputError("mesh: a three-dimensional scene poses a ContactProblem3D (build_problem_3d)", scene.where("mesh"));
  ContactProblem p;
  p.elasticity.mesh = &mesh;
  check_regions_used(scene, mesh, false);
  p.elasticity.materials = scene_materials(scene, mesh);
  p.elasticity.stabilization = scene.material.stabilization;
  const EdgeSelection select(scene, mesh);
  add_dirichlet(p.elasticity, scene, select);
  add_loads(p.elasticity, scene, select);
  const std::vector<SceneContact> scene_parts = contact_parts(scene);
  std::vector<ContactPart> parts;
  for (std::size_t i = 0; i < scene_parts.size(); ++i)
    parts.push_back(make_contact_part(p.elasticity, scene_parts[i], i, scene, mesh, select));
  check_parts_disjoint(parts, scene, mesh);
  p.parts = std::move(parts);
  return p;
}

bool scene_is_proportional(const Scene& scene) {
  const int dimension = scene.dimension();
  auto mentions_t = [dimension](const SceneScalar& v) {
    return v.is_expression() && ScalarExpression::parse(v.expression, dimension).uses_t();
  };
  auto any = [&](const auto&... v) { return (mentions_t(v) || ...); };
  if (any(scene.body_force[0], scene.body_force[1], scene.body_force[2])) return false;
  for (const auto& t : scene.tractions)
    if (t.pressure ? mentions_t(*t.pressure) : any(t.value[0], t.value[1], t.value[2])) return false;
  for (const auto& d : scene.dirichlet)
    if ((d.ux && mentions_t(*d.ux)) || (d.uy && mentions_t(*d.uy)) || (d.uz && mentions_t(*d.uz))) return false;
  for (const SceneContact& c : contact_parts(scene))
    if (c.obstacle ? c.obstacle->motion.has_value() : mentions_t(c.gap)) return false;
  return true;
}

void set_load_factor(const Scene& scene, double t, ContactProblem& problem) { detail::set_problem_at(scene, t, problem); }

void set_load_factor(const Scene& scene, double t, ContactProblem3D& problem) { detail::set_problem_at(scene, t, problem); }

}  // namespace hemivem
