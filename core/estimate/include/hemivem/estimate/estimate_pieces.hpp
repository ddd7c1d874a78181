// The error estimate (hemivem/estimate/error_estimate.hpp) of a mesh that the processes of a run
// across processes hold in pieces (hemivem/mesh/box_piece.hpp): each process estimates the cells
// it owns from its piece, and every process gets the estimate of the whole mesh.
#pragma once

#include <algorithm>
#include <string>
#include <utility>
#include <vector>

#include <hemivem/error.hpp>
#include <hemivem/estimate/error_estimate.hpp>
#include <hemivem/estimate/error_estimate3d.hpp>
#include <hemivem/mesh/vertex_order.hpp>
#include <hemivem/row_distribution.hpp>

namespace hemivem {

/// Where a process's piece lies in the whole mesh: the whole mesh's number of each cell of the
/// piece (piece_cells, piece_cells_around), the whole mesh's count of cells, and the process's
/// vertices.
struct PieceOfMesh {
  std::vector<int> cells;
  int whole_cells = 0;
  VertexShare vertices;
};

/// The cells of the piece `mesh` that the process owns: those whose smallest vertex is one of
/// its vertices (piece.vertices), one flag per cell of the piece. Each cell of the whole mesh is
/// owned by one process, and the piece holds every neighbour of a cell it owns.
std::vector<char> owned_cells(const Mesh& mesh, const PieceOfMesh& piece);
std::vector<char> owned_cells(const Mesh3D& mesh, const PieceOfMesh& piece);

/// Where each cell's record starts in `records`, the records of the cells the processes own
/// gathered from them (each [the whole mesh's number of a cell, then `length(at)` numbers], `at`
/// where the record starts), indexed by the whole mesh's number of the cell: the records in the
/// whole mesh's order of cells. InternalError when a record runs past the end, or a cell of the
/// `cells` cells of the whole mesh is given twice, out of range or not at all.
template <class Length>
std::vector<Eigen::Index> record_starts(const Eigen::VectorXd& records, int cells, const Length& length) {
  std::vector<Eigen::Index> start(static_cast<std::size_t>(cells), -1);
  for (Eigen::Index at = 0; at < records.size();) {
    const double number = records(at);
    if (!(number >= 0.0 && number < cells))  // NaN included
      throw InternalError("the processes' pieces give a cell numbered " + std::to_string(number) +
                          ", out of the whole mesh's " + std::to_string(cells));
    const auto c = static_cast<std::size_t>(number);
    if (start[c] >= 0) throw InternalError("the processes' pieces give cell " + std::to_string(c) + " twice");
    start[c] = at;
    at += 1 + length(at);
    if (at > records.size()) throw InternalError("the processes' records end inside the record of a cell");
  }
  if (std::count(start.begin(), start.end(), Eigen::Index{-1}) > 0)
    throw InternalError("the processes' pieces leave cells of the whole mesh without a record");
  return start;
}

/// The residual terms of the cells of the piece that the process owns (owned_cells), as (the whole mesh's number of the cell, its terms), from
/// `problem` on the piece and the whole `solution`. A piece holds every neighbour of such a cell,
/// so that its terms are the whole mesh's, to the bit. InputError as estimate_error.
template <int dim>
std::vector<std::pair<int, std::vector<double>>> owned_estimate_terms(const BasicContactProblem<dim>& problem,
                                                                      const BasicContactSolution<dim>& solution,
                                                                      const PieceOfMesh& piece);

/// estimate_error of the whole mesh, collective over `rows`: each process's owned terms
/// (owned_estimate_terms) gathered in the whole mesh's order of cells and summed as
/// estimate_error sums them, the same on every process and estimate_error's on the whole mesh to
/// the bit. Its indicators are per cell of the whole mesh. InputError as estimate_error, on the
/// process that finds it (the caller tells the others); InternalError when the processes' cells
/// do not make the whole mesh's once each.
template <int dim>
ErrorEstimate estimate_error_of_pieces(const BasicContactProblem<dim>& problem, const BasicContactSolution<dim>& solution,
                                       const PieceOfMesh& piece, const RowDistribution& rows);

}  // namespace hemivem
