// Scenes: one contact problem described in a TOML file (schema in docs/reference/scenes.md).
//
// A Scene is plain data with the defaults of the paper's Example 4.1 on N = 64 squares.
// parse_scene reads and validates a file; every defect (unknown key, wrong type, value out
// of range, syntax) is an InputError whose where() is "file:line" (or "file:line:column"
// for syntax errors). build_problem turns a Scene into a mesh and a ContactProblem.
//
// Three-dimensional scenes (docs/reference/scenes.md, "Three-dimensional scenes"): a scene whose
// mesh is a box of six numbers, a 3D generator (cubes, tetrahedra) or a Gmsh file of volume
// elements has SceneMesh::dimension 3; its vectors have three components, its sides are those of
// a box and its expressions take z. build_problem<3> makes its mesh and ContactProblem3D.
//
// Loading paths ([path], ScenePath): the scene's data as functions of a load factor t. Loads
// (body force, traction values, pressures) and prescribed displacements ([[dirichlet]] values;
// [clamped] is zero) that do not mention t are multiplied by t; gaps and obstacles that do not
// mention t stay fixed; an obstacle's motion is driving data (a number m moves it by t m); any
// value that mentions t is evaluated at t as written. A static solve is t = 1: a scene means
// the same problem with or without [path].
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include <hemivem/contact/contact3d.hpp>
#include <hemivem/scene/resources.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/support/names.hpp>
#include <hemivem/vem/material.hpp>
#include <hemivem/mesh/body_range.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/reduced_problem.hpp>
#include <hemivem/vem/element.hpp>

