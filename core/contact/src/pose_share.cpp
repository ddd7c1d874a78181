// pose_share (hemivem/contact/pose_share.hpp): a process's share of the full-space route's posed
// problem from the cells of its own rows, in the steps of BasicContactSolver::prepare() (assembly,
// contact set-up, posing) restricted to those rows. Each step is the one the whole posing takes,
// on less: the same kernels, the same rotation, the same numbering of the coordinates.
#include <hemivem/contact/pose_share.hpp>

#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/error.hpp>
#include <hemivem/vem/assembly.hpp>
#include <hemivem/vem/assembly3d.hpp>
#include <hemivem/vem/rigid_motions.hpp>

#include <algorithm>
#include <memory>
#include <numeric>
#include <string>
#include <vector>

namespace hemivem {

namespace {

/// InputError for what the share cannot pose: no contact node, or two bodies joined.
template <int dim>
void require_one_body_in_contact(const ContactSetUp<dim>& contact) {
  if (contact.boundary.size() == 0)
    throw InputError("the problem has no contact node: there is no contact problem to pose, only its linear system "
                     "(assemble_rows gives a process's rows of it)")
        .mark_about(ProblemPart::contact);
  if (contact.boundary.across.empty()) return;
  const auto joined = std::find_if(contact.parts.begin(), contact.parts.end(),
                                   [](const BasicContactPart<dim>& p) { return !p.against.empty(); });
  const std::string part = joined != contact.parts.end() ? joined->name : contact.parts.front().name;
  throw InputError("contact part '" + part + "' meets another body: two bodies joined at their contact are posed "
                   "with their whole system, in one process only")
      .mark_about(ProblemPart::contact);
}

/// The owned rows of the rotated part `At` of `rows` (local columns: owned rows, then ghosts) and
/// the layout's ghosts: the unknowns outside the owned range that the owned rows read.
SparseMatrix owned_rows(const SparseMatrix& At, const SystemRows& rows, RowLayout& layout) {
  const Eigen::Index at = rows.at, owned = rows.owned;
  const auto is_owned = [&](Eigen::Index i) { return i >= at && i < at + owned; };
  // the local column of each column of At (its rows are the unknowns, increasing: so are the ghosts)
  std::vector<Eigen::Index> local(rows.unknowns.size(), -1);
  for (Eigen::Index c = 0; c < At.outerSize(); ++c) {
    if (is_owned(c)) {
      local[static_cast<std::size_t>(c)] = c - at;
      continue;
    }
    for (SparseMatrix::InnerIterator e(At, c); e; ++e)  // At is symmetric: column c's rows read it
      if (is_owned(e.row())) {
        local[static_cast<std::size_t>(c)] = owned + static_cast<Eigen::Index>(layout.ghosts.size());
        layout.ghosts.push_back(rows.unknowns[static_cast<std::size_t>(c)]);
        break;
      }
  }
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index c = 0; c < At.outerSize(); ++c)
    for (SparseMatrix::InnerIterator e(At, c); e; ++e)
      if (is_owned(e.row()))
        entries.emplace_back(static_cast<int>(e.row() - at), static_cast<int>(local[static_cast<std::size_t>(c)]),
                             e.value());
  SparseMatrix A(owned, owned + static_cast<Eigen::Index>(layout.ghosts.size()));
  A.setFromTriplets(entries.begin(), entries.end());
  A.makeCompressed();
  return A;
}

/// The owned rows of the rigid motions of `mesh` in the rotated free unknowns of `posed`.
template <int dim>
Eigen::MatrixXd near_null_rows(const MeshOf<dim>& mesh, const Condensation& posed, const SystemRows& rows,
                               const std::vector<int>& owned_unknowns) {
  const MeshRigidMotions<dim> motions(mesh);
  Eigen::MatrixXd N(rows.owned, motions.count);
  Eigen::VectorXd motion(rows.owned);
  for (int k = 0; k < motions.count; ++k) {
    for (Eigen::Index i = 0; i < rows.owned; ++i) {
      const int d = rows.dofs.free_dofs[static_cast<std::size_t>(rows.first + i)];
      motion(i) = motions.at(k, d / dim)(d % dim);
    }
    N.col(k) = posed.rotated_part(motion, owned_unknowns);
  }
  return N;
}

}  // namespace

template <int dim>
PosedShare pose_share(const BasicContactProblem<dim>& problem, int first_vertex, int end_vertex) {
  SystemRows rows = assemble_rows(problem.elasticity, first_vertex, end_vertex);
  const ContactSetUp<dim> contact = contact_set_up(problem, rows.dofs);
  require_one_body_in_contact(contact);
  require_full_space_posable(contact.parts, contact.held_by_contact);
  const auto posed = about(ProblemPart::contact, [&] {
    return std::make_unique<Condensation>(rows.dofs, contact.boundary, part_conditions(contact.parts),
                                          Condensation::CoordinatesOnly{});
  });
  PosedShare out;
  out.layout.first = rows.first;
  out.layout.owned = rows.owned;
  out.layout.global = rows.dofs.num_free();
  {
    const SparseMatrix At = posed->rotated_part(rows.A, rows.unknowns);
    SparseMatrix().swap(rows.A);  // the part's unrotated entries are no longer needed
    SparseMatrix A = owned_rows(At, rows, out.layout);
    out.share.matrix.swap(A);  // no copy (SparseMatrix has no move assignment)
  }
  std::vector<int> owned_unknowns(static_cast<std::size_t>(rows.owned));
  std::iota(owned_unknowns.begin(), owned_unknowns.end(), static_cast<int>(rows.first));
  out.share.load = posed->rotated_part(rows.b, owned_unknowns);
  share_coordinates(*posed, rows.first, rows.owned, out.share);
  out.near_null_space = near_null_rows<dim>(*problem.elasticity.mesh, *posed, rows, owned_unknowns);
  out.block_size = node_block_size(rows.dofs, dim);
  return out;
}

template PosedShare pose_share<2>(const ContactProblem&, int, int);
template PosedShare pose_share<3>(const BasicContactProblem<3>&, int, int);

}  // namespace hemivem
