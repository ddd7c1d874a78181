// The global assembly of the elasticity system, written once for plane (dim = 2) and solid
// (dim = 3) bodies: the stiffness and its product with a displacement, the dof map of the
// prescribed displacements, the load vector, the reduced system and its right-hand side, and the
// rows of the reduced system that a range of vertices owns (assemble_rows). Per dimension only the
// element's stiffness (element_stiffness, element_stiffness_3d), a facet's measure and the load
// kernels differ; the load kernels and the projections are each dimension's own file
// (assembly.cpp, assembly3d.cpp).
#include <hemivem/vem/assembly.hpp>
#include <hemivem/vem/assembly3d.hpp>
#include <hemivem/error.hpp>

#include "element_loop.hpp"
#include "load_kernels.hpp"

#include <algorithm>
#include <bit>
#include <cstdint>
#include <cstring>
#include <map>

namespace hemivem {

namespace {

// ---- the kernels of each dimension ----

std::span<const int> cell_vertices(const Mesh& mesh, int e) { return mesh.element(e); }
const std::vector<int>& cell_vertices(const Mesh3D& mesh, int c) { return mesh.cell_vertices(c); }

/// The last cell matrix a thread computed and what it was computed from: the cell's vertices
/// less its first vertex, its faces in its own numbering (3D), its material and stabilization. A
/// cell that is a translate of it (each of these the same bit for bit: the cells of a grid's row)
/// has the same matrix, as deal.II's FEValues reuses the values of a translated cell.
template <class Point>
class TranslatedCell {
 public:
  /// K of the cell `relative` (vertices less the first), `faces`, `lame`, `stabilization`: the
  /// last one where the cell is its translate, computed by `compute(K)` otherwise.
  template <class Compute>
  void stiffness(const std::vector<Point>& relative, const std::vector<std::vector<int>>& faces, const Lame& lame,
                 Stabilization stabilization, Eigen::MatrixXd& K, Compute&& compute) {
    if (valid_ && stabilization == stabilization_ && bits_equal(lame.lambda, lambda_) && bits_equal(lame.mu, mu_) &&
        relative.size() == relative_.size() &&
        std::memcmp(relative.data(), relative_.data(), relative.size() * sizeof(Point)) == 0 && faces == faces_) {
      K = K_;
      return;
    }
    compute(K);
    relative_ = relative;
    faces_ = faces;
    lambda_ = lame.lambda;
    mu_ = lame.mu;
    stabilization_ = stabilization;
    K_ = K;
    valid_ = true;
  }