namespace hemivem {

/// The schema version this library reads and writes.
inline constexpr int scene_schema_version = 1;

/// A set of boundary edges: the union of the sides of the mesh bounding box, named edge
/// groups of the mesh, and straight segments [x0, y0, x1, y1] (edges whose end points lie
/// within `tolerance` times the mesh's size, the longer side of its bounding box, of a segment
/// or side: the same selection at every scale). At least one of the three is given. In three
/// dimensions a set of boundary faces: the sides of the box, face groups, no segments.
/// A support ([clamped], [[dirichlet]]) may also hold single vertices: `points`, each matched
/// to the mesh vertex within `tolerance` times the mesh's size.
struct BoundarySelector {
  /// "left", "right", "top", "bottom"; in 3D "x0", "x1", "y0", "y1", "z0", "z1", "bottom" (z0), "top" (z1)
  std::vector<std::string> sides;
  std::vector<std::string> groups;               ///< Mesh::edge_group names (3D: Mesh3D::face_group names)
  std::vector<std::array<double, 4>> segments;   ///< x0, y0, x1, y1
  double tolerance = 1e-8;
  std::vector<std::array<double, 3>> points;     ///< supports only: x, y (z = 0 in 2D)
  bool has_facets() const noexcept { return !sides.empty() || !groups.empty() || !segments.empty(); }
  bool empty() const noexcept { return !has_facets() && points.empty(); }
  bool operator==(const BoundarySelector&) const = default;
};

/// A number, or an expression in x, y (z in 3D) and the load factor t (muparser syntax,
/// hemivem/scene/expression.hpp) given as a string: "0.02 + 0.5*x^2", "-8*t^2".
struct SceneScalar {
  double value = 0.0;
  std::string expression;  ///< empty: the number `value`
  bool is_expression() const noexcept { return !expression.empty(); }
  bool operator==(const SceneScalar&) const = default;
};

struct SceneMesh {
  /// 2, or 3: a box `box` (mesh.domain of six numbers), a generator of mesh3d_generator_names()
  /// that meshes boxes only (cubes, tetrahedra), mesh.n = [nx, ny, nz], or a Gmsh file of volume
  /// elements.
  int dimension = 2;
  std::string generator = "squares";   ///< used when `file` is empty ("cubes" by default in 3D)
  std::filesystem::path file;          ///< .poly2d or .msh; absolute once parsed
  int n = 64;                          ///< cells per side; along x when `ny` is given
  std::optional<int> ny;               ///< cells along y: mesh.n = [nx, ny] (rectangle domains)
  std::optional<int> nz;               ///< 3D: cells along z, with ny: mesh.n = [nx, ny, nz]
  std::array<double, 6> box{0.0, 1.0, 0.0, 1.0, 0.0, 1.0};  ///< 3D: x0, x1, y0, y1, z0, z1
  std::int64_t seed = 1;
  std::array<double, 4> domain{0.0, 1.0, 0.0, 1.0};  ///< x0, x1, y0, y1
  /// A polygon domain's corners (voronoi and triangles); empty: the rectangle `domain`.
  std::vector<std::array<double, 2>> polygon;
  /// generator "polar" (make_polar): a ring, a disk or a sector of either around `center`,
  /// between the radii `radii` = [r0, r1] and the angles `angles` = [a0, a1] (degrees),
  /// n = [cells along the radius, cells around]. With `grading` > 1 the cells grow by that
  /// ratio inwards from the circle r1 and, given `focus` (degrees), away from that angle on
  /// both sides (polar_grid).
  std::array<double, 2> center{0.0, 0.0};
  std::array<double, 2> radii{0.0, 1.0};
  std::array<double, 2> angles{0.0, 360.0};
  double grading = 1.0;
  std::optional<double> focus;
  /// n x n, or n x ny.
  GridSize cells() const { return ny ? GridSize(n, *ny) : GridSize(n); }
  /// 3D: n x n x n, or nx x ny x nz.
  GridSize3 cells3() const { return ny && nz ? GridSize3(n, *ny, *nz) : GridSize3(n); }
  /// How the mesh is made, for reports: "squares n=64", "voronoi n=[32, 8]", or the file.
  std::string description() const;
  /// mesh.n as a scene writes it: "64", "[32, 8]", "[8, 8, 4]" (cells() or cells3() by dimension).
  std::string n_text() const { return dimension == 3 ? cells3().text() : cells().text(); }
  bool operator==(const SceneMesh&) const = default;
};

struct SceneRegionMaterial {
  int region = 0;
  double young = 1.0;
  double poisson = 0.0;
  /// [x0, x1, y0, y1]: when given, the elements whose centroid lies in this rectangle are
  /// put into `region` (later regions win where boxes overlap); otherwise the region ids of
  /// the mesh file are used.
  std::optional<std::array<double, 4>> box;
  bool operator==(const SceneRegionMaterial&) const = default;
};

struct SceneMaterial {
  double young = 65.0;
  double poisson = 0.29;
  PlaneModel model = PlaneModel::strain;
  Stabilization stabilization = Stabilization::two_mu;
  std::vector<SceneRegionMaterial> regions;  ///< overrides for single regions
  /// Whether some region puts the elements into it by a box.
  bool has_region_boxes() const noexcept {
    for (const SceneRegionMaterial& r : regions)
      if (r.box) return true;
    return false;
  }
  bool operator==(const SceneMaterial&) const = default;
};

/// A traction on boundary edges: a vector `value` [tx, ty], or a `pressure` p along the
/// inward normal of each edge (t = -p n, n the outward normal). In 3D on faces, [tx, ty, tz].
struct SceneTraction {
  BoundarySelector boundary;
  std::array<SceneScalar, 3> value{};  ///< [tx, ty] and tz = 0 in 2D
  std::optional<SceneScalar> pressure;  ///< given: the traction is the pressure, value unused
  bool operator==(const SceneTraction&) const = default;
};

/// A prescribed displacement on boundary edges ([[dirichlet]]) and at single vertices
/// (`point`): both components (value = [ux, uy]) or one of them (a roller: the other
/// component stays free). In 3D on faces: value = [ux, uy, uz], or any of ux, uy, uz (the
/// others stay free).
struct SceneDirichlet {
  BoundarySelector boundary;
  std::optional<SceneScalar> ux, uy, uz;
  bool operator==(const SceneDirichlet&) const = default;
};

struct SceneLaw {
  /// A shipped law (contact_law_names()) or "piecewise" (breakpoints + j1/j2 pieces); for
  /// friction, a friction law (friction_law_names()).
  std::string name = "paper";
  /// e.g. stiffness, sigma, r1, residual, r2; friction: bound, static, kinetic, distance,
  /// coefficient
  std::map<std::string, double> parameters;
  std::vector<double> breakpoints;
  std::vector<std::vector<double>> j1, j2;   ///< per piece, coefficients lowest degree first
  /// The potential alone (piecewise): hemivem computes the DC split (PiecewisePolynomialLaw::from_j);
  /// empty when j1 and j2 are given.
  std::vector<std::vector<double>> j;
  /// Friction "tresca" with bound = [[u_nu, h], ...]: the bound h(u_nu), piecewise linear
  /// through these points (increasing u_nu, h >= 0), constant beyond the first and the last
  /// (FrictionBound::Kind::normal_displacement); empty: the number parameters["bound"].
  std::vector<std::array<double, 2>> bound_table;
  bool operator==(const SceneLaw&) const = default;
};

/// [contact.obstacle]: a rigid obstacle instead of a gap (hemivem/obstacle.hpp). Points and
/// vectors have two coordinates in 2D (the third is 0) and three in 3D.
struct SceneObstacle {
  std::string shape = "plane";              ///< "plane", "circle" or "polyline"; 3D: "plane", "sphere" or "cylinder"
  std::array<double, 3> point{0.0, 0.0, 0.0};   ///< plane: a point of it
  std::array<double, 3> normal{0.0, 1.0, 0.0};  ///< plane: the normal pointing into the body
  std::array<double, 3> center{0.0, 0.0, 0.0};  ///< circle, sphere, cylinder (a point of its axis)
  std::array<double, 3> axis{1.0, 0.0, 0.0};    ///< cylinder: the direction of its axis
  double radius = 1.0;                      ///< circle, sphere, cylinder
  std::vector<std::array<double, 2>> points;  ///< polyline: the surface, the body on its left
  /// [mx, my] ([mx, my, mz] in 3D): the obstacle translated by the motion at the load factor t
  /// (numbers m: t m; expressions in t only). None: the obstacle stays where it is given. A
  /// static solve (t = 1) sees the obstacle moved by the motion at 1.
  std::optional<std::array<SceneScalar, 3>> motion;
  bool operator==(const SceneObstacle&) const = default;
};

/// One contact part: [contact], or one table of [[contact]] (docs/reference/scenes.md).
struct SceneContact {
  /// Names the part in results (contact.csv, result.json ...): letters, digits, '-', '_' and
  /// '.'; empty: contact_part_name's default.
  std::string name;
  BoundarySelector boundary{{"bottom"}, {}, {}, 1e-8, {}};
  SceneLaw law;
  SceneScalar gap{0.02, {}};  ///< g >= 0 at every contact node (unused with an obstacle)
  std::optional<SceneObstacle> obstacle;
  /// box, one-sided, none, or bilateral (u_nu = 0: the body slides on Gamma_3; gap and normal
  /// law unused).
  ConstraintKind constraint = ConstraintKind::box;
  /// contact.law_origin: "body" (the law acts on u_nu, its origin where the body starts) or
  /// "surface" (on the distance u_nu - g to the foundation's or obstacle's surface).
  std::string law_origin = "body";
  /// [contact.friction]: the law of the tangential displacement ("tresca", "slip-weakening",
  /// an even "piecewise" law, or "coulomb"; parameters bound (a number, or a table h(u_nu):
  /// SceneLaw::bound_table) / static, kinetic, distance / coefficient); none: frictionless.
  /// "coulomb" (the bound mu p, p the contact pressure) and a bound table depend on the normal
  /// contact: the problem's friction is then tresca_law(1) with a FrictionBound.
  std::optional<SceneLaw> friction;
  /// In a scene of several bodies ([[body]]): the body whose boundary `boundary` selects (its
  /// side and group names written "body.side", "body.group"); empty in a scene of one body.
  std::string body;
  /// Two bodies (docs/two-bodies.md): the other body's surface this part meets, `against =
  /// "body.side"` (or "body.group"); the part's law, constraint, gap and friction then act on
  /// the displacement relative to that body's. None: a foundation or an obstacle.
  std::optional<BoundarySelector> against;
  std::string against_body;
  /// With `against`: "vertex" (each node meets the vertex of the other body at its point; the
  /// meshes are matched along the part), or "projection" (the point of the other surface along
  /// its normal, at its distance: surfaces that do not coincide).
  BodyPairing pairing = BodyPairing::vertex;
  bool operator==(const SceneContact&) const = default;
};

/// [[body]]: one body of a scene of several (docs/two-bodies.md), with the keys a scene of one
/// body has for its mesh, material, supports and loads.
/// Whether `name` may name a body: 1 to 64 ASCII letters, digits, '-' or '_' (it names the
/// body's output file, solution.body-NAME.vtu, whatever the locale).
bool valid_body_name(const std::string& name);

struct SceneBody {
  std::string name;  ///< letters, digits, '-' and '_'; unique
  SceneMesh mesh;
  SceneMaterial material;
  BoundarySelector clamped{{}, {}, {}, 1e-8, {}};
  std::vector<SceneDirichlet> dirichlet;
  std::array<SceneScalar, 3> body_force{};
  std::vector<SceneTraction> tractions;
  /// Line of each key of the body's table, by dotted path within it ("mesh.n").
  std::map<std::string, int> lines;
  bool operator==(const SceneBody& o) const {
    return name == o.name && mesh == o.mesh && material == o.material && clamped == o.clamped &&
           dirichlet == o.dirichlet && body_force == o.body_force && tractions == o.tractions;
  }
};

struct SceneSolver {
  std::string linear = "auto";  ///< an engine's name, or "auto": the fastest built (chosen by the command)
  std::string minimizer = "ssn";
  double tolerance = 1e-10;
  int max_iterations = 1000;
  /// The minimizer's parameters by name ([solver.parameters]; checked by the engine).
  std::map<std::string, double> parameters;
  /// "local" (one run of the minimizer) or "global" (GlobalSearch: several starts with every
  /// built minimizer, the lowest certified critical point; a single run when the problem's
  /// uniqueness margin is positive).
  std::string search = "local";
  int max_starts = 64;        ///< global: the most starts (local runs) of the search
  double time_budget = 60.0;  ///< global: seconds after which no new start begins
  int seed = 1;               ///< global: the seed of the random starts
  /// global: the engines that run besides `minimizer`, in order; empty: every built minimizer.
  std::vector<std::string> search_engines;
  /// grid_sequence = "auto": the coarser grids chosen by the route and the mesh
  /// (grid_sequence_levels, hemivem/scene/grid_sequence.hpp).
  static constexpr int grid_sequence_auto = -1;
  /// The coarser grids the full-space route solves on first: a count (0: none) or
  /// grid_sequence_auto.
  int grid_sequence = grid_sequence_auto;
  bool operator==(const SceneSolver&) const = default;
};

/// [adapt]: adaptive refinement (docs/adaptivity.md). Solve, estimate the error
/// (hemivem/estimate/error_estimate.hpp), mark the elements holding the share `fraction` of the
/// estimate's square (Dörfler marking), refine them, solve again from the previous solution,
/// until the relative estimate is at most `target` or a budget is spent.
struct SceneAdapt {
  double target = 0.01;          ///< the relative error estimate to reach, in (0, 1)
  int max_unknowns = 1000000;    ///< no step solves more free degrees of freedom than this
  int max_steps = 30;            ///< solves at most (the first included)
  double fraction = 0.5;         ///< Dörfler's theta, in (0, 1]
  bool operator==(const SceneAdapt&) const = default;
};

/// [path]: a loading path (hemivem/path/path.hpp), the problem solved at the load factors
/// t_1 < ... < t_K, each step a static contact problem started from the one before.
struct ScenePath {
  /// K with t_k = k / K (used when `t` is empty), 1 ... 1000000.
  int steps = 10;
  /// The load factors given one by one: finite, > 0, strictly increasing; empty: `steps`.
  std::vector<double> t;
  /// At most this many steps have their full fields written, evenly spread, the last one
  /// included (is_frame); 1 ... 1000000.
  int frames = 100;
  /// t_1 ... t_K.
  std::vector<double> factors() const;
  /// Whether step k (1-based, of K = factors().size()) is a frame: k == K or
  /// floor(k F / K) != floor((k - 1) F / K), F = frames; every step when F >= K, exactly F
  /// steps otherwise. False for k outside 1 ... K.
  bool is_frame(int step) const;
};
/// Equal factors and frames: `steps` counts only when `t` is empty.
bool operator==(const ScenePath& a, const ScenePath& b);

/// The output names a scene may ask for.
const std::vector<std::string>& scene_output_names();
/// The formats a scene's figures may be written in (output.figure_format): png, pdf, svg.
const std::vector<std::string>& scene_figure_formats();

namespace detail {
struct SceneDocument;  // the parsed TOML a scene was read from (internal)
}

struct Scene {
  int schema_version = scene_schema_version;
  /// Free text recorded in results; a scene file without `title` is named after the file.
  std::string title = "Example 4.1 (Feng, Han, Huang 2021)";
  SceneMesh mesh;
  SceneMaterial material;
  /// Gamma_1 (u = 0): the paper's sides in a scene made in code; a scene read from text holds
  /// only the [clamped] it writes (empty without the table).
  BoundarySelector clamped{{"left", "right"}, {}, {}, 1e-8, {}};
  std::vector<SceneDirichlet> dirichlet;                       ///< other prescribed displacements
  std::array<SceneScalar, 3> body_force{};                     ///< f0 (fz = 0 in 2D)
  std::vector<SceneTraction> tractions{
      SceneTraction{{{"top"}, {}, {}, 1e-8, {}}, {SceneScalar{0.0, {}}, SceneScalar{-8.0, {}}}, std::nullopt}};  ///< Gamma_2
  std::optional<SceneContact> contact = SceneContact{};       ///< Gamma_3 (its first part); none = no contact
  /// [[contact]]: the contact parts after the first (empty without contact or with one part).
  std::vector<SceneContact> more_contact;
  SceneSolver solver;
  /// [adapt]: solve adaptively; none: one solve on the scene's mesh.
  std::optional<SceneAdapt> adapt;
  /// [path]: solve along a loading path; none: one static solve (t = 1).
  std::optional<ScenePath> path;
  std::vector<std::string> outputs = scene_output_names();
  /// output.figure_format: the formats each figure named in `outputs` is written in, each
  /// once (scene_figure_formats; u_nu.png, u_nu.pdf, u_nu.svg).
  std::vector<std::string> figure_formats{"png"};

