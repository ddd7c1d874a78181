#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/support/condition.hpp>
#include <hemivem/error.hpp>
#include <hemivem/process_group.hpp>

#include <Eigen/Eigenvalues>

#include <algorithm>
#include <bit>
#include <array>
#include <cmath>
#include <limits>
#include <numeric>
#include <map>

namespace hemivem {

Eigen::VectorXd ContactBoundary::normal_displacements(const Eigen::VectorXd& u) const {
  Eigen::VectorXd a(size());
  for (int i = 0; i < size(); ++i) {
    const auto k = static_cast<std::size_t>(i);
    a(i) = dimension == 3 ? normals3d[k].dot(u.segment<3>(3 * nodes[k])) : normals[k].dot(u.segment<2>(2 * nodes[k]));
  }
  return a;
}

namespace {

/// The contact boundary of `edges` (edge id, part index), each node in the first part one of
/// its edges is in; `gap_of(part, vertex, normal)` gives a node's gap.
ContactBoundary boundary_of(const Mesh& mesh, const std::vector<std::pair<int, int>>& edges, const DofMap& dofs,
                            const std::function<double(int, int, const Vec2&)>& gap_of) {
  ContactBoundary cb;
  struct Sum {
    Vec2 normal = Vec2::Zero();  // sum of m_e
    double weight = 0.0;         // sum of |e|/2
    int part = -1;
    Vec2 lo = Vec2::Zero(), hi = Vec2::Zero();  // the other ends of its edges, less the node
  };
  std::map<int, Sum> acc;  // by vertex
  for (const auto& [id, part] : edges) {
    if (id < 0 || id >= mesh.num_edges()) throw InputError("contact edge id " + std::to_string(id) + " out of range");
    const MeshEdge& e = mesh.edge(id);
    if (!e.on_boundary()) throw InputError("contact edge " + std::to_string(id) + " is not on the boundary");
    cb.edges.push_back(id);
    const Vec2 d = mesh.vertex(e.v1) - mesh.vertex(e.v0);
    const Vec2 m(d.y(), -d.x());  // outward (the edge runs counter-clockwise in its element), length |e|
    for (int v : {e.v0, e.v1}) {
      Sum& sum = acc[v];
      sum.normal += m;
      sum.weight += 0.5 * d.norm();
      sum.part = sum.part < 0 ? part : std::min(sum.part, part);
      const Vec2 other = mesh.vertex(v == e.v0 ? e.v1 : e.v0) - mesh.vertex(v);
      sum.lo = sum.lo.cwiseMin(other);
      sum.hi = sum.hi.cwiseMax(other);
    }
  }
  for (const auto& [v, entry] : acc) {
    const bool fx = dofs.free_index(2 * v) < 0;
    const bool fy = dofs.free_index(2 * v + 1) < 0;
    if (fx && fy) continue;  // on Gamma_1
    if (!(entry.normal.norm() > 0.0))
      throw InputError("contact node " + std::to_string(v) + " has no defined normal (its contact edges cancel)");
    Vec2 normal = entry.normal.normalized();
    int prescribed = -1;
    if (fx != fy) {
      // a roller or symmetry line meeting Gamma_3: allowed where the prescribed component is
      // tangential; a prescribed normal component takes the node out of the contact (the
      // support holds it)
      prescribed = fx ? 0 : 1;
      if (std::abs(normal(1 - prescribed)) <= tangential_tolerance) continue;
      // on a symmetry line: every contact edge on one side of it
      const double extent = (entry.hi - entry.lo).norm();
      const bool one_side = entry.lo(prescribed) >= -1e-12 * extent || entry.hi(prescribed) <= 1e-12 * extent;
      const double tolerance = one_side ? symmetry_tolerance : tangential_tolerance;
      if (!(std::abs(normal(prescribed)) <= tolerance))
        throw InputError("contact node " + std::to_string(v) + " at (" + std::to_string(mesh.vertex(v).x()) + ", " +
                         std::to_string(mesh.vertex(v).y()) + ") has its " + (fx ? "x" : "y") +
                         " displacement prescribed, which is not tangential to its contact normal (" +
                         std::to_string(normal.x()) + ", " + std::to_string(normal.y()) +
                         "): a contact node may have a prescribed component along its tangent or its normal, not "
                         "oblique to them; end the support's or the contact's part before it");
      normal(prescribed) = 0.0;
      normal(1 - prescribed) = normal(1 - prescribed) > 0.0 ? 1.0 : -1.0;
    }
    const double g = gap_of(entry.part, v, normal);
    cb.nodes.push_back(v);
    cb.normals.push_back(normal);
    cb.prescribed_component.push_back(prescribed);
    cb.part.push_back(entry.part);
    cb.weights.conservativeResize(cb.size());
    cb.weights(cb.size() - 1) = entry.weight;
    cb.gaps.conservativeResize(cb.size());
    cb.gaps(cb.size() - 1) = g;
  }
  return cb;
}

/// The gap of node v at x from `obstacle` (along its normal) or from `gap`; `which` names the
/// part in messages ("" for a boundary of one part).
double node_gap(const Vec2& x, int v, const Vec2& normal, const std::function<double(const Vec2&)>& gap,
                const Obstacle* obstacle, const std::string& which) {
  if (obstacle != nullptr) {
    const double g = obstacle->gap(x, normal);
    if (std::isnan(g)) throw InputError("the obstacle gives no gap at contact node " + std::to_string(v) + which);
    return g;
  }
  const double g = gap ? gap(x) : 0.0;
  if (!std::isfinite(g) || g < 0.0)
    throw InputError("gap " + std::to_string(g) + " at contact node " + std::to_string(v) + which +
                     " must be finite and >= 0");
  return g;
}

}  // namespace

ContactBoundary make_contact_boundary(const Mesh& mesh, const std::vector<int>& edges, const DofMap& dofs,
                                      const std::function<double(const Vec2&)>& gap, const Obstacle* obstacle) {
  std::vector<std::pair<int, int>> in_part;
  in_part.reserve(edges.size());
  for (int id : edges) in_part.emplace_back(id, 0);
  return boundary_of(mesh, in_part, dofs, [&](int, int v, const Vec2& normal) {
    return node_gap(mesh.vertex(v), v, normal, gap, obstacle, "");
  });
}

ContactBoundary make_contact_boundary(const Mesh& mesh, const std::vector<ContactPart>& parts, const DofMap& dofs) {
  std::vector<std::pair<int, int>> in_part;
  std::map<int, int> part_of_edge;
  for (std::size_t k = 0; k < parts.size(); ++k)
    for (int id : parts[k].facets) {
      const auto [at, added] = part_of_edge.emplace(id, static_cast<int>(k));
      if (!added && at->second != static_cast<int>(k))
        throw InputError("boundary edge " + std::to_string(id) + " is in the contact parts '" +
                         parts[static_cast<std::size_t>(at->second)].name + "' and '" + parts[k].name +
                         "'; an edge belongs to one part");
      in_part.emplace_back(id, static_cast<int>(k));
    }
  ContactBoundary boundary = boundary_of(mesh, in_part, dofs, [&](int k, int v, const Vec2& normal) {
    const ContactPart& part = parts[static_cast<std::size_t>(k)];
    const std::string which = parts.size() > 1 ? " (contact part '" + part.name + "')" : "";
    return node_gap(mesh.vertex(v), v, normal, part.gap, part.obstacle ? &*part.obstacle : nullptr, which);
  });
  pair_with_other_body<2>(mesh, parts, boundary);
  return boundary;
}


namespace {

/// Throws NumericalError for a failed call of the engine (a call that broke the engine's
/// contract has thrown InternalError already).
void require(const FactorizationResult& r, const SparseFactorization& engine, const std::string& what) {
  if (r.ok()) return;
  throw NumericalError(what + " with the " + engine.name() + " engine failed (" + to_string(r.status) + "): " +
                       r.message);
}

// The entry (i, j) of the compressed column-major A (0 where it is not stored).
double entry(const SparseMatrix& A, int i, int j) {
  const int* begin = A.innerIndexPtr() + A.outerIndexPtr()[j];
  const int* end = A.innerIndexPtr() + A.outerIndexPtr()[j + 1];
  const int* it = std::lower_bound(begin, end, i);
  return it != end && *it == i ? A.valuePtr()[it - A.innerIndexPtr()] : 0.0;
}

// A := Q^T A Q, in place, for Q the identity but for one block per contact node: the node's free
// dofs idx[0..m) with the columns of C (NodeFrame), on A's pattern (the dofs of a node share their
// pattern, as in every assembled stiffness), computed from the symmetric part of A so that the
// result is exactly symmetric: each entry of the lower triangle is computed once and mirrored.
// Exact zeros are dropped unless `keep_pattern`. One sweep over A: the columns in increasing order
// meet the entries above the diagonal of each column in increasing order, so each mirror is found
// by a cursor. An entry between two dofs off the contact is read only by itself and its mirror, so
// it is written at once; the entries of contact nodes read their nodes' blocks, so they are kept
// aside (a cost of the contact surface) and written after the sweep. Entries above the diagonal
// whose mirror A lacks keep their value; the mirrors A lacks are inserted.
template <class Frame>
void rotate_symmetric(SparseMatrix& A, const std::vector<Frame>& frames, bool keep_pattern) {
  A.makeCompressed();
  const int n = static_cast<int>(A.rows());
  // dof -> (its node, its slot in the node's frame); node -1 off the contact
  std::vector<int> node(static_cast<std::size_t>(n), -1), slot(static_cast<std::size_t>(n), -1);
  for (std::size_t k = 0; k < frames.size(); ++k)
    for (int j = 0; j < frames[k].m; ++j) {
      node[static_cast<std::size_t>(frames[k].idx[static_cast<std::size_t>(j)])] = static_cast<int>(k);
      slot[static_cast<std::size_t>(frames[k].idx[static_cast<std::size_t>(j)])] = j;
    }
  const int* outer = A.outerIndexPtr();
  const int* inner = A.innerIndexPtr();
  double* a = A.valuePtr();
  // A(i, j), looked for at position `guess` first (any guess is checked)
  auto entry_near = [&](int i, int j, int guess) {
    return guess >= outer[j] && guess < outer[j + 1] && inner[guess] == i ? a[guess] : entry(A, i, j);
  };
  // the dofs and coefficients of column d of Q
  auto q_column = [&](int d, int* dofs, double* coef) {
    const int k = node[static_cast<std::size_t>(d)];
    if (k < 0) {
      dofs[0] = d, coef[0] = 1.0;
      return 1;
    }
    const Frame& f = frames[static_cast<std::size_t>(k)];
    const int j = slot[static_cast<std::size_t>(d)];
    for (int r = 0; r < f.m; ++r) dofs[r] = f.idx[static_cast<std::size_t>(r)], coef[r] = f.C(r, j);
    return f.m;
  };
  struct Rotated {
    int at, mirror;  // the entry's position in A's storage and its mirror's (-1: none)
    double value;
  };
  std::vector<Rotated> rotated;  // the entries of contact nodes, written after the sweep
  std::vector<int> cursor(outer, outer + n);  // per column: its next entry above the diagonal
  std::vector<Eigen::Triplet<double, int>> missing;  // mirrors of entries whose mirror A lacks
  for (int q = 0; q < n; ++q) {
    for (int k = outer[q]; k < outer[q + 1]; ++k) {
      const int p = inner[k];
      if (p < q) continue;
      int& c = cursor[static_cast<std::size_t>(p)];
      while (c < outer[p + 1] && inner[c] < q) ++c;
      const int mirror = c < outer[p + 1] && inner[c] == q && p != q ? c : -1;
      double v;
      if (node[static_cast<std::size_t>(p)] < 0 && node[static_cast<std::size_t>(q)] < 0) {
        if (p == q) continue;
        v = 0.5 * (a[k] + (mirror >= 0 ? a[mirror] : 0.0));
        a[k] = v;
        if (mirror >= 0) a[mirror] = v;
      } else {
        int jq[3], ip[3];
        double cq[3], cp[3];
        const int nq = q_column(q, jq, cq), np = q_column(p, ip, cp);
        // A(ip[s], jq[t]) is looked for first where the pattern shared by a node's dofs puts it:
        // at p's offset in column q, in column jq[t], moved by s - (p's slot); A(jq[t], ip[s])
        // likewise from q's position in column p
        const int sp = std::max(0, slot[static_cast<std::size_t>(p)]), sq = std::max(0, slot[static_cast<std::size_t>(q)]);
        const int below = k - outer[q];
        const int across = p == q ? below : mirror >= 0 ? mirror - outer[p] : -1;
        v = 0.0;
        for (int s = 0; s < np; ++s)
          for (int t = 0; t < nq; ++t) {
            const int i = ip[s], j = jq[t];
            const double aij = entry_near(i, j, outer[j] + below + s - sp);
            const double aji = across >= 0 ? entry_near(j, i, outer[i] + across + t - sq) : entry(A, j, i);
            v += cp[s] * (0.5 * (aij + aji)) * cq[t];
          }
        rotated.push_back({k, mirror, v});
      }
      if (mirror < 0 && p != q) missing.emplace_back(q, p, v);
    }
  }
  for (const Rotated& r : rotated) {
    a[r.at] = r.value;
    if (r.mirror >= 0) a[r.mirror] = r.value;
  }
  if (!missing.empty()) {
    for (const auto& t : missing) A.coeffRef(t.row(), t.col()) = t.value();
    A.makeCompressed();
  }
  if (!keep_pattern) A.prune(0.0);
}

}  // namespace

namespace {

/// The conditions of the constructor of one part.
std::vector<PartConditions> one_part(std::shared_ptr<const ContactLaw> law, ConstraintKind constraint,
                                     std::shared_ptr<const ContactLaw> friction, bool law_from_surface) {
  if (!law) throw InputError("condensation needs a contact law");
  return {PartConditions{std::move(law), constraint, std::move(friction), law_from_surface}};
}

/// The pairs (p, the point across) of the nodes of `boundary` paired with another body.
std::vector<std::pair<int, Across>> pairs_of(const ContactBoundary& boundary) {
  std::vector<std::pair<int, Across>> pairs;
  for (int i = 0; i < boundary.size(); ++i)
    if (const Across& a = boundary.across[static_cast<std::size_t>(i)]; a.size() > 0)
      pairs.emplace_back(boundary.nodes[static_cast<std::size_t>(i)], a);
  return pairs;
}

}  // namespace

Condensation::Condensation(const LinearSystem& system, const ContactBoundary& boundary,
                           std::unique_ptr<SparseFactorization> factorization, std::shared_ptr<const ContactLaw> law,
                           ConstraintKind constraint, std::shared_ptr<const ContactLaw> friction,
                           bool semi_coercive, bool law_from_surface)
    : Condensation(system, boundary, std::move(factorization),
                   one_part(std::move(law), constraint, std::move(friction), law_from_surface), semi_coercive) {}

Condensation::Condensation(const LinearSystem& system, const ContactBoundary& boundary,
                           std::unique_ptr<SparseFactorization> factorization, const std::vector<PartConditions>& parts,
                           bool semi_coercive)
    : dofs_(system.dofs), factorization_(std::move(factorization)), semi_coercive_(semi_coercive) {
  if (!factorization_) throw InputError("condensation needs a factorization engine");
  SparseMatrix At;
  Eigen::VectorXd bt;
  pose(system, boundary, parts, &At, &bt);
  order_interior();
  measure_interior(At);
  compute_schur_complement(At);
  if (!split_interior_solve(*factorization_)) extract_a21(At);
  condense_load(bt);
  margin_ = std::numeric_limits<double>::quiet_NaN();
  processes_of(*factorization_).run_where_results_are([&] {
    set_uniqueness_margin(reduced_);
    margin_ = reduced_.uniqueness_margin;
  });
}

Condensation::Condensation(const LinearSystem& system, const ContactBoundary& boundary,
                           const std::vector<PartConditions>& parts, PoseOnly)
    : dofs_(system.dofs) {
  pose(system, boundary, parts, &At_, &bt_);
  reduced_.c = Eigen::VectorXd::Zero(reduced_.lo.size());  // its size is the number of coordinates
  margin_ = std::numeric_limits<double>::quiet_NaN();
}

Condensation::Condensation(DofMap dofs, const ContactBoundary& boundary, const std::vector<PartConditions>& parts,
                           CoordinatesOnly, const SystemColumns& columns)
    : dofs_(std::move(dofs)) {
  if (!boundary.across.empty()) {
    joining_ = Joining(dofs_, pairs_of(boundary), boundary.dimension);
    if (joining_.shifts_load()) {
      if (!columns) {
        const int dof = dofs_.free_dof(joining_.shifted_unknowns().front());
        throw InputError("contact node " + std::to_string(dof / boundary.dimension) + " has its " +
                         std::string(1, "xyz"[dof % boundary.dimension]) +
                         " displacement free where a vertex of the other body across from it has it prescribed: its "
                         "joined load takes the system's columns there, which this posing is not given");
      }
      joining_.set_shift_columns(columns(joining_.shifted_unknowns()));
    }
    dofs_.set_prescribed_values(dofs_.prescribed_part(joining_.join_prescribed(dofs_.prescribed())));
  }
  pose_coordinates(dofs_, boundary, parts);
  reduced_.c = Eigen::VectorXd::Zero(reduced_.lo.size());
  margin_ = std::numeric_limits<double>::quiet_NaN();
}

// The pairs of two bodies, the coordinates, their order, the rotated system and the reduced
// problem's laws and bounds (S and c are the condensation's).
void Condensation::pose(const LinearSystem& system, const ContactBoundary& boundary,
                        const std::vector<PartConditions>& parts, SparseMatrix* At, Eigen::VectorXd* bt) {
  // two bodies: the system in the coordinates relative at the pairs
  LinearSystem joined;
  if (!boundary.across.empty()) {
    joining_ = Joining(system.dofs, pairs_of(boundary), boundary.dimension);
    joined = joining_.join(system);
    dofs_ = joined.dofs;
  }
  const LinearSystem& sys = joining_.empty() ? system : joined;
  pose_coordinates(sys.dofs, boundary, parts);
  // the (x, y[, z]) -> (normal, tangential) rotation at the contact nodes: A~ = Q^T A Q, b~ = Q^T b
  if (joining_.empty())
    *At = system.A;
  else
    At->swap(joined.A);  // the joined system is this posing's own
  rotate_symmetric(*At, frames_, keeps_pattern());
  *bt = rotate_load(sys.b);
}

// The coordinates, their order and frames, and the reduced problem's laws, weights, bounds and
// origins, on the free dofs of `dofs`.
void Condensation::pose_coordinates(const DofMap& dofs, const ContactBoundary& boundary,
                                    const std::vector<PartConditions>& parts) {
  if (parts.empty()) throw InputError("condensation needs the conditions of the contact parts");
  nodes_ = boundary.nodes;
  dimension_ = boundary.dimension;
  number_coordinates(boundary, parts);
  order_unknowns(dofs, boundary);
  pose_reduced_problem(boundary, parts);
  origin_ = Eigen::VectorXd::Zero(reduced_.lo.size());
  law_at_start_ = reduced_.law_index;  // each coordinate's law where its gap is finite
  measure_from_surface(boundary);
}

// In 3D the rotation keeps A's pattern, exact zeros included (on cubes up to a third of the
// entries cancel exactly, depending on the mesh size): the 3 dofs of a vertex then share their
// pattern and METIS, which orders 3D bodies, compresses them to one vertex, three times faster
// than on the pruned pattern (docs/performance.md). In 2D, where AMD orders, the pruned copy is
// smaller.
bool Condensation::keeps_pattern() const noexcept { return dimension_ == 3; }

std::vector<Condensation::NodeFrame> Condensation::frames_in(const std::vector<int>& unknowns) const {
  std::vector<NodeFrame> local;
  for (const NodeFrame& f : frames_) {
    NodeFrame g = f;
    int found = 0;
    for (int j = 0; j < f.m; ++j) {
      const auto at = std::lower_bound(unknowns.begin(), unknowns.end(), f.idx[static_cast<std::size_t>(j)]);
      const bool in = at != unknowns.end() && *at == f.idx[static_cast<std::size_t>(j)];
      g.idx[static_cast<std::size_t>(j)] = in ? static_cast<int>(at - unknowns.begin()) : -1;
      found += in ? 1 : 0;
    }
    if (found == f.m)
      local.push_back(g);
    else if (found > 0)
      throw InternalError("a part of the system that holds some of a contact node's unknowns, not all");
  }
  return local;
}

void Condensation::rotate_part(SparseMatrix& A, const std::vector<int>& unknowns) const {
  const auto n = static_cast<Eigen::Index>(unknowns.size());
  if (A.rows() != n || A.cols() != n) throw InternalError("a part of the system of another size than its unknowns");
  if (!joining_.empty()) {
    SparseMatrix joined = joining_.join_part(A, unknowns);
    A.swap(joined);
  }
  rotate_symmetric(A, frames_in(unknowns), keeps_pattern());
}

Eigen::VectorXd Condensation::rotated_part(const Eigen::VectorXd& b, const std::vector<int>& unknowns) const {
  if (b.size() != static_cast<Eigen::Index>(unknowns.size()))
    throw InternalError("a part of a load of another size than its unknowns");
  if (joining_.empty()) return rotate_vector(b, frames_in(unknowns));
  return rotate_vector(joining_.join_part(b, unknowns, dofs_.prescribed()), frames_in(unknowns));
}

void Condensation::set_load(const Eigen::VectorXd& b, const Eigen::VectorXd& prescribed) {
  if (b.size() != dofs_.num_free() || prescribed.size() != dofs_.num_dofs())
    throw InputError("a load needs " + std::to_string(dofs_.num_free()) + " free and " +
                     std::to_string(dofs_.num_dofs()) + " prescribed values, got " + std::to_string(b.size()) +
                     " and " + std::to_string(prescribed.size()));
  if (!joining_.empty()) {
    Eigen::VectorXd joined_prescribed;
    const Eigen::VectorXd joined_b = joining_.join_load(b, prescribed, joined_prescribed);
    dofs_.set_prescribed_values(dofs_.prescribed_part(joined_prescribed));
    take_load(rotate_load(joined_b));
    return;
  }
  dofs_.set_prescribed_values(dofs_.prescribed_part(prescribed));
  take_load(rotate_load(b));
}

void Condensation::set_prescribed_values(const Eigen::VectorXd& values) {
  if (!joining_.empty() || factorization_ || At_.rows() > 0)
    throw InternalError("set_prescribed_values is for a posing of one body's coordinates alone");
  if (values.size() != dofs_.num_dofs() - dofs_.num_free())
    throw InternalError("set_prescribed_values needs " + std::to_string(dofs_.num_dofs() - dofs_.num_free()) +
                        " values, got " + std::to_string(values.size()));
  dofs_.set_prescribed_values(values);
}

// The rotated load: condensed, or kept as the posed system's.
void Condensation::take_load(Eigen::VectorXd bt) {
  if (factorization_)
    condense_load(bt);
  else
    bt_ = std::move(bt);
}

void Condensation::set_gaps(const Eigen::VectorXd& gaps) {
  const bool any_normal =
      std::any_of(normal_coordinate_.begin(), normal_coordinate_.end(), [](int k) { return k >= 0; });
  if (!any_normal) return;
  if (gaps.size() != static_cast<Eigen::Index>(nodes_.size()))
    throw InputError("gaps for " + std::to_string(nodes_.size()) + " contact nodes needed, got " +
                     std::to_string(gaps.size()));
  for (Eigen::Index i = 0; i < gaps.size(); ++i) {
    const int k = normal_coordinate_[static_cast<std::size_t>(i)];
    if (k < 0) continue;
    const double g = gaps(i);
    if (std::isnan(g)) throw InputError("the gap of contact node " + std::to_string(nodes_[static_cast<std::size_t>(i)]) + " is NaN");
    const ConstraintKind constraint = constraint_[static_cast<std::size_t>(i)];
    reduced_.lo(k) = lower_bound(constraint, g);
    reduced_.hi(k) = upper_bound(constraint, g);
    if (!from_surface_[static_cast<std::size_t>(i)]) continue;
    // a node whose ray misses the obstacle never meets it: the zero law; one that meets it
    // again gets its part's law back
    if (std::isfinite(g)) {
      reduced_.law_index(k) = law_at_start_(k);
    } else {
      if (!zero_) zero_ = zero_law();
      const auto at = std::find(reduced_.laws.begin(), reduced_.laws.end(), zero_);
      if (at == reduced_.laws.end()) reduced_.laws.push_back(zero_);
      reduced_.law_index(k) = static_cast<int>(std::find(reduced_.laws.begin(), reduced_.laws.end(), zero_) - reduced_.laws.begin());
    }
    origin_(k) = std::isfinite(g) ? g : 0.0;
    if (std::isfinite(g)) {
      reduced_.lo(k) -= g;
      reduced_.hi(k) -= g;
    }
  }
  const bool shifted = std::any_of(from_surface_.begin(), from_surface_.end(), [](char f) { return f != 0; });
  if (!factorization_) return;  // posed without condensation: no c to shift
  processes_of(*factorization_).run_where_results_are([&] {
    reduced_.c = raw_c_;
    if (shifted) reduced_.c -= reduced_.S * origin_;
  });
}

// Each node's conditions, and its coordinates: every normal unknown (node order), then every
// tangential one.
void Condensation::number_coordinates(const ContactBoundary& boundary, const std::vector<PartConditions>& parts) {
  const auto n1 = static_cast<std::size_t>(boundary.size());
  normal_coordinate_.assign(n1, -1);
  tangential_coordinate_.assign(n1, -1);
  second_tangential_coordinate_.assign(n1, -1);
  constraint_.assign(n1, ConstraintKind::none);
  from_surface_.assign(n1, 0);
  auto conditions = [&](std::size_t i) -> const PartConditions& {
    if (parts.size() == 1) return parts.front();
    const int k = boundary.part_of(static_cast<int>(i));
    if (k < 0 || k >= static_cast<int>(parts.size()))
      throw InputError("contact node " + std::to_string(boundary.nodes[i]) + " is in contact part " +
                       std::to_string(k) + ", but " + std::to_string(parts.size()) + " parts are given");
    return parts[static_cast<std::size_t>(k)];
  };
  int next = 0;
  for (std::size_t i = 0; i < n1; ++i) {
    const PartConditions& c = conditions(i);
    constraint_[i] = c.constraint;
    const bool bilateral = c.constraint == ConstraintKind::bilateral;
    from_surface_[i] = c.law_from_surface && !bilateral;
    if (!bilateral) {
      if (!c.law) throw InputError("condensation needs a contact law");
      normal_coordinate_[i] = next++;
    }
  }
  for (std::size_t i = 0; i < n1; ++i) {
    const PartConditions& c = conditions(i);
    if (!c.friction && c.constraint != ConstraintKind::bilateral) continue;
    // a tangential displacement that is prescribed (a roller, a symmetry line or plane meeting
    // the contact) is no unknown: its tangential reaction is the support's. A solid's node with
    // both tangentials free has two, the group of the friction law of their norm.
    int free_tangentials = 0;
    if (boundary.dimension == 3) {
      const int mask = boundary.prescribed_mask.empty() ? 0 : boundary.prescribed_mask[i];
      free_tangentials = 2 - std::popcount(static_cast<unsigned>(mask));
    } else {
      free_tangentials = !boundary.prescribed_component.empty() && boundary.prescribed_component[i] >= 0 ? 0 : 1;
    }
    if (free_tangentials >= 1) tangential_coordinate_[i] = next++;
    if (free_tangentials == 2) second_tangential_coordinate_[i] = next++;
  }
}

namespace {

/// The frame of a contact node with outward unit normal `nu` (d components; zero on the
/// prescribed ones) whose free components are those with free[c] >= 0: an orthonormal basis of
/// their span, the normal first. In 2D with both components free the tangent is
/// tau = (-nu_y, nu_x); with two free components in 3D, the normal turned by a right angle in their
/// plane; with three, t1 = e x nu normalised for the axis e least aligned with nu, t2 = nu x t1.
template <class Frame>
Frame node_frame(int d, const Vec3& nu, const std::array<int, 3>& free) {
  Frame f;
  std::array<int, 3> comp{};
  for (int c = 0; c < d; ++c)
    if (free[static_cast<std::size_t>(c)] >= 0) {
      comp[static_cast<std::size_t>(f.m)] = c;
      f.idx[static_cast<std::size_t>(f.m++)] = free[static_cast<std::size_t>(c)];
    }
  Eigen::Matrix3d B = Eigen::Matrix3d::Zero();  // columns: the slots' directions in all components
  B.col(0) = nu;
  if (f.m == 2) {
    const int a = comp[0], b = comp[1];
    B(a, 1) = -nu(b);
    B(b, 1) = nu(a);
  } else if (f.m == 3) {
    const std::array<Vec3, 2> t = tangent_frame(nu);
    B.col(1) = t[0];
    B.col(2) = t[1];
  }
  f.full = B;
  for (int r = 0; r < f.m; ++r)
    for (int j = 0; j < f.m; ++j) f.C(r, j) = B(comp[static_cast<std::size_t>(r)], j);
  return f;
}

}  // namespace

void Condensation::order_unknowns(const DofMap& dofs, const ContactBoundary& boundary) {
  const int n1 = boundary.size();
  const int d = boundary.dimension;
  for (int i = 0; i < n1; ++i) {
    const auto k = static_cast<std::size_t>(i);
    const int v = boundary.nodes[k];
    std::array<int, 3> free{-1, -1, -1};
    for (int c = 0; c < d; ++c) free[static_cast<std::size_t>(c)] = dofs.free_index(d * v + c);
    Vec3 nu = Vec3::Zero();
    if (d == 3) {
      nu = boundary.normals3d[k];
    } else {
      nu.head<2>() = boundary.normals[k];
    }
    const int prescribed = d == 2 && !boundary.prescribed_component.empty() ? boundary.prescribed_component[k] : -1;
    const int mask = d == 3 && !boundary.prescribed_mask.empty() ? boundary.prescribed_mask[k] : 0;
    if (prescribed >= 0 || mask != 0) {
      // free components along the normal and the tangentials not prescribed
      if (prescribed >= 0) free[static_cast<std::size_t>(prescribed)] = -1;
      for (int c = 0; c < 3; ++c)
        if (mask & (1 << c)) free[static_cast<std::size_t>(c)] = -1;
    }
    NodeFrame frame = node_frame<NodeFrame>(d, nu, free);
    const int expected = d - (prescribed >= 0 ? 1 : 0) - std::popcount(static_cast<unsigned>(mask));
    if (frame.m == 0 || frame.m != expected) throw InputError("contact node " + std::to_string(v) + " is not free");
    frames_.push_back(frame);
    block1_.push_back(frame.idx[0]);
  }
  // the tangential displacements that are unknowns follow the normal ones; the reduced
  // coordinates are the normal ones that are unknowns, then those
  coordinate1_.assign(static_cast<std::size_t>(std::count_if(normal_coordinate_.begin(), normal_coordinate_.end(),
                                                             [](int k) { return k >= 0; }) +
                                               std::count_if(tangential_coordinate_.begin(), tangential_coordinate_.end(),
                                                             [](int k) { return k >= 0; }) +
                                               std::count_if(second_tangential_coordinate_.begin(),
                                                             second_tangential_coordinate_.end(), [](int k) { return k >= 0; })),
                      -1);
  for (int i = 0; i < n1; ++i) {
    if (const int k = normal_coordinate(i); k >= 0) coordinate1_[static_cast<std::size_t>(k)] = i;
    if (const int k = tangential_coordinate(i); k >= 0) {
      coordinate1_[static_cast<std::size_t>(k)] = static_cast<int>(block1_.size());
      block1_.push_back(frames_[static_cast<std::size_t>(i)].idx[1]);
    }
    if (const int k = second_tangential_coordinate(i); k >= 0) {
      coordinate1_[static_cast<std::size_t>(k)] = static_cast<int>(block1_.size());
      block1_.push_back(frames_[static_cast<std::size_t>(i)].idx[2]);
    }
  }
}

// Block 2, the interior the condensation factorizes: every free unknown not in block 1.
void Condensation::order_interior() {
  const int n = dofs_.num_free();
  std::vector<char> in1(static_cast<std::size_t>(n), 0);
  for (int k : block1_) in1[static_cast<std::size_t>(k)] = 1;
  block2_.reserve(static_cast<std::size_t>(n) - block1_.size());
  for (int k = 0; k < n; ++k)
    if (!in1[static_cast<std::size_t>(k)]) block2_.push_back(k);
}

Eigen::VectorXd Condensation::rotate_vector(const Eigen::VectorXd& b, const std::vector<NodeFrame>& frames) {
  Eigen::VectorXd bt = b;
  for (const NodeFrame& f : frames)
    for (int j = 0; j < f.m; ++j) {
      double v = 0.0;
      for (int r = 0; r < f.m; ++r) v += f.C(r, j) * b(f.idx[static_cast<std::size_t>(r)]);
      bt(f.idx[static_cast<std::size_t>(j)]) = v;
    }
  return bt;
}

Eigen::VectorXd Condensation::rotate_load(const Eigen::VectorXd& b) const { return rotate_vector(b, frames_); }

void Condensation::measure_interior(const SparseMatrix& At) {
  std::vector<char> in1(static_cast<std::size_t>(At.rows()), 0);
  for (int k : block1_) in1[static_cast<std::size_t>(k)] = 1;
  for (int j : block2_) {
    double sum = 0.0;
    for (SparseMatrix::InnerIterator it(At, j); it; ++it)
      if (!in1[static_cast<std::size_t>(it.row())]) sum += std::abs(it.value());
    a22_norm1_ = std::max(a22_norm1_, sum);
  }
}

void Condensation::pose_reduced_problem(const ContactBoundary& boundary, const std::vector<PartConditions>& parts) {
  const auto nc = static_cast<Eigen::Index>(coordinate1_.size());
  reduced_.laws.clear();
  reduced_.law_index.resize(nc);
  reduced_.lo.resize(nc);
  reduced_.hi.resize(nc);
  reduced_.w.resize(nc);
  auto number_of = [this](const std::shared_ptr<const ContactLaw>& law) {
    for (std::size_t k = 0; k < reduced_.laws.size(); ++k)
      if (reduced_.laws[k] == law) return static_cast<int>(k);
    reduced_.laws.push_back(law);
    return static_cast<int>(reduced_.laws.size()) - 1;
  };
  auto conditions = [&](int i) -> const PartConditions& {
    return parts.size() == 1 ? parts.front() : parts[static_cast<std::size_t>(boundary.part_of(i))];
  };
  // the normals, with their part's law and the bounds of its constraint
  for (int i = 0; i < boundary.size(); ++i) {
    const int k = normal_coordinate(i);
    if (k < 0) continue;
    reduced_.law_index(k) = number_of(conditions(i).law);
    reduced_.lo(k) = lower_bound(constraint_[static_cast<std::size_t>(i)], boundary.gaps(i));
    reduced_.hi(k) = upper_bound(constraint_[static_cast<std::size_t>(i)], boundary.gaps(i));
    reduced_.w(k) = boundary.weights(i);
  }
  // the tangentials, free, with their part's friction law (j = 0 for a bilateral part without
  // one); a solid's two tangentials form a group, the law acting on their norm
  reduced_.groups.clear();
  for (int i = 0; i < boundary.size(); ++i) {
    const std::shared_ptr<const ContactLaw>& friction = conditions(i).friction;
    for (const int k : {tangential_coordinate(i), second_tangential_coordinate(i)}) {
      if (k < 0) continue;
      if (!friction && !zero_) zero_ = zero_law();
      reduced_.law_index(k) = number_of(friction ? friction : zero_);
      reduced_.lo(k) = -std::numeric_limits<double>::infinity();
      reduced_.hi(k) = std::numeric_limits<double>::infinity();
      reduced_.w(k) = boundary.weights(i);
    }
    if (const int k2 = second_tangential_coordinate(i); k2 >= 0) reduced_.groups.push_back({tangential_coordinate(i), k2});
  }
}

// The normal unknowns of the nodes whose law acts from the surface become the distances to it,
// a_i - g_i: the bounds shift by -g_i; a node that never meets the surface (g_i infinite) gets
// the zero law.
void Condensation::measure_from_surface(const ContactBoundary& boundary) {
  int none = -1;
  for (int i = 0; i < boundary.size(); ++i) {
    const int k = normal_coordinate(i);
    if (k < 0 || !from_surface_[static_cast<std::size_t>(i)]) continue;
    const double g = boundary.gaps(i);
    if (std::isfinite(g)) {
      origin_(k) = g;
      reduced_.lo(k) -= g;
      reduced_.hi(k) -= g;
    } else {
      if (none < 0) {
        if (!zero_) zero_ = zero_law();
        const auto at = std::find(reduced_.laws.begin(), reduced_.laws.end(), zero_);
        none = static_cast<int>(at - reduced_.laws.begin());
        if (at == reduced_.laws.end()) reduced_.laws.push_back(zero_);
      }
      reduced_.law_index(k) = none;
    }
  }
}

void Condensation::compute_schur_complement(const SparseMatrix& At) {
  Eigen::MatrixXd S1;
  if (semi_coercive_) {
    // S is singular: condense A + rho E11 (positive definite), then S = (S + rho I) - rho I
    SparseMatrix shifted = At;
    double rho = 0.0;
    for (int k : block1_) rho = std::max(rho, shifted.coeff(k, k));
    if (!(rho > 0.0)) rho = 1.0;
    for (int k : block1_) shifted.coeffRef(k, k) += rho;
    require(factorization_->schur_complement(shifted, block1_, &S1), *factorization_, "static condensation");
    processes_of(*factorization_).run_where_results_are([&] {
      if (S1.size() > 0) S1.diagonal().array() -= rho;
    });
  } else {
    require(factorization_->schur_complement(At, block1_, &S1), *factorization_, "static condensation");
  }
  // the reduced coordinates among block 1 (all of it but the normals of bilateral nodes)
  if (S1.size() > 0) {
    const auto nc = static_cast<Eigen::Index>(coordinate1_.size());
    Eigen::MatrixXd S(nc, nc);
    for (Eigen::Index q = 0; q < nc; ++q)
      for (Eigen::Index p = 0; p < nc; ++p)
        S(p, q) = S1(coordinate1_[static_cast<std::size_t>(p)], coordinate1_[static_cast<std::size_t>(q)]);
    reduced_.S = 0.5 * (S + S.transpose());
  } else {
    reduced_.S = std::move(S1);
  }
}

// c = b1 - A12 A22^{-1} b2 (where the results are held), shifted by -S origin with
// law_from_surface.
void Condensation::condense_load(const Eigen::VectorXd& bt) {
  Eigen::VectorXd b1(static_cast<Eigen::Index>(block1_.size()));
  for (std::size_t i = 0; i < block1_.size(); ++i) b1(static_cast<Eigen::Index>(i)) = bt(block1_[i]);
  b2_.resize(static_cast<Eigen::Index>(block2_.size()));
  for (std::size_t i = 0; i < block2_.size(); ++i) b2_(static_cast<Eigen::Index>(i)) = bt(block2_[i]);
  SplitInteriorSolve* split = split_interior_solve(*factorization_);
  Eigen::MatrixXd y;
  if (split) {
    // c = b1 - A12 A22^{-1} b2 in one forward substitution; back_substitute() needs one backward
    require(split->condense_rhs(b1, b2_, &raw_c_), *factorization_, "interior solve");
  } else {
    require(factorization_->solve_interior(b2_, &y), *factorization_, "interior solve");
  }
  processes_of(*factorization_).run_where_results_are([&] {
    if (!split) raw_c_ = b1 - A21_.transpose() * y.col(0);
    if (static_cast<std::size_t>(raw_c_.size()) != coordinate1_.size()) {
      Eigen::VectorXd c(static_cast<Eigen::Index>(coordinate1_.size()));
      for (std::size_t k = 0; k < coordinate1_.size(); ++k) c(static_cast<Eigen::Index>(k)) = raw_c_(coordinate1_[k]);
      raw_c_ = std::move(c);
    }
    reduced_.c = raw_c_;
    if (std::any_of(from_surface_.begin(), from_surface_.end(), [](char f) { return f != 0; }))
      reduced_.c -= reduced_.S * origin_;
  });
}

void Condensation::widen_uniqueness_roundoff(double kappa) {
  hemivem::widen_uniqueness_roundoff(reduced_, kappa);
  margin_ = reduced_.uniqueness_margin;
}

void Condensation::extract_a21(const SparseMatrix& At) {
  // A21 = At(block2, block1) (block2 is increasing, so each column's rows stay sorted)
  const auto n = static_cast<std::size_t>(At.rows());
  const auto n1 = static_cast<Eigen::Index>(block1_.size());
  std::vector<int> position2(n, -1);
  for (std::size_t i = 0; i < block2_.size(); ++i) position2[static_cast<std::size_t>(block2_[i])] = static_cast<int>(i);
  std::vector<int> a21_outer{0}, a21_inner;
  std::vector<double> a21_values;
  for (int j : block1_) {
    for (SparseMatrix::InnerIterator it(At, j); it; ++it) {
      const int r = position2[static_cast<std::size_t>(it.row())];
      if (r < 0) continue;
      a21_inner.push_back(r);
      a21_values.push_back(it.value());
    }
    a21_outer.push_back(static_cast<int>(a21_inner.size()));
  }
  A21_ = Eigen::Map<const SparseMatrix>(static_cast<Eigen::Index>(block2_.size()), n1,
                                        static_cast<Eigen::Index>(a21_inner.size()), a21_outer.data(),
                                        a21_inner.data(), a21_values.data());
}

double Condensation::condition_estimate() const {
  if (!factorization_) throw InternalError("a posed problem without condensation has no condition estimate");
  auto apply = [this](const Eigen::MatrixXd& x) {
    Eigen::MatrixXd y;
    if (!factorization_->solve_interior(x, &y).ok() || y.cols() != x.cols()) return Eigen::MatrixXd();
    return y;
  };
  return a22_norm1_ * estimate_norm1_symmetric_blocks(static_cast<int>(block2_.size()), apply);
}

const SparseFactorization& Condensation::factorization() const {
  if (!factorization_) throw InternalError("a posed problem without condensation has no factorization");
  return *factorization_;
}

std::vector<int> Condensation::tied_rows() const {
  std::vector<char> coordinate(block1_.size(), 0);
  for (int q : coordinate1_) coordinate[static_cast<std::size_t>(q)] = 1;
  std::vector<int> rows;
  for (std::size_t q = 0; q < block1_.size(); ++q)
    if (!coordinate[q]) rows.push_back(block1_[q]);
  return rows;
}

Eigen::VectorXd Condensation::displacement_of(Eigen::VectorXd xt) const {
  if (xt.size() != dofs_.num_free())
    throw InternalError("displacement_of needs " + std::to_string(dofs_.num_free()) + " unknowns, got " +
                        std::to_string(xt.size()));
  return from_rotated(std::move(xt));
}

Eigen::VectorXd Condensation::rotated_free(const Eigen::VectorXd& u) const { return rotated_free(u, 0, dofs_.num_free()); }

Eigen::VectorXd Condensation::rotated_free(const Eigen::VectorXd& u, Eigen::Index first, Eigen::Index count) const {
  if (u.size() != dofs_.num_dofs())
    throw InputError("a start needs " + std::to_string(dofs_.num_dofs()) + " nodal displacements, got " +
                     std::to_string(u.size()));
  if (first < 0 || count < 0 || first + count > dofs_.num_free())
    throw InternalError("rotated_free of the unknowns " + std::to_string(first) + " to " +
                        std::to_string(first + count - 1) + " of " + std::to_string(dofs_.num_free()));
  const Eigen::VectorXd relative = joining_.empty() ? Eigen::VectorXd() : joining_.relative(u);
  const Eigen::VectorXd& v = joining_.empty() ? u : relative;
  std::vector<int> unknowns(static_cast<std::size_t>(count));
  std::iota(unknowns.begin(), unknowns.end(), static_cast<int>(first));
  Eigen::VectorXd free(count);
  for (Eigen::Index k = 0; k < count; ++k) free(k) = v(dofs_.free_dof(first + k));
  return rotate_vector(free, frames_in(unknowns));  // the frames are orthogonal: Q^T u, as for a load
}

Eigen::VectorXd Condensation::back_substitute(const Eigen::VectorXd& a) const {
  if (!factorization_) throw InternalError("a posed problem without condensation has no back-substitution");
  const ProcessGroup& processes = processes_of(*factorization_);
  const SplitInteriorSolve* split = split_interior_solve(*factorization_);
  Eigen::VectorXd x1;     // block 1's values
  Eigen::MatrixXd rhs;    // the interior right-hand side b2 - A21 x1 (without a split solve)
  processes.run_where_results_are([&] {
    x1 = block1_values(a);
    if (!split) rhs = b2_ - A21_ * x1;
  });
  Eigen::VectorXd u2;
  Eigen::MatrixXd x2;
  if (split)
    require(split->expand(x1, &u2), *factorization_, "back-substitution");
  else
    require(factorization_->solve_interior(rhs, &x2), *factorization_, "back-substitution");
  Eigen::VectorXd u;
  processes.run_where_results_are([&] { u = displacement(x1, split ? u2 : Eigen::VectorXd(x2.col(0))); });
  return u;
}

Eigen::VectorXd Condensation::reduced_point(const Eigen::VectorXd& u) const {
  if (u.size() != dofs_.num_dofs())
    throw InputError("a start needs " + std::to_string(dofs_.num_dofs()) + " nodal displacements, got " +
                     std::to_string(u.size()));
  Eigen::VectorXd a(reduced_.lo.size());
  const int d = dimension_;
  const Eigen::VectorXd v = joining_.empty() ? u : joining_.relative(u);
  for (std::size_t i = 0; i < frames_.size(); ++i) {
    const Eigen::Matrix3d& B = frames_[i].full;
    const Eigen::VectorXd ui = v.segment(d * nodes_[i], d);
    const int node = static_cast<int>(i);
    if (const int k = normal_coordinate(node); k >= 0) a(k) = B.col(0).head(d).dot(ui) - origin_(k);
    if (const int k = tangential_coordinate(node); k >= 0) a(k) = B.col(1).head(d).dot(ui);
    if (const int k = second_tangential_coordinate(node); k >= 0) a(k) = B.col(2).head(d).dot(ui);
  }
  return a;
}

Vec3 Condensation::slot_direction(int node, int slot) const {
  if (node < 0 || node >= static_cast<int>(frames_.size()) || slot < 0 || slot > 2)
    throw InputError("no slot " + std::to_string(slot) + " of contact node " + std::to_string(node));
  return frames_[static_cast<std::size_t>(node)].full.col(slot);
}

// a, with the normal displacements 0 where they are not unknowns (bilateral).
Eigen::VectorXd Condensation::block1_values(const Eigen::VectorXd& a) const {
  const auto unknowns = static_cast<Eigen::Index>(coordinate1_.size());
  if (a.size() != unknowns)
    throw InputError("back-substitution needs " + std::to_string(unknowns) + " contact displacements, got " +
                     std::to_string(a.size()));
  if (static_cast<std::size_t>(unknowns) == block1_.size()) return a + origin_;
  Eigen::VectorXd x1 = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(block1_.size()));
  for (Eigen::Index k = 0; k < unknowns; ++k) x1(coordinate1_[static_cast<std::size_t>(k)]) = a(k) + origin_(k);
  return x1;
}