 private:
  static bool bits_equal(double a, double b) { return std::bit_cast<std::uint64_t>(a) == std::bit_cast<std::uint64_t>(b); }
  std::vector<Point> relative_;
  std::vector<std::vector<int>> faces_;
  double lambda_ = 0.0, mu_ = 0.0;
  Stabilization stabilization_ = Stabilization::two_mu;
  Eigen::MatrixXd K_;
  bool valid_ = false;
};

/// A cell's vertices less its first, into z.
template <class MeshType, class Point>
void relative_vertices(const MeshType& mesh, int c, std::vector<Point>& z) {
  const auto& vertices = cell_vertices(mesh, c);
  const Point origin = mesh.vertex(*vertices.begin());
  z.clear();
  for (int v : vertices) z.push_back(mesh.vertex(v) - origin);
}

/// K_E of cell c, computed from its vertices less its first (a thread's own buffers: called from
/// several threads at once), or the thread's last one where the cell is its translate.
void cell_stiffness(const Mesh& mesh, int e, const Lame& lame, Stabilization stabilization, Eigen::MatrixXd& K) {
  thread_local std::vector<Vec2> poly;
  thread_local TranslatedCell<Vec2> last;
  static const std::vector<std::vector<int>> no_faces;
  relative_vertices(mesh, e, poly);
  last.stiffness(poly, no_faces, lame, stabilization, K,
                 [&](Eigen::MatrixXd& M) { element_stiffness(poly, lame, stabilization, M); });
}
void cell_stiffness(const Mesh3D& mesh, int c, const Lame& lame, Stabilization stabilization, Eigen::MatrixXd& K) {
  thread_local std::vector<Vec3> z;
  thread_local std::vector<std::vector<int>> faces;
  thread_local TranslatedCell<Vec3> last;
  relative_vertices(mesh, c, z);
  mesh.local_faces(c, faces);
  last.stiffness(z, faces, lame, stabilization, K,
                 [&](Eigen::MatrixXd& M) { element_stiffness_3d(z, faces, lame, stabilization, M); });
}

double facet_measure(const Mesh& mesh, int f) { return mesh.edge_length(f); }
double facet_measure(const Mesh3D& mesh, int f) { return mesh.face_area(f); }

template <int dim>
constexpr const char* facet_word() {
  return dim == 2 ? "edge" : "face";
}

// ---- written once ----

/// The cell matrices of the mesh, or of the cells `cells` (increasing) when not null, in cell
/// order (detail::for_each_element_matrix).
template <int dim, class Visit>
void for_each_cell_matrix(const MeshOf<dim>& mesh, const MaterialTable& materials, Stabilization stabilization,
                          const std::vector<int>* cells, Visit&& visit) {
  std::map<int, Lame> lame_by_region;
  for (int region : mesh.regions())
    if (!lame_by_region.count(region)) lame_by_region.emplace(region, materials.lame(region));
  const auto cell = [&](int e) { return cells ? (*cells)[static_cast<std::size_t>(e)] : e; };
  detail::for_each_element_matrix<dim>(
      cells ? static_cast<int>(cells->size()) : mesh.num_cells(),
      [&](int e) -> decltype(auto) { return cell_vertices(mesh, cell(e)); },
      [&](int e, Eigen::MatrixXd& K) {
        cell_stiffness(mesh, cell(e), lame_by_region.at(mesh.region(cell(e))), stabilization, K);
      },
      visit);
}

/// The load vector's terms, each handed to `add` in the order the load vector sums them: the body
/// force's on every cell, or on the cells `cells` (increasing) when not null, then every traction's.
template <int dim>
void load_terms(const MeshOf<dim>& mesh, const VectorFieldOf<dim>& body_force,
                const std::vector<BasicTractionLoad<dim>>& tractions, const std::vector<int>* cells,
                const detail::LoadTerms& add) {
  if (body_force) {
    const int count = cells ? static_cast<int>(cells->size()) : mesh.num_cells();
    for (int e = 0; e < count; ++e)
      detail::cell_body_load(mesh, cells ? (*cells)[static_cast<std::size_t>(e)] : e, body_force, add);
  }
  for (const auto& load : tractions) {
    if (!load.traction && !load.pressure) throw InputError("a traction load has neither a traction nor a pressure");
    for (int id : load.facets) detail::facet_traction_load(mesh, load, id, add);
  }
}

/// The position of each vertex among some of a mesh's vertices (increasing, distinct): -1 for
/// one not among them; the vertex itself when they are every vertex.
class VertexPositions {
 public:
  /// Every vertex of a mesh of `num_vertices`.
  explicit VertexPositions(int num_vertices) : count_(num_vertices), all_(true) {}
  /// The vertices `vertices`; InputError for one out of range or out of order.
  VertexPositions(std::span<const int> vertices, int num_vertices)
      : vertices_(vertices),
        count_(static_cast<int>(vertices.size())),
        all_(vertices.size() == static_cast<std::size_t>(num_vertices)) {
    for (std::size_t k = 0; k < vertices.size(); ++k)
      if (vertices[k] < 0 || vertices[k] >= num_vertices || (k > 0 && vertices[k] <= vertices[k - 1]))
        throw InputError("the vertices of a part of the load or of K u must be vertices of the mesh (0 .. " +
                         std::to_string(num_vertices - 1) + "), increasing: vertex " + std::to_string(vertices[k]) +
                         " at position " + std::to_string(k));
  }
  int size() const noexcept { return count_; }
  int operator()(int v) const {
    if (all_) return v;
    const auto it = std::lower_bound(vertices_.begin(), vertices_.end(), v);
    return it != vertices_.end() && *it == v ? static_cast<int>(it - vertices_.begin()) : -1;
  }