  /// [[body]]: the bodies of a scene of several (docs/two-bodies.md); empty for one body, whose
  /// mesh, material, supports and loads are the keys above. With bodies those keys are not
  /// used (mesh.dimension is the bodies'), and contact parts name their body.
  std::vector<SceneBody> bodies;

  /// Where the scene came from (a path, or a name such as "<default>").
  std::string source = "<default>";
  /// Line of each key read from the source, by dotted path ("contact.gap",
  /// "loads.traction[0].side"); keys set by apply_override map to 0.
  std::map<std::string, int> lines;
  /// The parsed document the scene was read from, shared and never modified: apply_overrides
  /// edits a copy of it, so that every key it does not touch keeps its line in messages. Null
  /// for a scene made in code; not used once the scene's fields differ from what was read.
  std::shared_ptr<const detail::SceneDocument> document;
  /// What apply_overrides did that changes more than one key (an array of tables replaced or
  /// removed as a whole), one sentence each, in the order given; scene_warnings lists them.
  /// Not problem data: operator== ignores them.
  std::vector<std::string> override_notices;

  /// "source:line" for a key read from the source, else "source".
  std::string where(const std::string& key) const;
  /// Whether output.write names `output` (one of scene_output_names()).
  bool writes(std::string_view output) const;
  /// 2, or 3 for a three-dimensional scene (SceneMesh::dimension).
  int dimension() const noexcept { return mesh.dimension; }
};

/// Equality of the problem data (source and lines are ignored).
bool operator==(const Scene& a, const Scene& b);

/// How the scene's mesh is made, for reports: SceneMesh::description(), or for a scene of several
/// bodies each body's ("upper: voronoi n=[5, 3]; lower: squares n=[7, 3]").
std::string scene_mesh_description(const Scene& scene);

/// The condensed route's memory estimate for the scene's generated mesh, before the mesh is made:
/// estimate_memory (plane) or estimate_memory_3d (solid) of its generator and cells, the estimate
/// the scene's build checks (of its own mesh: a scene of several bodies has one per body). None
/// for a mesh read from a file (known once read).
std::optional<MemoryEstimate> generated_mesh_memory(const Scene& scene);

/// Body b of a scene of several as a scene of one body: its mesh, material, supports and loads,
/// the scene's contact parts on that body (their sides and groups, without the body's name;
/// a part against another body as a part against nothing, with no gap), solver and outputs,
/// and the lines of its keys. InputError for b out of range.
Scene body_scene(const Scene& scene, std::size_t b);

/// Every contact part of the scene in order: *contact, then more_contact (empty without contact).
std::vector<SceneContact> contact_parts(const Scene& scene);
/// Whether `holds` is true of the selector of every support (clamped, then each dirichlet), load
/// (each traction) and contact part (the part's own side, not the side against it), asked in
/// that order until one is false.
bool every_selector(const Scene& scene, const std::function<bool(const BoundarySelector&)>& holds);
/// The key of contact part i in messages, Scene::lines and overrides: "contact" when the scene
/// has one part, "contact[i]" when it has several.
std::string contact_key(const Scene& scene, std::size_t part);
/// The name of contact part i: its name, or by default its key (contact_key: "contact" for a
/// scene of one part, "contact[0]", "contact[1]" ... for several).
std::string contact_part_name(const Scene& scene, std::size_t part);

/// Reads and validates a scene file; relative mesh paths are resolved against its folder.
Scene parse_scene(const std::filesystem::path& path);
/// The same from text; `name` stands for the file in messages, relative mesh paths are
/// resolved against the folder of `name` (the current directory when it has none).
Scene parse_scene_string(std::string_view text, std::string name);
/// Example 4.1 on N = 64 squares: scenes/paper-example-4.1.toml, embedded in the library
/// when it is built.
Scene default_scene();

/// Applies "dotted.key=value" (value in TOML syntax; a bare word is taken as a string), e.g.
/// "contact.gap=0.01", "mesh.generator=voronoi", "solver.minimizer=bundle-dca". The value
/// replaces the key in the scene's parsed document (Scene::document; a scene made or changed
/// in code is written with to_toml first) and the document is read again, so the result is
/// validated as a whole: an error in an overridden key names "--set key" and the nearest
/// valid key, an error in a key of the file names its line. Setting
/// mesh.generator clears mesh.file and vice versa, setting path.t clears path.steps and vice versa; a relative mesh.file is resolved against
/// the current directory. Setting a contact.* key on a scene without contact adds the
/// default contact part (the bottom side, the paper's law). With several contact parts
/// ([[contact]]) a key names its part, "contact[1].gap=0.01"; "contact[0].gap" also names
/// the single [contact] table, and "contact.gap" the single table of a [[contact]] of one.
/// "key[+]={...}" appends one table to an array of tables ("dirichlet[+]={side=\"left\", ux=0}",
/// "contact[+]", "loads.traction[+]", "material.region[+]"; a single [contact] table becomes the
/// first of two). "key=[...]" replaces the whole array and "key=" removes it: both are allowed
/// and recorded in Scene::override_notices (the key, how many tables by how many).
void apply_override(Scene& scene, std::string_view key_eq_value);

/// Applies several overrides at once: every value is put in place first and the scene is
/// validated once, so the order does not matter ("contact.parameters.sigma=0.5" and
/// "contact.law=kinked" in either order). Later overrides of the same key win.
void apply_overrides(Scene& scene, const std::vector<std::string>& key_eq_values);

/// The scene as TOML text: every key written, parse_scene_string(to_toml(s), n) == s.
std::string to_toml(const Scene& scene);

/// Writes to_toml(scene) to `path` atomically (the resolved scene of a run's output folder).
void write_scene(const std::filesystem::path& path, const Scene& scene);

/// A scene made concrete (build_problem<dim>), a plane (dim = 2, BuiltProblem) or a solid
/// (dim = 3, BuiltProblem3D) body. Not movable: problem.elasticity.mesh points at mesh.
template <int dim>
struct BasicBuiltProblem {
  MeshOf<dim> mesh;
  BasicContactProblem<dim> problem;  ///< no contact parts when has_contact is false
  bool has_contact = false;
  std::vector<std::string> warnings;  ///< scene_warnings(scene)
  /// A scene of several bodies: each body's part of `mesh`, in the scene's order; empty for one.
  std::vector<BodyRange> bodies;
  BasicBuiltProblem() = default;
  BasicBuiltProblem(const BasicBuiltProblem&) = delete;
  BasicBuiltProblem& operator=(const BasicBuiltProblem&) = delete;
};
using BuiltProblem = BasicBuiltProblem<2>;
using BuiltProblem3D = BasicBuiltProblem<3>;

/// What a user should know about the problem a scene poses, though it is valid: the
/// overrides that replaced or removed an array of tables (Scene::override_notices), a
/// problem that nothing drives (no load, no prescribed displacement other than zero, no
/// obstacle and no gap that pushes), whose solution is u = 0.
std::vector<std::string> scene_warnings(const Scene& scene);

/// Builds a scene of dimension dim (scene.dimension()): the mesh, the materials by region, the
/// boundary parts its selectors pick, the prescribed displacements ([clamped], [[dirichlet]]:
/// the components given), the loads (body force, tractions and pressures) and the contact parts
/// with their gap or obstacle, laws and constraint (at t = 1). Plane bodies (build_problem,
/// build_problem<2>): a generator of generators.hpp on the rectangle or polygon, or a file
/// (.poly2d via read_poly2d, .msh via read_gmsh), region boxes applied; solids
/// (build_problem<3>): a generator of generators3d.hpp on the box, or a Gmsh file of volumes,
/// with the 3D Lame constants. Errors name the scene key's file:line (a side or group that
/// selects no boundary facet, an unknown group, a region without material); a scene of the
/// other dimension is an InputError at its `mesh` key. `processes` (one row per process, or
/// null): across processes, the mesh generator's work split among them where it splits it (the
/// voronoi generator on a rectangle or a box: make_mesh, make_mesh3d), every process making the
/// whole mesh alike;
/// collective then.
template <int dim = 2>
std::unique_ptr<BasicBuiltProblem<dim>> build_problem(const Scene& scene, const RowDistribution* processes = nullptr);

/// A solid scene on a mesh of one's own instead of the scene's (its mesh keys are not used):
/// the scene's sides are the sides of this mesh's bounding box, its groups this mesh's face
/// groups and its regions this mesh's region ids; the memory the solve needs is checked under
/// the scene's `mesh` key.
std::unique_ptr<BuiltProblem3D> build_problem(const Scene& scene, Mesh3D mesh);

/// The same on a given mesh instead of the scene's (its mesh keys are not used): the scene's
/// region boxes are applied to it when `apply_region_boxes` (a mesh of one's own), and not
/// when its region ids are already the scene's (a mesh refined from the scene's, whose
/// elements inherit their parents' regions).
std::unique_ptr<BuiltProblem> build_problem(const Scene& scene, Mesh mesh, bool apply_region_boxes = true);

/// Whether the scene's data along a path are those at t = 1 scaled: no load, prescribed
/// displacement (of any body, in a scene of several), gap or obstacle value mentions t and the
/// obstacle has no motion. The problem
/// at t is then the one at t = 1 with its load vector and prescribed displacements times t
/// (PathLoading's proportional loading).
bool scene_is_proportional(const Scene& scene);
/// Whether a contact part's gap mentions t or its obstacle moves: the contact boundary's gaps
/// then change along the path (PathLoading::updates_gaps).
bool scene_path_moves_gaps(const Scene& scene);

/// Sets the data of `problem`, built from `scene` (build_problem, make_contact_problem), to
/// their values at the load factor t (the rule at the top of this file): the body force, each
/// traction or pressure, each prescribed displacement (the [clamped] part stays zero), each
/// contact part's gap or obstacle (moved by its motion). The mesh, the materials, the boundary parts, the
/// laws and which components are prescribed are left as they are. A value that is not finite
/// (or a negative gap) is an InputError naming the scene key, the point and t when it is
/// evaluated; InternalError for a t that is not finite or a problem whose parts do not match
/// the scene's. A scene of several bodies: each body's loads and prescribed displacements (its
/// scene of one body's, body_scene) onto that body's tractions and supports in the problem
/// build_problem joined, the contact parts as for one body.
void set_load_factor(const Scene& scene, double t, ContactProblem& problem);
/// The same for a solid's problem (build_problem<3>).
void set_load_factor(const Scene& scene, double t, ContactProblem3D& problem);

/// The contact problem of a scene on a given mesh (the scene's mesh keys are not used): the
/// materials by the mesh's region ids (the scene's region boxes are applied by build_problem
/// only), the boundary parts selected on the mesh's bounding box, loads and contact data (their
/// values at t = 1, set_load_factor), one ContactPart per contact part of the scene, named by
/// contact_part_name; no part when the scene has no contact. An edge
/// that two contact parts select is an error naming both. The result points at `mesh`. Errors
/// as build_problem's.
ContactProblem make_contact_problem(const Scene& scene, const Mesh& mesh);
/// The same for a solid scene on a polyhedral mesh.
ContactProblem3D make_contact_problem(const Scene& scene, const Mesh3D& mesh);

}  // namespace hemivem
