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
#include "scene_problem.hpp"
#include "scene_reader.hpp"

namespace hemivem {

using detail::fmt;
using detail::lower;

namespace {

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

namespace {

/// A scene of several bodies with their supports and loads together, as one body's would be:
/// what scene_warnings judges.
Scene bodies_together(const Scene& scene) {
  Scene flat = scene;
  flat.bodies.clear();
  for (const SceneBody& b : scene.bodies) {
    if (!b.clamped.empty()) flat.clamped = b.clamped;
    flat.dirichlet.insert(flat.dirichlet.end(), b.dirichlet.begin(), b.dirichlet.end());
    flat.tractions.insert(flat.tractions.end(), b.tractions.begin(), b.tractions.end());
  }
  if (!scene.bodies.empty()) flat.body_force = scene.bodies.front().body_force;
  return flat;
}

}  // namespace

std::optional<MemoryEstimate> generated_mesh_memory(const Scene& scene) {
  if (!scene.mesh.file.empty()) return std::nullopt;
  const SceneMesh& m = scene.mesh;
  if (scene.dimension() == 3) {
    const GridSize3 cells = m.cells3();
    return estimate_memory_3d(m.generator, cells.nx, cells.ny, cells.nz);
  }
  const GridSize cells = m.cells();
  return estimate_memory(m.generator, cells.nx, cells.ny);
}

std::string scene_mesh_description(const Scene& scene) {
  if (scene.bodies.empty()) return scene.mesh.description();
  std::string text;
  for (const SceneBody& b : scene.bodies) text += (text.empty() ? "" : "; ") + b.name + ": " + b.mesh.description();
  return text;
}

std::vector<std::string> scene_warnings(const Scene& given) {
  if (!given.bodies.empty()) return scene_warnings(bodies_together(given));
  const Scene& scene = given;
  auto zero = [](const SceneScalar& v) { return !v.is_expression() && v.value == 0.0; };
  auto nonzero = [&](const std::array<SceneScalar, 3>& v) { return !zero(v[0]) || !zero(v[1]) || !zero(v[2]); };
  auto prescribes = [&](const SceneDirichlet& d) {
    return (d.ux && !zero(*d.ux)) || (d.uy && !zero(*d.uy)) || (d.uz && !zero(*d.uz));
  };
  bool driven = nonzero(scene.body_force);
  for (const auto& t : scene.tractions) driven = driven || (t.pressure ? !zero(*t.pressure) : nonzero(t.value));
  for (const auto& d : scene.dirichlet) driven = driven || prescribes(d);
  const std::vector<SceneContact> parts = contact_parts(scene);
  // a projection onto another body measures the distance between the surfaces, which the
  // geometry may make negative (an interference fit) before any mesh is built
  for (const SceneContact& c : parts)
    driven = driven || c.obstacle.has_value() || c.gap.is_expression() || c.gap.value < 0.0 ||
             (c.against.has_value() && c.pairing == BodyPairing::projection);
  std::vector<std::string> out = scene.override_notices;
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

void detail::require_file_memory(const Scene& scene, const MemoryEstimate& condensed, int largest) {
  const std::string what = scene.mesh.file.string() + ": " + detail::count_text(condensed.vertices) +
                           " vertices, elements of up to " + std::to_string(largest) + " vertices";
  detail::require_route_memory(scene, condensed, what, scene.where("mesh.file"));
}

std::unique_ptr<BuiltProblem> detail::built_plane(const Scene& scene, const RowDistribution* processes) {
  return build_problem(scene, plane_mesh(scene, processes));
}

Mesh detail::plane_mesh(const Scene& scene, const RowDistribution* processes) {
  Mesh mesh;
  if (!scene.mesh.file.empty()) {
    const std::string ext = lower(scene.mesh.file.extension().string());
    if (ext == ".msh") mesh = read_gmsh(scene.mesh.file);
    else if (ext == ".poly2d") mesh = read_poly2d(scene.mesh.file).mesh;
    else throw InputError("mesh.file: unknown mesh format; expected .poly2d or .msh", scene.where("mesh.file"));
    int largest = 0;
    for (int e = 0; e < mesh.num_elements(); ++e) largest = std::max(largest, mesh.element_size(e));
    detail::require_file_memory(scene, estimate_memory(mesh), largest);
  } else {
    const auto& d = scene.mesh.domain;
    const GridSize cells = scene.mesh.cells();
    detail::require_generated_memory(scene);
    mesh = detail::generated_mesh(scene, [&] {
      if (scene.mesh.generator == "polar") {
        const auto [radii, angles] = polar_lists(scene);
        return make_polar(Vec2(scene.mesh.center[0], scene.mesh.center[1]), radii, angles);
      }
      if (scene.mesh.polygon.empty())
        return make_mesh(scene.mesh.generator, cells, Rectangle{d[0], d[1], d[2], d[3]},
                         static_cast<std::uint64_t>(scene.mesh.seed), processes);
      return make_mesh(scene.mesh.generator, scene.mesh.n, polygon_domain(scene),
                       static_cast<std::uint64_t>(scene.mesh.seed));
    });
  }

  return mesh;
}

std::unique_ptr<BuiltProblem> build_problem(const Scene& scene, Mesh given, bool apply_region_boxes) {
  return detail::built_plane_on(scene, std::move(given), apply_region_boxes, true);
}

namespace detail {

PolygonDomain polygon_domain(const Scene& scene) {
  PolygonDomain out;
  for (const auto& p : scene.mesh.polygon) out.corners.emplace_back(p[0], p[1]);
  return out;
}

std::array<std::vector<double>, 2> polar_lists(const Scene& scene) {
  const GridSize c = scene.mesh.cells();
  return polar_grid(scene.mesh.radii, scene.mesh.angles, c.nx, c.ny, scene.mesh.grading, scene.mesh.focus);
}

void apply_region_boxes(const Scene& scene, Mesh& mesh) {
  if (!scene.material.has_region_boxes()) return;
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

int region_count(const Scene& one, std::span<const int> own) {
  if (!one.material.has_region_boxes()) return 0;
  int largest = own.empty() ? 0 : *std::max_element(own.begin(), own.end());
  for (const auto& r : one.material.regions)
    if (r.box) largest = std::max(largest, r.region);
  return largest + 1;
}

std::unique_ptr<BuiltProblem> built_plane_on(const Scene& scene, Mesh mesh, bool apply_region_boxes, bool whole,
                                             std::span<const int> cut, const SupportsAcross* across) {
  // Regions given by boxes, then materials by region.
  if (apply_region_boxes) detail::apply_region_boxes(scene, mesh);
  if (whole) check_regions_used<2>(scene, mesh, true);
  return built_on<2>(scene, std::move(mesh), whole, cut, across);
}

}  // namespace detail

namespace {

bool mentions_t(const Scene& scene, const SceneScalar& v) {
  return v.is_expression() && ScalarExpression::parse(v.expression, scene.dimension()).uses_t();
}

}  // namespace

bool scene_is_proportional(const Scene& scene) {
  // a scene of several bodies: each body's loads and prescribed displacements as its scene of one body's
  for (std::size_t b = 0; b < scene.bodies.size(); ++b)
    if (!scene_is_proportional(body_scene(scene, b))) return false;
  auto any = [&](const auto&... v) { return (mentions_t(scene, v) || ...); };
  if (any(scene.body_force[0], scene.body_force[1], scene.body_force[2])) return false;
  for (const auto& t : scene.tractions)
    if (t.pressure ? mentions_t(scene, *t.pressure) : any(t.value[0], t.value[1], t.value[2])) return false;
  for (const auto& d : scene.dirichlet)
    if ((d.ux && mentions_t(scene, *d.ux)) || (d.uy && mentions_t(scene, *d.uy)) || (d.uz && mentions_t(scene, *d.uz)))
      return false;
  return !scene_path_moves_gaps(scene);
}

bool scene_path_moves_gaps(const Scene& scene) {
  for (const SceneContact& c : contact_parts(scene))
    if (c.obstacle ? c.obstacle->motion.has_value() : mentions_t(scene, c.gap)) return true;
  return false;
}

void set_load_factor(const Scene& scene, double t, ContactProblem& problem) { detail::set_problem_at(scene, t, problem); }

void set_load_factor(const Scene& scene, double t, ContactProblem3D& problem) { detail::set_problem_at(scene, t, problem); }

}  // namespace hemivem
