// pose_share (hemivem/contact/pose_share.hpp): a process's share of the full-space route's posed
// problem from the cells of its own rows, in the steps of BasicContactSolver::prepare() (assembly,
// contact set-up, posing) restricted to those rows. Each step is the one the whole posing takes,
// on less: the same kernels, the same rotation, the same numbering of the coordinates.
#include <hemivem/contact/pose_share.hpp>

#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/every_process.hpp>
#include <hemivem/vem/assembly.hpp>
#include <hemivem/vem/assembly3d.hpp>
#include <hemivem/vem/rigid_motions.hpp>

#include "forces_of_vertices.hpp"

#include <algorithm>
#include <chrono>
#include <climits>
#include <exception>
#include <memory>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

namespace hemivem {

namespace {

double since(std::chrono::steady_clock::time_point t) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t).count();
}

/// InputError for what the share cannot pose: no contact node.
template <int dim>
void require_contact_nodes(const ContactSetUp<dim>& contact) {
  if (contact.boundary.size() == 0)
    throw InputError("the problem has no contact node: there is no contact problem to pose, only its linear system "
                     "(assemble_rows gives a process's rows of it)")
        .mark_about(ProblemPart::contact);
}

/// The free dofs of vertex v, increasing (none where every component is prescribed).
template <int dim>
void push_free_dofs(const DofMap& dofs, int v, std::vector<int>& out) {
  for (int c = 0; c < dim; ++c)
    if (const int f = dofs.free_index(dim * v + c); f >= 0) out.push_back(f);
}

/// Sorts `v` and drops repeats.
void sort_unique(std::vector<int>& v) {
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
}

/// The vertices a process owns, vertex_order[first], ..., vertex_order[end - 1], with the free
/// unknowns numbered along vertex_order (make_dof_map with it); without an order, the vertices
/// first, ..., end - 1 and the free unknowns in dof order.
struct ShareVertices {
  std::vector<int> order;     ///< empty: the mesh's own order
  std::vector<int> position;  ///< each vertex's position in `order` (empty without one)
  int first = 0, end = 0;

  ShareVertices(std::vector<int> vertex_order, int first_position, int end_position)
      : order(std::move(vertex_order)), first(first_position), end(end_position) {
    position.assign(order.size(), -1);
    for (std::size_t p = 0; p < order.size(); ++p)
      if (const auto v = static_cast<std::size_t>(order[p]); v < order.size()) position[v] = static_cast<int>(p);
  }
  int position_of(int v) const { return order.empty() ? v : position[static_cast<std::size_t>(v)]; }
  bool owns(int v) const {
    const int p = position_of(v);
    return p >= first && p < end;
  }
  /// The owned vertices, increasing.
  std::vector<int> owned() const {
    std::vector<int> v(static_cast<std::size_t>(end - first));
    for (int p = first; p < end; ++p)
      v[static_cast<std::size_t>(p - first)] = order.empty() ? p : order[static_cast<std::size_t>(p)];
    std::sort(v.begin(), v.end());
    return v;
  }
  /// The rows of the vertices at the positions [a, b) (assemble_rows).
  template <int dim>
  SystemRows rows(const BasicElasticityProblem<dim>& problem, int a, int b) const {
    return order.empty() ? assemble_rows(problem, a, b) : assemble_rows(problem, order, a, b);
  }
  /// The dof map the rows are numbered by.
  template <int dim>
  DofMap dofs(const BasicElasticityProblem<dim>& problem) const {
    return order.empty() ? make_dof_map(*problem.mesh, problem.dirichlet)
                         : make_dof_map(*problem.mesh, problem.dirichlet, order);
  }
};

/// The rows of the pairs' nodes at the positions `nodes` of the share's order (increasing),
/// assembled in runs of consecutive positions (assemble_rows): their entries outside the owned
/// free unknowns [first, end) added to `entries` once each (an entry of two neighbouring nodes of
/// two runs is the first run's), their unknowns to `unknowns`, their loads to `load` as (free
/// unknown, value).
template <int dim>
void add_node_runs(const BasicElasticityProblem<dim>& problem, const ShareVertices& share, const std::vector<int>& nodes,
                   int first, int end, std::vector<Eigen::Triplet<double, int>>& entries, std::vector<int>& unknowns,
                   std::vector<std::pair<int, double>>& load) {
  const auto owned_free = [&](int f) { return f >= first && f < end; };
  std::vector<std::pair<int, int>> earlier;  // the free unknowns of the runs before, ranges increasing
  const auto assembled = [&](int f) {
    const auto it = std::upper_bound(earlier.begin(), earlier.end(), std::pair<int, int>(f, INT_MAX));
    return it != earlier.begin() && f < std::prev(it)->second;
  };
  for (std::size_t k = 0; k < nodes.size();) {
    std::size_t run = k + 1;  // a run of consecutive nodes, assembled together
    while (run < nodes.size() && nodes[run] == nodes[run - 1] + 1) ++run;
    const SystemRows more = share.rows(problem, nodes[k], nodes[run - 1] + 1);
    for (Eigen::Index c = 0; c < more.A.outerSize(); ++c)
      for (SparseMatrix::InnerIterator e(more.A, c); e; ++e) {
        const int i = more.unknowns[static_cast<std::size_t>(e.row())], j = more.unknowns[static_cast<std::size_t>(c)];
        // a node's row and column (the rotation reads both), but where the owned rows hold them
        if (!owned_free(i) && !owned_free(j) && !assembled(i) && !assembled(j)) entries.emplace_back(i, j, e.value());
      }
    earlier.emplace_back(static_cast<int>(more.first), static_cast<int>(more.first + more.owned));
    unknowns.insert(unknowns.end(), more.unknowns.begin(), more.unknowns.end());
    for (Eigen::Index f = 0; f < more.owned; ++f) load.emplace_back(static_cast<int>(more.first + f), more.b(f));
    k = run;
  }
}

