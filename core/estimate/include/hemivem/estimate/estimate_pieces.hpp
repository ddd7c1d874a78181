// The error estimate (hemivem/estimate/error_estimate.hpp) of a mesh that the processes of a run
// across processes hold in pieces (hemivem/mesh/box_piece.hpp): each process estimates the cells
// it owns from its piece, and every process gets the estimate of the whole mesh.
#pragma once

#include <utility>
#include <vector>

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
