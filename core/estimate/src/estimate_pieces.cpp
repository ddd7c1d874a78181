// The error estimate of a mesh in pieces (hemivem/estimate/estimate_pieces.hpp).
#include <hemivem/estimate/estimate_pieces.hpp>

#include <hemivem/error.hpp>

#include <algorithm>
#include <chrono>
#include <string>

#include "estimate_steps.hpp"
#include "estimate_terms.hpp"

namespace hemivem {

namespace {

/// The numbers an ElementTerms is sent as: its raw parts, weight and consistency energy.
constexpr Eigen::Index terms_size = detail::part_count + 2;

/// The smallest vertex of cell c.
int smallest_vertex(const Mesh& mesh, int c) {
  const auto v = mesh.element(c);
  return *std::min_element(v.begin(), v.end());
}
int smallest_vertex(const Mesh3D& mesh, int c) { return mesh.cell_vertices(c).front(); }

template <class MeshType>
std::vector<char> owned_cells_of(const MeshType& mesh, const PieceOfMesh& piece) {
  const std::vector<char> mine = piece.vertices.mask(mesh.num_vertices());
  std::vector<char> owned(static_cast<std::size_t>(mesh.num_cells()));
  for (int c = 0; c < mesh.num_cells(); ++c) owned[static_cast<std::size_t>(c)] = mine[static_cast<std::size_t>(smallest_vertex(mesh, c))];
  return owned;
}

}  // namespace

std::vector<char> owned_cells(const Mesh& mesh, const PieceOfMesh& piece) { return owned_cells_of(mesh, piece); }
std::vector<char> owned_cells(const Mesh3D& mesh, const PieceOfMesh& piece) { return owned_cells_of(mesh, piece); }

template <int dim>
std::vector<std::pair<int, std::vector<double>>> owned_estimate_terms(const BasicContactProblem<dim>& problem,
                                                                      const BasicContactSolution<dim>& solution,
                                                                      const PieceOfMesh& piece) {
  const std::vector<detail::ElementTerms> terms = detail::estimate_terms(problem, solution);
  if (terms.size() != piece.cells.size())
    throw InternalError("a piece of " + std::to_string(terms.size()) + " cells named by " +
                        std::to_string(piece.cells.size()) + " numbers of the whole mesh");
  const auto& mesh = *problem.elasticity.mesh;
  const std::vector<char> owned = owned_cells(mesh, piece);
  std::vector<std::pair<int, std::vector<double>>> out;
  for (std::size_t c = 0; c < terms.size(); ++c) {
    if (!owned[c]) continue;
    std::vector<double> t(terms[c].raw.begin(), terms[c].raw.end());
    t.push_back(terms[c].weight);
    t.push_back(terms[c].consistency_energy);
    out.emplace_back(piece.cells[c], std::move(t));
  }
  return out;
}

template <int dim>
ErrorEstimate estimate_error_of_pieces(const BasicContactProblem<dim>& problem, const BasicContactSolution<dim>& solution,
                                       const PieceOfMesh& piece, const RowDistribution& rows) {
  const auto start = std::chrono::steady_clock::now();
  const auto mine = owned_estimate_terms<dim>(problem, solution, piece);
  Eigen::VectorXd sent(static_cast<Eigen::Index>(mine.size()) * (terms_size + 1));
  for (std::size_t k = 0; k < mine.size(); ++k) {
    const Eigen::Index at = static_cast<Eigen::Index>(k) * (terms_size + 1);
    sent(at) = mine[k].first;
    for (Eigen::Index i = 0; i < terms_size; ++i) sent(at + 1 + i) = mine[k].second[static_cast<std::size_t>(i)];
  }
  const Eigen::VectorXd all = rows.all_gather(sent);
  const std::vector<Eigen::Index> records = record_starts(all, piece.whole_cells, [](Eigen::Index) { return terms_size; });
  std::vector<detail::ElementTerms> whole(records.size());
  for (std::size_t c = 0; c < whole.size(); ++c) {
    const Eigen::Index at = records[c];
    detail::ElementTerms& t = whole[c];
    for (std::size_t i = 0; i < detail::part_count; ++i) t.raw[i] = all(at + 1 + static_cast<Eigen::Index>(i));
    t.weight = all(at + 1 + detail::part_count);
    t.consistency_energy = all(at + 2 + detail::part_count);
  }
  return detail::sum_estimate(whole, start);
}

template std::vector<std::pair<int, std::vector<double>>> owned_estimate_terms<2>(const ContactProblem&,
                                                                                  const ContactSolution&,
                                                                                  const PieceOfMesh&);
template std::vector<std::pair<int, std::vector<double>>> owned_estimate_terms<3>(const ContactProblem3D&,
                                                                                  const ContactSolution3D&,
                                                                                  const PieceOfMesh&);
template ErrorEstimate estimate_error_of_pieces<2>(const ContactProblem&, const ContactSolution&, const PieceOfMesh&,
                                                   const RowDistribution&);
template ErrorEstimate estimate_error_of_pieces<3>(const ContactProblem3D&, const ContactSolution3D&,
                                                   const PieceOfMesh&, const RowDistribution&);

}  // namespace hemivem