/// What the joining of two bodies (Condensation::rotate_part) reads besides the rows of the
/// owned vertices: the whole row and the load of each pair's node p across from one of them
/// (assembled from p's cells: add_node_runs), and the unknowns across from every node the part
/// holds. `rows` is widened to them (its A, unknowns and at; its owned
/// rows unchanged: they are the owned rows that assemble_rows gave, and the nodes' rows are
/// added where they are not among them); `b` and `b_unknowns` become the load of the owned rows
/// and of those nodes, with their free unknowns.
template <int dim>
void add_pair_rows(const BasicElasticityProblem<dim>& problem, const ContactBoundary& boundary,
                   const ShareVertices& share, SystemRows& rows, Eigen::VectorXd& b, std::vector<int>& b_unknowns) {
  const DofMap& dofs = rows.dofs;
  const auto owns = [&](int v) { return share.owns(v); };
  std::vector<int> across_of(static_cast<std::size_t>(problem.mesh->num_vertices()), -1);  // the node's index
  std::vector<int> nodes;  // the pairs' nodes across from an owned vertex, not owned themselves
  for (int i = 0; i < boundary.size(); ++i) {
    const Across& a = boundary.across[static_cast<std::size_t>(i)];
    if (a.size() == 0) continue;
    const int p = boundary.nodes[static_cast<std::size_t>(i)];
    across_of[static_cast<std::size_t>(p)] = i;
    bool near = false;
    for (int k = 0; k < a.size(); ++k) near = near || owns(a.vertex[static_cast<std::size_t>(k)]);
    if (near && !owns(p)) nodes.push_back(share.position_of(p));
  }
  sort_unique(nodes);  // the nodes' positions in the order
  const auto first = static_cast<int>(rows.first), end = static_cast<int>(rows.first + rows.owned);
  // the part's entries as (row, column, value) of the free unknowns: its own, then the nodes' rows
  std::vector<Eigen::Triplet<double, int>> entries;
  entries.reserve(static_cast<std::size_t>(rows.A.nonZeros()));
  std::vector<int> unknowns = rows.unknowns;
  for (Eigen::Index c = 0; c < rows.A.outerSize(); ++c)
    for (SparseMatrix::InnerIterator e(rows.A, c); e; ++e)
      entries.emplace_back(rows.unknowns[static_cast<std::size_t>(e.row())], rows.unknowns[static_cast<std::size_t>(c)],
                           e.value());
  std::vector<std::pair<int, double>> load;  // of the nodes' rows, then of the owned rows
  add_node_runs<dim>(problem, share, nodes, first, end, entries, unknowns, load);
  // the unknowns across from every node among the part's (the joined columns of its rows)
  const std::size_t held = unknowns.size();
  for (std::size_t k = 0; k < held; ++k) {
    const int v = dofs.free_dof(unknowns[k]) / dim;
    if (const int i = across_of[static_cast<std::size_t>(v)]; i >= 0) {
      const Across& a = boundary.across[static_cast<std::size_t>(i)];
      for (int q = 0; q < a.size(); ++q) push_free_dofs<dim>(dofs, a.vertex[static_cast<std::size_t>(q)], unknowns);
    }
  }
  sort_unique(unknowns);
  const auto local = [&](int f) {
    return static_cast<int>(std::lower_bound(unknowns.begin(), unknowns.end(), f) - unknowns.begin());
  };
  for (auto& e : entries) e = Eigen::Triplet<double, int>(local(e.row()), local(e.col()), e.value());
  const auto n = static_cast<Eigen::Index>(unknowns.size());
  SparseMatrix A(n, n);
  A.setFromTriplets(entries.begin(), entries.end());
  std::vector<Eigen::Triplet<double, int>>().swap(entries);
  rows.A.swap(A);
  rows.unknowns = std::move(unknowns);
  rows.at = std::lower_bound(rows.unknowns.begin(), rows.unknowns.end(), first) - rows.unknowns.begin();
  // the load of the owned rows and of the nodes' rows, in the order of their unknowns
  for (Eigen::Index f = 0; f < rows.owned; ++f) load.emplace_back(first + static_cast<int>(f), rows.b(f));
  std::sort(load.begin(), load.end());
  b.resize(static_cast<Eigen::Index>(load.size()));
  b_unknowns.clear();
  for (std::size_t k = 0; k < load.size(); ++k) {
    b_unknowns.push_back(load[k].first);
    b(static_cast<Eigen::Index>(k)) = load[k].second;
  }
}