 private:
  std::span<const int> vertices_;
  int count_ = 0;
  bool all_ = false;
};

/// The load vector's entries at the dofs of the vertices `position` counts, in their order.
template <int dim>
Eigen::VectorXd load_at_of(const MeshOf<dim>& mesh, const VectorFieldOf<dim>& body_force,
                           const std::vector<BasicTractionLoad<dim>>& tractions, const VertexPositions& position) {
  Eigen::VectorXd f = Eigen::VectorXd::Zero(dim * static_cast<Eigen::Index>(position.size()));
  load_terms<dim>(mesh, body_force, tractions, nullptr, [&](int d, double value) {
    if (const int p = position(d / dim); p >= 0) f(dim * p + d % dim) += value;
  });
  return f;
}

template <int dim>
SparseMatrix pattern(const MeshOf<dim>& mesh, const std::vector<int>& index, int size) {
  return detail::stiffness_pattern<dim>(mesh.num_vertices(), mesh.num_cells(),
                                        [&](int c) -> decltype(auto) { return cell_vertices(mesh, c); }, index, size);
}

template <int dim>
SparseMatrix stiffness_of(const MeshOf<dim>& mesh, const MaterialTable& materials, Stabilization stabilization) {
  const int n = dim * mesh.num_vertices();
  std::vector<int> index(static_cast<std::size_t>(n));
  for (int d = 0; d < n; ++d) index[static_cast<std::size_t>(d)] = d;
  SparseMatrix K = pattern<dim>(mesh, index, n);
  detail::PatternScatter scatter(K);
  for_each_cell_matrix<dim>(mesh, materials, stabilization, nullptr,
                            [&](const std::vector<int>& dof, const Eigen::Map<const Eigen::MatrixXd>& Ke) {
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

/// sum over the cells holding a dof `touches` accepts of K_E applied to `local_of(dof)`, added by
/// `add(dof, value)`: the part of K u that those cells give.
template <int dim, class Touches, class LocalOf, class Add>
void apply_cells(const MeshOf<dim>& mesh, const MaterialTable& materials, Stabilization stabilization, Touches&& touches,
                 LocalOf&& local_of, Add&& add) {
  Eigen::MatrixXd K;
  Eigen::VectorXd local;
  for (int c = 0; c < mesh.num_cells(); ++c) {
    const auto& verts = cell_vertices(mesh, c);
    if (std::none_of(verts.begin(), verts.end(), [&](int v) {
          for (int d = 0; d < dim; ++d)
            if (touches(dim * v + d)) return true;
          return false;
        }))
      continue;
    cell_stiffness(mesh, c, materials.lame(mesh.region(c)), stabilization, K);
    local.resize(dim * static_cast<Eigen::Index>(verts.size()));
    for (std::size_t k = 0; k < verts.size(); ++k)
      for (int d = 0; d < dim; ++d) local(dim * static_cast<Eigen::Index>(k) + d) = local_of(dim * verts[k] + d);
    const Eigen::VectorXd Kl = K * local;
    for (std::size_t k = 0; k < verts.size(); ++k)
      for (int d = 0; d < dim; ++d) add(dim * verts[k] + d, Kl(dim * static_cast<Eigen::Index>(k) + d));
  }
}

/// (K u) at the dofs of the vertices `position` counts where `rows` (one flag per such dof, in
/// their order) flags them, 0 elsewhere; from the cells holding a flagged dof alone.
template <int dim>
Eigen::VectorXd apply_at_of(const MeshOf<dim>& mesh, const MaterialTable& materials, Stabilization stabilization,
                            const Eigen::VectorXd& u, const VertexPositions& position, const std::vector<char>& rows) {
  const std::size_t dofs = dim * static_cast<std::size_t>(position.size());
  if (u.size() != dim * mesh.num_vertices() || rows.size() != dofs)
    throw InputError("displacement vector has " + std::to_string(u.size()) + " entries and " +
                     std::to_string(rows.size()) + " rows are flagged, expected " +
                     std::to_string(dim * mesh.num_vertices()) + " and " + std::to_string(dofs));
  Eigen::VectorXd Ku = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(dofs));
  // the row of dof d among the flagged ones, or -1
  const auto row = [&](int d) {
    const int p = position(d / dim);
    return p >= 0 && rows[static_cast<std::size_t>(dim * p + d % dim)] != 0 ? dim * p + d % dim : -1;
  };
  apply_cells<dim>(
      mesh, materials, stabilization, [&](int d) { return row(d) >= 0; }, [&](int d) { return u(d); },
      [&](int d, double value) {
        if (const int r = row(d); r >= 0) Ku(r) += value;
      });
  return Ku;
}

}  // namespace

template <int dim>
std::vector<int> BasicDirichletCondition<dim>::held_vertices(const MeshOf<dim>& mesh) const {
  std::vector<int> held;
  for (int id : facets) {
    if (id < 0 || id >= mesh.num_facets())
      throw InputError(std::string("Dirichlet ") + facet_word<dim>() + " id " + std::to_string(id) + " out of range");
    for (int v : mesh.facet_vertices(id)) held.push_back(v);
  }
  for (int v : vertices) {
    if (v < 0 || v >= mesh.num_vertices())
      throw InputError("Dirichlet vertex id " + std::to_string(v) + " out of range (the mesh has " +
                       std::to_string(mesh.num_vertices()) + " vertices)");
    held.push_back(v);
  }
  return held;
}

template struct BasicDirichletCondition<2>;
template struct BasicDirichletCondition<3>;

namespace {

template <int dim>
DofMap dof_map_of(const MeshOf<dim>& mesh, const std::vector<BasicDirichletCondition<dim>>& dirichlet,
                  const std::vector<int>* vertex_order = nullptr) {
  std::vector<std::pair<int, double>> prescribed;
  for (const auto& bc : dirichlet)
    for (int v : bc.held_vertices(mesh)) {
      const PointOf<dim> value = bc.value ? bc.value(mesh.vertex(v)) : PointOf<dim>::Zero();
      for (int c = 0; c < dim; ++c)
        if (bc.fix[static_cast<std::size_t>(c)]) prescribed.emplace_back(dim * v + c, value(c));
    }
  return detail::dof_map_of(dim * mesh.num_vertices(), std::move(prescribed), vertex_order, dim);
}

/// InputError, before any assembly, when nothing has a prescribed displacement, or only facets
/// whose measure is zero. Single vertices hold the body as far as the rigid motions they stop
/// (find_supports decides that).
template <int dim>
void require_held(const BasicElasticityProblem<dim>& problem) {
  double held = 0.0;
  std::size_t held_facets = 0, held_points = 0;
  for (const auto& bc : problem.dirichlet) {
    held_facets += bc.facets.size();
    held_points += bc.vertices.size();
    for (int id : bc.facets)
      if (id >= 0 && id < problem.mesh->num_facets()) held += facet_measure(*problem.mesh, id);
  }
  if (held_facets == 0 && held_points == 0)
    throw InputError(std::string("the body is not held: no boundary ") + facet_word<dim>() +
                     " or vertex has a prescribed displacement (Gamma_1 is empty)");
  if (held_points == 0 && !(held > 0.0))
    throw InputError(std::string("the body is not held: the boundary with prescribed displacement (Gamma_1) has zero ") +
                     (dim == 2 ? "length" : "area"));
}

template <int dim>
LinearSystem assemble_of(const BasicElasticityProblem<dim>& problem) {
  if (!problem.mesh) throw InputError("the elasticity problem has no mesh");
  const MeshOf<dim>& mesh = *problem.mesh;
  require_held(problem);
  LinearSystem sys;
  sys.dofs = make_dof_map(mesh, problem.dirichlet);
  const Eigen::VectorXd f = assemble_load(mesh, problem.body_force, problem.tractions);
  // A = K restricted to the free dofs and b = (f - K u_prescribed) on them, added cell by cell
  // into A's pattern (from the mesh) in the numbering of the free dofs: no global K, no
  // selection products, no triplets
  // the free index of every dof as a table: the whole system's assembly holds vectors of the
  // whole mesh's size anyway, and looks each cell's dofs up
  const std::vector<int> free_index = sys.dofs.free_index_table();
  sys.b.resize(sys.dofs.num_free());
  for (int d = 0; d < sys.dofs.num_dofs(); ++d)
    if (const int fi = free_index[static_cast<std::size_t>(d)]; fi >= 0) sys.b(fi) = f(d);
  {
    SparseMatrix A = pattern<dim>(mesh, free_index, sys.dofs.num_free());
    sys.A.swap(A);  // no copy (SparseMatrix has no move assignment)
  }
  for_each_cell_matrix<dim>(mesh, problem.materials, problem.stabilization, nullptr,
                            detail::FreeSystemAssembler{sys, free_index});
  return sys;
}

template <int dim>
void rhs_of(const BasicElasticityProblem<dim>& problem, const DofMap& dofs, Eigen::Ref<Eigen::VectorXd> b) {
  if (!problem.mesh) throw InputError("the elasticity problem has no mesh");
  const MeshOf<dim>& mesh = *problem.mesh;
  if (dofs.num_dofs() != dim * mesh.num_vertices())
    throw InputError("a dof map of " + std::to_string(dofs.num_dofs()) + " dofs for a mesh of " +
                     std::to_string(dim * mesh.num_vertices()));
  if (b.size() != dofs.num_free())
    throw InternalError("assemble_rhs: a vector of " + std::to_string(b.size()) + " entries for " +
                        std::to_string(dofs.num_free()) + " free dofs");
  // the load's terms added straight into the free dofs' entries, in the load vector's order (a
  // loading path assembles this at every step: no vector of every dof)
  b.setZero();
  load_terms<dim>(mesh, problem.body_force, problem.tractions, nullptr, [&](int d, double value) {
    if (const int fi = dofs.free_index(d); fi >= 0) b(fi) += value;
  });
  const auto lifted = [&](int d) { return dofs.prescribed_value(d) != 0.0; };
  // whether a prescribed value is not zero (a NaN counts), from the bits of the magnitudes in one
  // pass the compiler vectorizes
  std::uint64_t magnitude_bits = 0;
  for (const double value : dofs.prescribed_values())
    magnitude_bits |= std::bit_cast<std::uint64_t>(value) & ~(std::uint64_t{1} << 63);
  if (magnitude_bits != 0)
    apply_cells<dim>(
        mesh, problem.materials, problem.stabilization, lifted, [&](int d) { return dofs.prescribed_value(d); },
        [&](int d, double value) {
          if (const int fi = dofs.free_index(d); fi >= 0) b(fi) -= value;
        });
}

// ---- the rows of a range of vertices ----

/// The cells that hold a vertex v with owns(v), increasing.
template <int dim, class Owns>
std::vector<int> cells_holding(const MeshOf<dim>& mesh, Owns&& owns) {
  std::vector<int> cells;
  for (int c = 0; c < mesh.num_cells(); ++c) {
    const auto& verts = cell_vertices(mesh, c);
    if (std::any_of(verts.begin(), verts.end(), owns)) cells.push_back(c);
  }
  return cells;
}

/// The owned vertices of assemble_rows: order[p0], ..., order[p1 - 1], or p0, ..., p1 - 1
/// without an order.
struct OwnedVertices {
  const std::vector<int>* order = nullptr;
  int p0 = 0, p1 = 0;
  int at(int p) const { return order ? (*order)[static_cast<std::size_t>(p)] : p; }
};

/// rows.first, owned, unknowns and at for the owned vertices and the cells holding them (the
/// free dofs numbered along the owned vertices' order); returns each dof's position in
/// rows.unknowns (-1 for the others).
template <int dim>
std::vector<int> number_unknowns(const MeshOf<dim>& mesh, const OwnedVertices& owned, const std::vector<int>& cells,
                                 SystemRows& rows) {
  const DofMap& dofs = rows.dofs;
  const auto free_of = [&](int v) {  // how many of vertex v's dofs are free
    int n = 0;
    for (int c = 0; c < dim; ++c) n += dofs.is_prescribed(dim * v + c) ? 0 : 1;
    return n;
  };
  if (owned.order) {  // the free dofs of the vertices before the owned ones, then the owned ones'
    rows.first = 0;
    for (int p = 0; p < owned.p0; ++p) rows.first += free_of(owned.at(p));
    rows.owned = 0;
    for (int p = owned.p0; p < owned.p1; ++p) rows.owned += free_of(owned.at(p));
  } else {  // the free dofs before dof d: d less the prescribed ones
    const std::vector<int>& held = dofs.prescribed_dofs();
    const auto free_before = [&](int d) {
      return d - (std::lower_bound(held.begin(), held.end(), d) - held.begin());
    };
    rows.first = free_before(dim * owned.p0);
    rows.owned = free_before(dim * owned.p1) - rows.first;
  }
  std::vector<char> in_part(static_cast<std::size_t>(mesh.num_vertices()), 0);
  for (int p = owned.p0; p < owned.p1; ++p) in_part[static_cast<std::size_t>(owned.at(p))] = 1;
  for (int c : cells)
    for (int v : cell_vertices(mesh, c)) in_part[static_cast<std::size_t>(v)] = 1;
  std::vector<int> index(static_cast<std::size_t>(rows.dofs.num_dofs()), -1);
  for (int d = 0; d < rows.dofs.num_dofs(); ++d)
    if (in_part[static_cast<std::size_t>(d / dim)])
      if (const int f = dofs.free_index(d); f >= 0) {
        index[static_cast<std::size_t>(d)] = static_cast<int>(rows.unknowns.size());
        rows.unknowns.push_back(f);
      }
  if (owned.order) {  // the unknowns in the order of the free dofs, and each dof's position among them
    std::sort(rows.unknowns.begin(), rows.unknowns.end());
    for (int d = 0; d < rows.dofs.num_dofs(); ++d)
      if (index[static_cast<std::size_t>(d)] >= 0)
        index[static_cast<std::size_t>(d)] = static_cast<int>(
            std::lower_bound(rows.unknowns.begin(), rows.unknowns.end(), dofs.free_index(d)) -
            rows.unknowns.begin());
  }
  rows.at = std::lower_bound(rows.unknowns.begin(), rows.unknowns.end(), rows.first) - rows.unknowns.begin();
  return index;
}

template <int dim>
SystemRows rows_of(const BasicElasticityProblem<dim>& problem, const OwnedVertices& owned) {
  if (!problem.mesh) throw InputError("the elasticity problem has no mesh");
  const MeshOf<dim>& mesh = *problem.mesh;
  const int range = owned.order ? static_cast<int>(owned.order->size()) : mesh.num_vertices();
  if (owned.p0 < 0 || owned.p1 < owned.p0 || owned.p1 > range)
    throw InputError("the rows of vertices " + std::to_string(owned.p0) + " to " + std::to_string(owned.p1) +
                     " (excluded): not a range of the mesh's " + std::to_string(mesh.num_vertices()) + " vertices");
  require_held(problem);
  SystemRows rows;
  rows.dofs = dof_map_of<dim>(mesh, problem.dirichlet, owned.order);
  std::vector<char> mine(static_cast<std::size_t>(mesh.num_vertices()), 0);
  for (int p = owned.p0; p < owned.p1; ++p) mine[static_cast<std::size_t>(owned.at(p))] = 1;
  const auto owns = [&](int v) { return mine[static_cast<std::size_t>(v)] != 0; };
  const std::vector<int> cells = cells_holding<dim>(mesh, owns);
  const std::vector<int> index = number_unknowns<dim>(mesh, owned, cells, rows);
  // b's owned rows: the load's terms of those rows, then (with A) the prescribed values lifted
  rows.b = Eigen::VectorXd::Zero(rows.owned);
  load_terms<dim>(mesh, problem.body_force, problem.tractions, &cells, [&](int d, double value) {
    if (const int f = rows.dofs.free_index(d); f >= rows.first && f < rows.first + rows.owned)
      rows.b(f - rows.first) += value;
  });
  {
    SparseMatrix A = detail::stiffness_pattern<dim>(
        mesh.num_vertices(), static_cast<int>(cells.size()),
        [&](int e) -> decltype(auto) { return cell_vertices(mesh, cells[static_cast<std::size_t>(e)]); }, index,
        static_cast<int>(rows.unknowns.size()), [&](int v, int w) { return owns(v) || owns(w); });
    rows.A.swap(A);
  }
  for_each_cell_matrix<dim>(mesh, problem.materials, problem.stabilization, &cells,
                            detail::OwnedRowsAssembler(rows, index));
  return rows;
}

}  // namespace

Eigen::VectorXd assemble_load(const Mesh& mesh, const VectorField& body_force, const std::vector<TractionLoad>& tractions) {
  return load_at_of<2>(mesh, body_force, tractions, VertexPositions(mesh.num_vertices()));
}
Eigen::VectorXd assemble_load(const Mesh3D& mesh, const VectorField3& body_force,
                              const std::vector<TractionLoad3D>& tractions) {
  return load_at_of<3>(mesh, body_force, tractions, VertexPositions(mesh.num_vertices()));
}

Eigen::VectorXd assemble_load_at(const Mesh& mesh, const VectorField& body_force,
                                 const std::vector<TractionLoad>& tractions, std::span<const int> vertices) {
  return load_at_of<2>(mesh, body_force, tractions, VertexPositions(vertices, mesh.num_vertices()));
}
Eigen::VectorXd assemble_load_at(const Mesh3D& mesh, const VectorField3& body_force,
                                 const std::vector<TractionLoad3D>& tractions, std::span<const int> vertices) {
  return load_at_of<3>(mesh, body_force, tractions, VertexPositions(vertices, mesh.num_vertices()));
}

SparseMatrix assemble_stiffness(const Mesh& mesh, const MaterialTable& materials, Stabilization stabilization) {
  return stiffness_of<2>(mesh, materials, stabilization);
}
SparseMatrix assemble_stiffness(const Mesh3D& mesh, const MaterialTable& materials, Stabilization stabilization) {
  return stiffness_of<3>(mesh, materials, stabilization);
}

Eigen::VectorXd apply_stiffness(const Mesh& mesh, const MaterialTable& materials, Stabilization stabilization,
                                const Eigen::VectorXd& u, const std::vector<char>& rows) {
  return apply_at_of<2>(mesh, materials, stabilization, u, VertexPositions(mesh.num_vertices()), rows);
}
Eigen::VectorXd apply_stiffness(const Mesh3D& mesh, const MaterialTable& materials, Stabilization stabilization,
                                const Eigen::VectorXd& u, const std::vector<char>& rows) {
  return apply_at_of<3>(mesh, materials, stabilization, u, VertexPositions(mesh.num_vertices()), rows);
}

Eigen::VectorXd apply_stiffness_at(const Mesh& mesh, const MaterialTable& materials, Stabilization stabilization,
                                   const Eigen::VectorXd& u, std::span<const int> vertices,
                                   const std::vector<char>& rows) {
  return apply_at_of<2>(mesh, materials, stabilization, u, VertexPositions(vertices, mesh.num_vertices()), rows);
}
Eigen::VectorXd apply_stiffness_at(const Mesh3D& mesh, const MaterialTable& materials, Stabilization stabilization,
                                   const Eigen::VectorXd& u, std::span<const int> vertices,
                                   const std::vector<char>& rows) {
  return apply_at_of<3>(mesh, materials, stabilization, u, VertexPositions(vertices, mesh.num_vertices()), rows);
}

DofMap make_dof_map(const Mesh& mesh, const std::vector<DirichletCondition>& dirichlet) {
  return dof_map_of<2>(mesh, dirichlet);
}
DofMap make_dof_map(const Mesh3D& mesh, const std::vector<DirichletCondition3D>& dirichlet) {
  return dof_map_of<3>(mesh, dirichlet);
}
DofMap make_dof_map(const Mesh& mesh, const std::vector<DirichletCondition>& dirichlet,
                    const std::vector<int>& vertex_order) {
  return dof_map_of<2>(mesh, dirichlet, &vertex_order);
}
DofMap make_dof_map(const Mesh3D& mesh, const std::vector<DirichletCondition3D>& dirichlet,
                    const std::vector<int>& vertex_order) {
  return dof_map_of<3>(mesh, dirichlet, &vertex_order);
}

LinearSystem assemble(const ElasticityProblem& problem) { return assemble_of<2>(problem); }
LinearSystem assemble(const ElasticityProblem3D& problem) { return assemble_of<3>(problem); }

SystemRows assemble_rows(const ElasticityProblem& problem, int first_vertex, int end_vertex) {
  return rows_of<2>(problem, {nullptr, first_vertex, end_vertex});
}
SystemRows assemble_rows(const ElasticityProblem3D& problem, int first_vertex, int end_vertex) {
  return rows_of<3>(problem, {nullptr, first_vertex, end_vertex});
}
SystemRows assemble_rows(const ElasticityProblem& problem, const std::vector<int>& vertex_order, int first, int end) {
  return rows_of<2>(problem, {&vertex_order, first, end});
}
SystemRows assemble_rows(const ElasticityProblem3D& problem, const std::vector<int>& vertex_order, int first, int end) {
  return rows_of<3>(problem, {&vertex_order, first, end});
}

Eigen::VectorXd assemble_rhs(const ElasticityProblem& problem, const DofMap& dofs) {
  Eigen::VectorXd b(dofs.num_free());
  rhs_of<2>(problem, dofs, b);
  return b;
}
Eigen::VectorXd assemble_rhs(const ElasticityProblem3D& problem, const DofMap& dofs) {
  Eigen::VectorXd b(dofs.num_free());
  rhs_of<3>(problem, dofs, b);
  return b;
}
void assemble_rhs(const ElasticityProblem& problem, const DofMap& dofs, Eigen::Ref<Eigen::VectorXd> b) {
  rhs_of<2>(problem, dofs, b);
}
void assemble_rhs(const ElasticityProblem3D& problem, const DofMap& dofs, Eigen::Ref<Eigen::VectorXd> b) {
  rhs_of<3>(problem, dofs, b);
}

}  // namespace hemivem