// The full nodal displacement from block 1's and block 2's values in rotated coordinates.
Eigen::VectorXd Condensation::displacement(const Eigen::VectorXd& x1, const Eigen::VectorXd& u2) const {
  Eigen::VectorXd ut(dofs_.num_free());
  for (std::size_t i = 0; i < block1_.size(); ++i) ut(block1_[i]) = x1(static_cast<Eigen::Index>(i));
  for (std::size_t i = 0; i < block2_.size(); ++i) ut(block2_[i]) = u2(static_cast<Eigen::Index>(i));
  return from_rotated(std::move(ut));
}

// Q ut: each contact node's components back from its frame to x, y[, z].
Eigen::VectorXd Condensation::unrotate(Eigen::VectorXd ut) const {
  for (const NodeFrame& f : frames_) {
    double rotated[3] = {0.0, 0.0, 0.0};
    for (int j = 0; j < f.m; ++j) rotated[j] = ut(f.idx[static_cast<std::size_t>(j)]);
    for (int r = 0; r < f.m; ++r) {
      double v = 0.0;
      for (int j = 0; j < f.m; ++j) v += f.C(r, j) * rotated[j];
      ut(f.idx[static_cast<std::size_t>(r)]) = v;
    }
  }
  return ut;
}

// The full nodal displacement of the rotated free unknowns: u = Q ut at the contact nodes, the
// prescribed values, and the pairs of two bodies undone.
Eigen::VectorXd Condensation::from_rotated(Eigen::VectorXd ut) const {
  ut = unrotate(std::move(ut));
  return joining_.empty() ? dofs_.expand(ut) : joining_.displacement(dofs_.expand(ut));
}

Eigen::VectorXd Condensation::unrotated_free(const Eigen::VectorXd& vt) const {
  if (vt.size() != dofs_.num_free())
    throw InternalError("unrotated_free needs " + std::to_string(dofs_.num_free()) + " values, got " +
                        std::to_string(vt.size()));
  if (joining_.empty()) return unrotate(vt);
  return joining_.unjoined_forces(unrotate(vt));
}

Eigen::VectorXd Condensation::unrotated_product(const Eigen::VectorXd& uf) const {
  if (!joining_.empty()) throw InternalError("the product with the unrotated matrix of two joined bodies");
  if (factorization_) throw InternalError("the product with the unrotated matrix of a condensed problem");
  if (uf.size() != At_.cols())
    throw InternalError("unrotated_product needs " + std::to_string(At_.cols()) + " free values, got " +
                        std::to_string(uf.size()));
  return unrotate(At_ * rotate_load(uf));
}

}  // namespace hemivem