/// The columns of the system of `problem` at the free unknowns `unknowns` (every free row, in
/// that order), each from the cells holding its vertex (assemble_rows: an owned column holds
/// every row of those cells), to the bit of the whole assembly's.
template <int dim>
SparseMatrix system_columns(const BasicElasticityProblem<dim>& problem, const ShareVertices& share, const DofMap& dofs,
                            const std::vector<int>& unknowns) {
  std::vector<Eigen::Triplet<double, int>> entries;
  for (std::size_t k = 0; k < unknowns.size(); ++k) {
    const int p = share.position_of(dofs.free_dof(unknowns[k]) / dim);
    const SystemRows rows = share.rows(problem, p, p + 1);
    const auto at = std::lower_bound(rows.unknowns.begin(), rows.unknowns.end(), unknowns[k]) - rows.unknowns.begin();
    for (SparseMatrix::InnerIterator e(rows.A, at); e; ++e)
      entries.emplace_back(rows.unknowns[static_cast<std::size_t>(e.row())], static_cast<int>(k), e.value());
  }
  SparseMatrix columns(dofs.num_free(), static_cast<Eigen::Index>(unknowns.size()));
  columns.setFromTriplets(entries.begin(), entries.end());
  return columns;
}

/// The owned rows of the rotated part `At` of `rows` (local columns: owned rows, then ghosts) and
/// the layout's ghosts: the unknowns outside the owned range that the owned rows read. Made in
/// At's own storage, which it takes (At is left empty): the owned rows of each column (a
/// contiguous run of its sorted rows) are moved down in place, the ghosts' columns below the
/// owned range are then rotated behind the owned columns, and the storage is handed over
/// unshrunk (the rows of ghosts in owned columns, a cost of the share's boundary, stay
/// allocated): the posing's peak is the part once, not the part and a copy of its rows.
SparseMatrix owned_rows(SparseMatrix& At, const SystemRows& rows, RowLayout& layout) {
  if (!At.isCompressed()) throw InternalError("owned_rows reads a compressed rotated part");
  const Eigen::Index at = rows.at, owned = rows.owned;
  const auto run = [&](Eigen::Index c) {  // the owned rows of column c: [begin, end) in At's storage
    const int* first = At.innerIndexPtr() + At.outerIndexPtr()[c];
    const int* last = At.innerIndexPtr() + At.outerIndexPtr()[c + 1];
    const int* b = std::lower_bound(first, last, static_cast<int>(at));
    const int* e = std::lower_bound(b, last, static_cast<int>(at + owned));
    return std::pair<Eigen::Index, Eigen::Index>(b - At.innerIndexPtr(), e - At.innerIndexPtr());
  };
  // the local column of each column of At (its rows are the unknowns, increasing: so are the ghosts)
  std::vector<Eigen::Index> local(static_cast<std::size_t>(At.outerSize()), -1);
  for (Eigen::Index c = 0; c < At.outerSize(); ++c) {
    if (c >= at && c < at + owned) {
      local[static_cast<std::size_t>(c)] = c - at;
    } else if (const auto [b, e] = run(c); e > b) {  // At is symmetric: column c's rows read it
      local[static_cast<std::size_t>(c)] = owned + static_cast<Eigen::Index>(layout.ghosts.size());
      layout.ghosts.push_back(rows.unknowns[static_cast<std::size_t>(c)]);
    }
  }
  const Eigen::Index columns = owned + static_cast<Eigen::Index>(layout.ghosts.size());
  // each kept column's run moved down to `to`: the runs are read before anything is written at
  // or above their start, as `to` never passes the start of the column being read
  int* inner = At.innerIndexPtr();
  double* value = At.valuePtr();
  std::vector<int> starts(static_cast<std::size_t>(columns) + 1, 0);
  Eigen::Index to = 0, below_owned = 0, through_owned = 0;  // the ends of the lower ghosts' and the owned runs
  for (Eigen::Index c = 0; c < At.outerSize(); ++c) {
    if (const Eigen::Index l = local[static_cast<std::size_t>(c)]; l >= 0) {
      const auto [b, e] = run(c);
      for (Eigen::Index k = b; k < e; ++k, ++to) {
        inner[to] = inner[k] - static_cast<int>(at);
        value[to] = value[k];
      }
      starts[static_cast<std::size_t>(l) + 1] = static_cast<int>(e - b);
    }
    if (c + 1 == at) below_owned = to;
    if (c + 1 == at + owned) through_owned = to;
  }
  std::rotate(inner, inner + below_owned, inner + through_owned);
  std::rotate(value, value + below_owned, value + through_owned);
  for (std::size_t l = 0; l < static_cast<std::size_t>(columns); ++l) starts[l + 1] += starts[l];
  SparseMatrix A(owned, columns);
  A.data().swap(At.data());
  A.resizeNonZeros(to);  // within the storage taken: no reallocation
  std::copy(starts.begin(), starts.end(), A.outerIndexPtr());
  SparseMatrix().swap(At);
  return A;
}

/// The owned rows of `count` motions of the vertices of `mesh`, at(k, v) the displacement of
/// vertex v under motion k, in the rotated free unknowns of `posed`. Of two joined bodies, from
/// each motion of every vertex (relative at the pairs: rotated_free).
template <int dim, class MotionAt>
Eigen::MatrixXd owned_motion_rows(int count, const MotionAt& at, const MeshOf<dim>& mesh, const Condensation& posed,
                                  const SystemRows& rows, const std::vector<int>& owned_unknowns) {
  Eigen::MatrixXd N(rows.owned, count);
  if (posed.joins_bodies()) {
    Eigen::VectorXd u(static_cast<Eigen::Index>(dim) * mesh.num_vertices());
    for (int k = 0; k < count; ++k) {
      for (int v = 0; v < mesh.num_vertices(); ++v) u.segment<dim>(dim * v) = at(k, v);
      N.col(k) = posed.rotated_free(u, rows.first, rows.owned);
    }
    return N;
  }
  Eigen::VectorXd motion(rows.owned);
  for (int k = 0; k < count; ++k) {
    for (Eigen::Index i = 0; i < rows.owned; ++i) {
      const int d = rows.dofs.free_dof(rows.first + i);
      motion(i) = at(k, d / dim)(d % dim);
    }
    N.col(k) = posed.rotated_part(motion, owned_unknowns);
  }
  return N;
}

/// The owned rows of the rigid motions of `mesh` (the near-null space of its stiffness).
template <int dim>
Eigen::MatrixXd near_null_rows(const MeshOf<dim>& mesh, const Condensation& posed, const SystemRows& rows,
                               const std::vector<int>& owned_unknowns) {
  const MeshRigidMotions<dim> motions(mesh);
  return owned_motion_rows<dim>(
      motions.count, [&](int k, int v) { return motions.at(k, v); }, mesh, posed, rows, owned_unknowns);
}

/// The owned rows of the rigid motions the supports leave free (a semi-coercive problem's, which
/// its contact alone holds: FullSpaceShare::free_motions), as the whole posing makes them. The
/// mesh holds every vertex (a piece of a generated mesh too, hemivem/mesh/box_piece.hpp), so each
/// process finds the same motions.
template <int dim>
Eigen::MatrixXd free_motion_rows(const BasicElasticityProblem<dim>& problem, const Condensation& posed,
                                 const SystemRows& rows, const std::vector<int>& owned_unknowns) {
  const MeshOf<dim>& mesh = *problem.mesh;
  const BasicRigidMotions<dim> free(mesh, rows.dofs, problem.piece_bodies);
  return owned_motion_rows<dim>(
      free.size(), [&](int k, int v) { return free.displacement(k, v); }, mesh, posed, rows, owned_unknowns);
}

/// A share and what its posing made of the whole contact surface: the dof map, the contact
/// set-up and the posed coordinates (Condensation::CoordinatesOnly), from which the results of
/// the whole problem are made once the processes' values are gathered.
template <int dim>
struct SharePosing {
  PosedShare share;
  /// The system's dof map where the posing's differs (Condensation::dof_map: two joined bodies,
  /// their prescribed values joined); else the posing's alone is held.
  std::optional<DofMap> dofs;
  ContactSetUp<dim> contact;
  std::unique_ptr<Condensation> posed;
  Eigen::VectorXd load;  // the share's rows of the load, unrotated
  double assembly_seconds = 0.0;  // assemble_rows
  double setup_seconds = 0.0;     // contact_set_up
};

/// The contact set-up of `problem` on the dof map of `share` and the seconds it took.
template <int dim>
std::pair<ContactSetUp<dim>, double> surface_of(const BasicContactProblem<dim>& problem, const ShareVertices& share) {
  if (!problem.elasticity.mesh) throw InputError("the elasticity problem has no mesh");
  const auto t = std::chrono::steady_clock::now();
  ContactSetUp<dim> contact = contact_set_up(problem, share.dofs(problem.elasticity));
  return {std::move(contact), since(t)};
}

/// The share of the vertices `vertices` of `problem` whose contact set-up is `surface` (surface_of).
template <int dim>
SharePosing<dim> pose_share_and_surface(const BasicContactProblem<dim>& problem, const ShareVertices& vertices,
                                        std::pair<ContactSetUp<dim>, double> surface) {
  SharePosing<dim> out;
  out.contact = std::move(surface.first);
  out.setup_seconds = surface.second;
  require_contact_nodes(out.contact);
  require_contact_laws(out.contact.parts);
  auto t = std::chrono::steady_clock::now();
  SystemRows rows = vertices.rows(problem.elasticity, vertices.first, vertices.end);
  std::vector<int> owned_unknowns(static_cast<std::size_t>(rows.owned));
  std::iota(owned_unknowns.begin(), owned_unknowns.end(), static_cast<int>(rows.first));
  Eigen::VectorXd b = rows.b;  // the load the share's rows are posed from, of the unknowns b_unknowns
  std::vector<int> b_unknowns = owned_unknowns;
  if (!out.contact.boundary.across.empty())
    add_pair_rows<dim>(problem.elasticity, out.contact.boundary, vertices, rows, b, b_unknowns);
  out.assembly_seconds = since(t);
  out.posed = about(ProblemPart::contact, [&] {
    return std::make_unique<Condensation>(
        rows.dofs, out.contact.boundary, part_conditions(out.contact.parts), Condensation::CoordinatesOnly{},
        [&](const std::vector<int>& unknowns) {
          return system_columns<dim>(problem.elasticity, vertices, rows.dofs, unknowns);
        });
  });
  const Condensation& posed = *out.posed;
  PosedShare& share = out.share;
  share.layout.first = rows.first;
  share.layout.owned = rows.owned;
  share.layout.global = rows.dofs.num_free();
  {
    posed.rotate_part(rows.A, rows.unknowns);
    SparseMatrix A = owned_rows(rows.A, rows, share.layout);
    share.share.matrix.swap(A);  // no copy (SparseMatrix has no move assignment)
  }
  {
    const Eigen::VectorXd bt = posed.rotated_part(b, b_unknowns);
    const auto at = std::lower_bound(b_unknowns.begin(), b_unknowns.end(), static_cast<int>(rows.first)) - b_unknowns.begin();
    share.share.load = bt.segment(at, rows.owned);
  }
  out.load = std::move(rows.b);
  share_coordinates(posed, rows.first, rows.owned, share.share);
  share.near_null_space = near_null_rows<dim>(*problem.elasticity.mesh, posed, rows, owned_unknowns);
  if (!out.contact.held_by_contact.empty())
    share.share.free_motions = free_motion_rows<dim>(problem.elasticity, posed, rows, owned_unknowns);
  share.block_size = node_block_size(rows.dofs, dim);
  if (posed.joins_bodies()) out.dofs = std::move(rows.dofs);
  return out;
}

/// Every process's point, law forces and reactions of its coordinates (share.coordinate_numbers)
/// put into `m` as the whole problem's `count` coordinates, in one gathering (collective): each
/// process sends (number, a, law force, reaction) per coordinate, zeros for forces it lacks.
void gather_coordinates(const RowDistribution& rows, const FullSpaceShare& share, Eigen::Index count,
                        MinimizerResult& m) {
  const auto mine = static_cast<Eigen::Index>(share.coordinate_numbers.size());
  const auto value = [mine](const Eigen::VectorXd& v, Eigen::Index k) { return v.size() == mine ? v(k) : 0.0; };
  Eigen::VectorXd sent(4 * mine);
  for (Eigen::Index k = 0; k < mine; ++k)
    sent.segment<4>(4 * k) << static_cast<double>(share.coordinate_numbers[static_cast<std::size_t>(k)]),
        value(m.a, k), value(m.law_force, k), value(m.reaction, k);
  const Eigen::VectorXd all = rows.all_gather(sent);
  m.a = m.law_force = m.reaction = Eigen::VectorXd::Zero(count);
  for (Eigen::Index at = 0; at + 3 < all.size(); at += 4) {
    const auto k = static_cast<Eigen::Index>(all(at));
    m.a(k) = all(at + 1);
    m.law_force(k) = all(at + 2);
    m.reaction(k) = all(at + 3);
  }
}

/// The balance of forces of the whole problem from each process's balance of its own vertices
/// (force_balance_of_vertices), added up in the order of the processes (collective): the same on
/// each. The contact's resultant and `internal` are `mine`'s, made of the whole contact table.
template <int dim>
BasicForceBalance<PointOf<dim>> added_balance(BasicForceBalance<PointOf<dim>> mine, const RowDistribution& rows) {
  const auto parts = static_cast<Eigen::Index>(1 + mine.reactions.size());
  Eigen::VectorXd sent(dim * parts);
  sent.head<dim>() = mine.applied;
  for (Eigen::Index k = 1; k < parts; ++k) sent.segment<dim>(dim * k) = mine.reactions[static_cast<std::size_t>(k - 1)].force;
  const Eigen::VectorXd sum = rows.sum_in_rank_order(sent);
  mine.applied = sum.head<dim>();
  for (Eigen::Index k = 1; k < parts; ++k) mine.reactions[static_cast<std::size_t>(k - 1)].force = sum.segment<dim>(dim * k);
  return mine;
}

}  // namespace

template <int dim>
PosedShare pose_share(const BasicContactProblem<dim>& problem, int first_vertex, int end_vertex) {
  const ShareVertices vertices({}, first_vertex, end_vertex);
  return std::move(pose_share_and_surface(problem, vertices, surface_of(problem, vertices)).share);
}

template <int dim>
PosedShare pose_share(const BasicContactProblem<dim>& problem, const std::vector<int>& vertex_order, int first,
                      int end) {
  const ShareVertices vertices(vertex_order, first, end);
  return std::move(pose_share_and_surface(problem, vertices, surface_of(problem, vertices)).share);
}

std::pair<int, int> vertex_share(int num_vertices, int rank, int size) {
  if (size < 1 || rank < 0 || rank >= size || num_vertices < 0)
    throw InternalError("vertex_share of rank " + std::to_string(rank) + " of " + std::to_string(size) + " processes");
  const auto [first, end] = even_share(num_vertices, rank, size);
  return {static_cast<int>(first), static_cast<int>(end)};
}

template <int dim>
struct FullSpaceShares<dim>::Impl {
  SharePosing<dim> posing;
  KrylovSolver& krylov;
  std::unique_ptr<RowDistribution> rows;
  KrylovHints hints;
  std::map<std::string, double> timings;
  /// This process's part of the energy the joined system leaves out (Condensation::shift_energy).
  double shift_energy = 0.0;
  std::vector<int> vertices;  ///< this process's (vertex_share), increasing
  /// One body: the values of the prescribed dofs (in dof order) the shares were posed with.
  Eigen::VectorXd posed_prescribed;

  /// This process's rows, first, ..., first + owned - 1.
  std::vector<int> owned_unknowns() const {
    std::vector<int> owned(static_cast<std::size_t>(posing.share.layout.owned));
    std::iota(owned.begin(), owned.end(), static_cast<int>(posing.share.layout.first));
    return owned;
  }

  Impl(SharePosing<dim> p, KrylovSolver& k, std::unique_ptr<RowDistribution> r, double seconds, std::vector<int> v)
      : posing(std::move(p)),
        krylov(k),
        rows(std::move(r)),
        hints(std::move(posing.share.near_null_space), posing.share.block_size),  // held once, by the hints
        timings{{"assembly", posing.assembly_seconds},
                {"setup", posing.setup_seconds},
                {"posing", seconds - posing.assembly_seconds - posing.setup_seconds}},
        vertices(std::move(v)) {
    hints.rows = rows.get();
    shift_energy = posing.posed->shift_energy(posing.load, posing.share.layout.first);
    if (!posing.posed->joins_bodies()) posed_prescribed = posing.posed->dof_map().prescribed_values();
  }

  /// The values of `prescribed` (every dof's) at the prescribed dofs, in dof order.
  Eigen::VectorXd prescribed_values(const Eigen::VectorXd& prescribed) const {
    const DofMap& dofs = posing.posed->dof_map();
    if (prescribed.size() != dofs.num_dofs())
      throw InputError("a load needs " + std::to_string(dofs.num_dofs()) + " prescribed values, got " +
                       std::to_string(prescribed.size()));
    return dofs.prescribed_part(prescribed);
  }
};

namespace {

/// Process world.rank's vertices (vertex_share) along `vertex_order` (empty: the mesh's order).
template <int dim>
ShareVertices process_vertices(const BasicContactProblem<dim>& problem, ProcessWorld world,
                               const std::vector<int>& vertex_order) {
  if (!problem.elasticity.mesh) throw InputError("the elasticity problem has no mesh");
  const auto [first, end] = vertex_share(problem.elasticity.mesh->num_vertices(), world.rank, world.size);
  return ShareVertices(vertex_order, first, end);
}

}  // namespace

template <int dim>
FullSpaceShares<dim>::FullSpaceShares(const BasicContactProblem<dim>& problem, KrylovSolver& krylov, ProcessWorld world,
                                      const RowDistributor& distribute, const std::vector<int>& vertex_order) {
  const auto start = std::chrono::steady_clock::now();
  const ShareVertices vertices = process_vertices(problem, world, vertex_order);
  std::optional<SharePosing<dim>> posing;
  const auto pose = [&] {
    posing.emplace(pose_share_and_surface(problem, vertices, surface_of(problem, vertices)));
    return true;
  };
  if (world.size > 1) {
    // a refusal one process meets (its piece of the mesh its own) is every process's: the others
    // would wait for it in the distribution of the rows
    RowLayout each;  // one row on each process, for the processes' collectives
    each.first = world.rank;
    each.owned = 1;
    each.global = world.size;
    on_every_process(*distribute(each), pose);
  } else {
    pose();
  }
  std::unique_ptr<RowDistribution> rows = distribute(posing->share.layout);
  impl_ = std::make_unique<Impl>(std::move(*posing), krylov, std::move(rows), since(start), vertices.owned());
}

template <int dim>
FullSpaceShares<dim>::~FullSpaceShares() = default;

template <int dim>
Condensation& FullSpaceShares<dim>::posed() noexcept {
  return *impl_->posing.posed;
}

template <int dim>
const Condensation& FullSpaceShares<dim>::posed() const noexcept {
  return *impl_->posing.posed;
}

template <int dim>
const DofMap& FullSpaceShares<dim>::dofs() const noexcept {
  const SharePosing<dim>& p = impl_->posing;
  return p.dofs ? *p.dofs : p.posed->dof_map();
}

template <int dim>
const ContactSetUp<dim>& FullSpaceShares<dim>::contact() const noexcept {
  return impl_->posing.contact;
}

template <int dim>
const RowDistribution& FullSpaceShares<dim>::distribution() const noexcept {
  return *impl_->rows;
}

template <int dim>
const std::map<std::string, double>& FullSpaceShares<dim>::timings() const noexcept {
  return impl_->timings;
}

template <int dim>
void FullSpaceShares<dim>::set_load(const Eigen::VectorXd& b, const Eigen::VectorXd& prescribed) {
  Impl& p = *impl_;
  Condensation& posed = *p.posing.posed;
  const RowLayout& layout = p.posing.share.layout;
  if (posed.joins_bodies()) {
    posed.set_load(b, prescribed);
    p.posing.share.share.load = posed.rotated_load().segment(layout.first, layout.owned);
    p.shift_energy = posed.shift_energy(b.segment(layout.first, layout.owned), layout.first);
    return;
  }
  if (b.size() != layout.global)
    throw InputError("a load needs " + std::to_string(layout.global) + " free values, got " + std::to_string(b.size()));
  Eigen::VectorXd values = p.prescribed_values(prescribed);
  p.posing.share.share.load = posed.rotated_part(b.segment(layout.first, layout.owned), p.owned_unknowns());
  posed.set_prescribed_values(values);
}

template <int dim>
void FullSpaceShares<dim>::scale_load(double t) {
  Impl& p = *impl_;
  Condensation& posed = *p.posing.posed;
  if (posed.joins_bodies()) {
    // the system's dof map, held beside the posing's, keeps the prescribed values posed
    set_load(t * p.rows->all_gather(p.posing.load), t * dofs().prescribed());
    return;
  }
  p.posing.share.share.load = posed.rotated_part(t * p.posing.load, p.owned_unknowns());
  posed.set_prescribed_values(t * p.posed_prescribed);
}

template <int dim>
bool FullSpaceShares<dim>::load_is_zero() const {
  return impl_->rows->max(impl_->posing.share.share.load.isZero(0.0) ? 0.0 : 1.0) == 0.0;
}

template <int dim>
PointOf<dim> FullSpaceShares<dim>::applied(const BasicElasticityProblem<dim>& at) const {
  if (!at.mesh) throw InputError("the elasticity problem has no mesh");
  const std::vector<int>& vertices = impl_->vertices;
  if (!vertices.empty() && at.mesh->num_vertices() <= vertices.back())
    throw InternalError("a load of fewer vertices than the shares'");
  // the load of this process's vertices alone
  const Eigen::VectorXd f = assemble_load_at(*at.mesh, at.body_force, at.tractions, vertices);
  PointOf<dim> mine = PointOf<dim>::Zero();
  for (Eigen::Index d = 0; d < f.size(); ++d) mine(d % dim) += f(d);
  return impl_->rows->sum_in_rank_order(Eigen::VectorXd(mine));
}

template <int dim>
BasicForceBalance<PointOf<dim>> FullSpaceShares<dim>::balance(const BasicElasticityProblem<dim>& at,
                                                              const Eigen::VectorXd& u,
                                                              const std::vector<BasicContactNode<dim>>& contact) const {
  BasicForceBalance<PointOf<dim>> mine;
  std::exception_ptr failure;  // told to every process so that none waits for another
  try {
    mine = detail::force_balance_of_vertices<dim>(at, u, external_contact_resultant(contact), forces_across(contact),
                                                  impl_->vertices);
    for (const auto& n : contact)
      if (n.across.size() > 0) mine.internal = std::max(mine.internal, n.force_on_body().norm());
  } catch (...) {
    failure = std::current_exception();
  }
  if (impl_->rows->max(failure ? 1.0 : 0.0) > 0.0) {
    if (failure) std::rethrow_exception(failure);
    throw InternalError("another process failed to make its part of the balance of forces");
  }
  return added_balance<dim>(std::move(mine), *impl_->rows);
}

template <int dim>
auto FullSpaceShares<dim>::minimize(const ReducedProblem& coordinates, const Eigen::VectorXd& origin,
                                    const MinimizerOptions& options, const Eigen::VectorXd& start,
                                    FullSpaceStatistics* statistics) -> Point {
  Impl& p = *impl_;
  PosedShare& mine = p.posing.share;
  const RowDistribution& rows = *p.rows;
  const bool whole = start.size() == mine.layout.global;
  if (start.size() != 0 && !whole && start.size() != mine.layout.owned)
    throw InternalError("a start of the full-space route needs every rotated unknown or this process's own");
  set_share_coordinates(coordinates, origin, mine.share);
  Eigen::VectorXd x = whole ? Eigen::VectorXd(start.segment(mine.layout.first, mine.layout.owned)) : start;
  Point point;
  point.result = minimize_full_space_in_place(mine.share, p.krylov, p.hints, options, &x, statistics);
  // the residual of the owned rows and the energy of the quadratic part, over the processes
  Eigen::VectorXd with_ghosts(rows.columns());
  with_ghosts.head(mine.layout.owned) = x;
  rows.update_ghosts(with_ghosts);
  const Eigen::VectorXd Ax = mine.share.matrix * with_ghosts;
  point.quadratic = rows.sum(0.5 * x.dot(Ax) - x.dot(mine.share.load) + p.shift_energy);
  point.residual = Ax - mine.share.load;
  point.x = std::move(x);
  gather_coordinates(rows, mine.share, coordinates.size(), point.result);
  return point;
}

template <int dim>
bool FullSpaceShares<dim>::contact_reads_residual() const {
  const Condensation& posed = *impl_->posing.posed;
  for (int i = 0; i < contact().boundary.size(); ++i)
    if (posed.normal_coordinate(i) < 0) return true;
  return false;
}

template <int dim>
BasicContactSolution<dim> solve_full_space_shares(const BasicContactProblem<dim>& problem, KrylovSolver& krylov,
                                                  ProcessWorld world, const RowDistributor& distribute,
                                                  const MinimizerOptions& options, Eigen::VectorXd start_u,
                                                  const std::vector<int>& vertex_order) {
  using Clock = std::chrono::steady_clock;
  const auto start = Clock::now();
  if (std::string why; !options.is_valid(&why)) throw InputError(why, "MinimizerOptions");
  BasicContactSolution<dim> s;
  std::optional<FullSpaceShares<dim>> shares(std::in_place, problem, krylov, world, distribute, vertex_order);
  const Condensation& posed = shares->posed();
  s.unknowns = shares->dofs().num_free();
  for (const auto& part : shares->contact().parts) s.contact_parts.push_back(part.name);
  s.held_by_contact = shares->contact().held_by_contact;
  s.uniqueness_margin = std::numeric_limits<double>::quiet_NaN();
  s.uniqueness_roundoff = std::numeric_limits<double>::quiet_NaN();
  for (const auto& [stage, seconds] : shares->timings()) s.timings[stage] = seconds;
  s.stages = {"assembly", "posing"};

  auto t = Clock::now();
  const RowLayout& layout = shares->distribution().layout();
  const Eigen::VectorXd start_xt =
      start_u.size() > 0 ? posed.rotated_free(start_u, layout.first, layout.owned) : Eigen::VectorXd();
  start_u = Eigen::VectorXd();  // its own rows rotated, the whole start is given back before the solve
  FullSpaceStatistics stats;
  auto point = shares->minimize(posed.reduced(), posed.origin(), options, start_xt, &stats);
  MinimizerResult& m = point.result;
  s.status = m.status;
  s.message = m.message;
  s.certificate = m.certificate;
  s.may_be_nonunique = m.may_be_nonunique;
  s.energy = posed.reduced().law_energy(m.a, point.quadratic);
  s.timings["full_space"] = since(t);
  s.timings["preconditioner"] = stats.preconditioner_seconds;
  s.timings["krylov"] = stats.krylov_seconds;
  s.full_space = stats;
  s.stages.push_back("full_space");
  // the engine's matrix and preconditioner given back before the whole results are made
  t = Clock::now();
  krylov.release();
  const double engine_release = since(t);
  // the results of the whole problem, from what every process gathered: the same on each
  t = Clock::now();
  const RowDistribution& rows = shares->distribution();
  Eigen::VectorXd xt = rows.all_gather(point.x);
  Eigen::VectorXd residual =
      shares->contact_reads_residual() ? rows.all_gather(point.residual) : Eigen::VectorXd();
  point.x = point.residual = Eigen::VectorXd();
  std::exception_ptr failure;  // told to every process so that none waits for another
  try {
    s.u = posed.displacement_of(std::move(xt));  // rotated back in place: two whole vectors at most
    const Eigen::VectorXd unrotated = residual.size() > 0 ? posed.unrotated_free(residual) : Eigen::VectorXd();
    residual = Eigen::VectorXd();
    const ContactBoundary& boundary = shares->contact().boundary;
    for (int i = 0; i < boundary.size(); ++i)
      s.contact.push_back(contact_node(*problem.elasticity.mesh, boundary, posed, shares->dofs(), i, m,
                                       unrotated.size() > 0 ? &unrotated : nullptr));
  } catch (...) {
    failure = std::current_exception();
  }
  s.minimizer = std::move(m);
  if (shares->distribution().max(failure ? 1.0 : 0.0) > 0.0) {
    if (failure) std::rethrow_exception(failure);
    throw InternalError("another process failed to make the results of the whole problem");
  }
  s.forces = shares->balance(problem.elasticity, s.u, s.contact);
  require_finite_solution(s);
  s.timings["post_process"] = since(t);
  t = Clock::now();
  shares.reset();  // the share's rows given back
  s.timings["release"] = engine_release + since(t);
  s.timings["total"] = since(start);
  return s;
}

template PosedShare pose_share<2>(const ContactProblem&, int, int);
template PosedShare pose_share<3>(const BasicContactProblem<3>&, int, int);
template PosedShare pose_share<2>(const ContactProblem&, const std::vector<int>&, int, int);
template PosedShare pose_share<3>(const BasicContactProblem<3>&, const std::vector<int>&, int, int);
template ContactSolution solve_full_space_shares<2>(const ContactProblem&, KrylovSolver&, ProcessWorld,
                                                    const RowDistributor&, const MinimizerOptions&,
                                                    Eigen::VectorXd, const std::vector<int>&);
template class FullSpaceShares<2>;
template class FullSpaceShares<3>;
template BasicContactSolution<3> solve_full_space_shares<3>(const BasicContactProblem<3>&, KrylovSolver&, ProcessWorld,
                                                            const RowDistributor&, const MinimizerOptions&,
                                                            Eigen::VectorXd, const std::vector<int>&);

}  // namespace hemivem
