// The loops over elements that every assembly shares, in 2D and 3D: the element matrices in
// parallel, visited in element order, and the pattern of the global stiffness.
#pragma once

#include <hemivem/error.hpp>
#include <hemivem/mesh/vertex_cells.hpp>
#include <hemivem/vem/assembly.hpp>
#include <hemivem/sparse_factorization.hpp>

#include <Eigen/Core>

#include <algorithm>
#include <exception>
#include <vector>

namespace hemivem::detail {

// Calls visit(dofs, K) with the global dofs (Dim v + c per vertex v of the element) and the
// stiffness K_E of every element (an Eigen::Map of a Dim n x Dim n matrix), in element order;
// `vertices_of(e)` gives the element's vertex ids (a range) and `stiffness(e, K)` its matrix (called
// from several threads at once). The element matrices of a chunk of elements are computed in
// parallel (OpenMP, where built with it) and visited in order, so that sums built by visit()
// are the same bit for bit whatever the number of threads.
template <int Dim, class Vertices, class Stiffness, class Visit>
void for_each_element_matrix(int num_elements, Vertices&& vertices_of, Stiffness&& stiffness, Visit&& visit) {
  // a chunk holds at most `chunk` elements and about `budget` doubles (a few MB of matrices
  // that stay in cache between their computation and their visit)
  constexpr int chunk = 4096;
  constexpr std::size_t budget = std::size_t{1} << 18;
  std::vector<std::size_t> offset(chunk + 1);
  std::vector<double> matrices;
  std::vector<int> dof;
  for (int begin = 0, end = 0; begin < num_elements; begin = end) {
    offset[0] = 0;
    for (end = begin; end < num_elements && end - begin < chunk &&
                      (end == begin || offset[static_cast<std::size_t>(end - begin)] < budget);
         ++end) {
      const auto n = static_cast<std::size_t>(Dim) * std::size(vertices_of(end));
      offset[static_cast<std::size_t>(end - begin) + 1] = offset[static_cast<std::size_t>(end - begin)] + n * n;
    }
    matrices.resize(offset[static_cast<std::size_t>(end - begin)]);
    std::exception_ptr failure;
#if defined(_OPENMP)
#pragma omp parallel
#endif
    {
      Eigen::MatrixXd K;
#if defined(_OPENMP)
#pragma omp for schedule(static)
#endif
      for (int e = begin; e < end; ++e) {
        try {
          stiffness(e, K);
          std::copy(K.data(), K.data() + K.size(), matrices.data() + offset[static_cast<std::size_t>(e - begin)]);
        } catch (...) {
#if defined(_OPENMP)
#pragma omp critical(hemivem_element_failure)
#endif
          if (!failure) failure = std::current_exception();
        }
      }
    }
    if (failure) std::rethrow_exception(failure);
    for (int e = begin; e < end; ++e) {
      dof.clear();
      for (int v : vertices_of(e))
        for (int c = 0; c < Dim; ++c) dof.push_back(Dim * v + c);
      const auto n = static_cast<Eigen::Index>(dof.size());
      visit(dof, Eigen::Map<const Eigen::MatrixXd>(matrices.data() + offset[static_cast<std::size_t>(e - begin)], n, n));
    }
  }
}

/// The rows of a stiffness pattern's vertices (stiffness_pattern): each vertex's first row, and
/// the vertices in the order of their rows. An index increasing in the dof (the vertices in
/// their own order) needs neither.
class VertexRows {
 public:
  VertexRows(int num_vertices, int dim, const std::vector<int>& index, int size) : num_vertices_(num_vertices) {
    const auto at = [](int k) { return static_cast<std::size_t>(k); };
    int last = -1;
    for (const int i : index)
      if (i >= 0) {
        in_dof_order_ = in_dof_order_ && i > last;
        last = i;
      }
    if (in_dof_order_) return;
    first_.assign(at(num_vertices), -1);
    std::vector<int> vertex_at(at(size), -1);
    for (int v = 0; v < num_vertices; ++v) {
      int next = -1;
      for (int c = 0; c < dim; ++c)
        if (const int i = index[at(dim * v + c)]; i >= 0) {
          if (next >= 0 && i != next)
            throw InternalError("a stiffness pattern whose index numbers a vertex's dofs apart");
          if (next < 0) first_[at(v)] = i;
          next = i + 1;
        }
      if (first_[at(v)] >= 0) vertex_at[at(first_[at(v)])] = v;
    }
    for (const int v : vertex_at)
      if (v >= 0) order_.push_back(v);
  }
  /// How many vertices the columns go through, and the n-th of them.
  int count() const noexcept { return in_dof_order_ ? num_vertices_ : static_cast<int>(order_.size()); }
  int vertex(int n) const noexcept { return in_dof_order_ ? n : order_[static_cast<std::size_t>(n)]; }
  /// Sorts vertices in the order of their rows (those without a row first, in their own order).
  template <class It>
  void sort(It begin, It end) const {
    if (in_dof_order_) {
      std::sort(begin, end);
      return;
    }
    std::sort(begin, end, [this](int a, int b) {
      const int ka = first_[static_cast<std::size_t>(a)], kb = first_[static_cast<std::size_t>(b)];
      return ka < kb || (ka == kb && a < b);
    });
  }

 private:
  int num_vertices_ = 0;
  bool in_dof_order_ = true;
  std::vector<int> first_, order_;
};

/// The pattern of a stiffness matrix over the dofs with index[d] >= 0 (index: dof Dim v + c ->
/// row and column; a vertex's dofs consecutive rows in the order of their components, the
/// vertices in any order): the column of dof d holds every dof of every vertex w sharing an
/// element with d's vertex v for which couples(v, w) (symmetric in v and w), rows increasing;
/// values zero. The vertices' neighbours are found first, so that the matrix's arrays are sized
/// once and written in place. InternalError for an index that numbers a vertex's dofs apart.
template <int Dim, class Vertices, class Couples>
SparseMatrix stiffness_pattern(int num_vertices, int num_elements, Vertices&& vertices_of, const std::vector<int>& index,
                               int size, Couples&& couples) {
  const int nv = num_vertices;
  const auto at = [](int k) { return static_cast<std::size_t>(k); };
  // the elements of each vertex (compressed rows)
  const VertexCells around = vertex_cells(nv, num_elements, vertices_of);
  const std::vector<int>& first = around.start;
  const std::vector<int>& elements = around.cells;
  // the rows of each vertex's dofs (Dim * w + r with index >= 0) and, per vertex, its
  // neighbours (itself included), sorted
  std::vector<int> rows_of(at(nv), 0);
  for (int v = 0; v < nv; ++v)
    for (int r = 0; r < Dim; ++r) rows_of[at(v)] += index[at(Dim * v + r)] >= 0 ? 1 : 0;
  // each vertex's first row (-1 for none), and the vertices in the order of their rows
  const VertexRows vertex_rows(nv, Dim, index, size);
  std::vector<int> adjacency_start(at(nv) + 1, 0), adjacency;
  std::size_t in_elements = 0;  // the vertices of some element
  for (int v = 0; v < nv; ++v) in_elements += first[at(v) + 1] > first[at(v)] ? 1 : 0;
  adjacency.reserve(in_elements * (Dim == 3 ? 27 : 9));
  std::vector<int> seen(at(nv), -1);
  std::vector<std::size_t> column_size(at(nv), 0);  // the entries of a column of v's
  for (int v = 0; v < nv; ++v) {
    const auto begin = adjacency.size();
    for (int k = first[at(v)]; k < first[at(v) + 1]; ++k)
      for (int w : vertices_of(elements[at(k)]))
        if (seen[at(w)] != v) {
          seen[at(w)] = v;
          if (!couples(v, w)) continue;
          adjacency.push_back(w);
          column_size[at(v)] += static_cast<std::size_t>(rows_of[at(w)]);
        }
    vertex_rows.sort(adjacency.begin() + static_cast<std::ptrdiff_t>(begin), adjacency.end());
    adjacency_start[at(v) + 1] = static_cast<int>(adjacency.size());
  }
  std::size_t nnz = 0;
  for (int v = 0; v < nv; ++v) nnz += static_cast<std::size_t>(rows_of[at(v)]) * column_size[at(v)];
  SparseMatrix M(size, size);
  M.resizeNonZeros(static_cast<Eigen::Index>(nnz));
  int* outer = M.outerIndexPtr();
  int* inner = M.innerIndexPtr();
  std::fill(M.valuePtr(), M.valuePtr() + nnz, 0.0);
  std::size_t k = 0;
  int column = 0;
  outer[0] = 0;
  for (int n = 0; n < vertex_rows.count(); ++n)
    for (int c = 0, v = vertex_rows.vertex(n); c < Dim; ++c) {
      if (index[at(Dim * v + c)] < 0) continue;
      for (int a = adjacency_start[at(v)]; a < adjacency_start[at(v) + 1]; ++a)
        for (int r = 0; r < Dim; ++r) {
          const int row = index[at(Dim * adjacency[at(a)] + r)];
          if (row >= 0) inner[k++] = row;
        }
      outer[++column] = static_cast<int>(k);
    }
  return M;
}

/// The same with every pair of vertices sharing an element coupled.
template <int Dim, class Vertices>
SparseMatrix stiffness_pattern(int num_vertices, int num_elements, Vertices&& vertices_of, const std::vector<int>& index,
                               int size) {
  return stiffness_pattern<Dim>(num_vertices, num_elements, vertices_of, index, size, [](int, int) { return true; });
}

/// Adds element matrices into a compressed matrix whose pattern holds their entries, column by
/// column. The positions of a column's entries are found by binary search only where a guess
/// fails: the position of the same row in the element's previous column, moved to this column
/// (the dofs of a vertex share their rows in a stiffness pattern), then the position after the
/// previous row's (a vertex's dofs are consecutive rows). Each guess is checked, so any order of
/// the element's rows works.
class PatternScatter {
 public:
  explicit PatternScatter(SparseMatrix& A) : A_(A) {}

  /// Starts an element whose rows are rows[0..m) (-1: not in A).
  void element(const int* rows, std::size_t m) {
    rows_ = rows;
    m_ = m;
    position_.assign(m, -1);
    previous_begin_ = -1;
  }
  /// The positions in A's values of the element's rows in `column` (-1 for rows not in A).
  const std::vector<int>& locate(int column) {
    const int* inner = A_.innerIndexPtr();
    const int begin = A_.outerIndexPtr()[column], end = A_.outerIndexPtr()[column + 1];
    int last = -1;
    for (std::size_t i = 0; i < m_; ++i) {
      const int row = rows_[i];
      int& p = position_[i];
      if (row < 0) {
        p = -1;
        continue;
      }
      if (previous_begin_ >= 0 && p >= 0) {
        const int guess = p - previous_begin_ + begin;
        if (guess >= begin && guess < end && inner[guess] == row) {
          last = p = guess;
          continue;
        }
      }
      if (last >= 0 && last + 1 < end && inner[last + 1] == row) {
        last = p = last + 1;
        continue;
      }
      last = p = static_cast<int>(std::lower_bound(inner + begin, inner + end, row) - inner);
    }
    previous_begin_ = begin;
    return position_;
  }
  double* values() { return A_.valuePtr(); }

 private:
  SparseMatrix& A_;
  const int* rows_ = nullptr;
  std::size_t m_ = 0;
  std::vector<int> position_;
  int previous_begin_ = -1;
};

/// A = K on the free dofs of `dofs` and b -= K u_prescribed, element by element into A's pattern
/// (`visit` of for_each_element_matrix).
class FreeSystemAssembler {
 public:
  /// `free_index`: sys.dofs.free_index_table().
  FreeSystemAssembler(LinearSystem& sys, const std::vector<int>& free_index)
      : sys_(sys), free_index_(free_index), scatter_(sys.A) {}
  void operator()(const std::vector<int>& dof, const Eigen::Map<const Eigen::MatrixXd>& K) {
    free_.resize(dof.size());
    for (std::size_t i = 0; i < dof.size(); ++i) free_[i] = free_index_[static_cast<std::size_t>(dof[i])];
    scatter_.element(free_.data(), free_.size());
    double* values = scatter_.values();
    for (std::size_t j = 0; j < dof.size(); ++j) {
      const int fj = free_[j];
      const auto kj = K.col(static_cast<Eigen::Index>(j));
      if (fj >= 0) {
        const std::vector<int>& position = scatter_.locate(fj);
        for (std::size_t i = 0; i < dof.size(); ++i)
          if (position[i] >= 0) values[position[i]] += kj(static_cast<Eigen::Index>(i));
        continue;
      }
      const double uj = sys_.dofs.prescribed_value(dof[j]);
      if (uj == 0.0) continue;
      for (std::size_t i = 0; i < dof.size(); ++i)
        if (const int fi = free_[i]; fi >= 0) sys_.b(fi) -= kj(static_cast<Eigen::Index>(i)) * uj;
    }
  }

 private:
  LinearSystem& sys_;
  const std::vector<int>& free_index_;
  PatternScatter scatter_;
  std::vector<int> free_;
};

/// The owned rows and columns of A and the owned rows of b of a SystemRows, element by element
/// into A's pattern (`visit` of for_each_element_matrix over the elements that hold an owned
/// vertex): the entries and the lifted prescribed values that FreeSystemAssembler adds there, in
/// the same order.
class OwnedRowsAssembler {
 public:
  /// `index`: each dof's row of rows.A (its position in rows.unknowns), -1 for a prescribed dof.
  OwnedRowsAssembler(SystemRows& rows, const std::vector<int>& index)
      : rows_(rows), index_(index), all_(rows.A), owned_(rows.A) {}
  void operator()(const std::vector<int>& dof, const Eigen::Map<const Eigen::MatrixXd>& K) {
    const std::size_t n = dof.size();
    local_.resize(n);
    mine_.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      local_[i] = index_[static_cast<std::size_t>(dof[i])];
      mine_[i] = owns(local_[i]) ? local_[i] : -1;
    }
    // an owned column takes every row of the element, another column its owned rows
    all_.element(local_.data(), n);
    owned_.element(mine_.data(), n);
    double* values = all_.values();
    for (std::size_t j = 0; j < n; ++j) {
      const auto kj = K.col(static_cast<Eigen::Index>(j));
      if (local_[j] >= 0) {
        const std::vector<int>& position = (owns(local_[j]) ? all_ : owned_).locate(local_[j]);
        for (std::size_t i = 0; i < n; ++i)
          if (position[i] >= 0) values[position[i]] += kj(static_cast<Eigen::Index>(i));
        continue;
      }
      const double uj = rows_.dofs.prescribed_value(dof[j]);
      if (uj == 0.0) continue;
      for (std::size_t i = 0; i < n; ++i)
        if (mine_[i] >= 0) rows_.b(mine_[i] - rows_.at) -= kj(static_cast<Eigen::Index>(i)) * uj;
    }
  }

 private:
  bool owns(int local) const { return local >= rows_.at && local < rows_.at + rows_.owned; }
  SystemRows& rows_;
  const std::vector<int>& index_;
  PatternScatter all_, owned_;
  std::vector<int> local_, mine_;
};

/// The dof map of `ndof` dofs, `dim` per vertex, with the prescribed (dof, value) pairs
/// `prescribed` (a dof given several values takes the last): the free dofs numbered in dof order,
/// or, given `vertex_order` (a permutation of the `ndof / dim` vertices; InputError otherwise),
/// vertex by vertex along it.
DofMap dof_map_of(int ndof, std::vector<std::pair<int, double>> prescribed, const std::vector<int>* vertex_order,
                  int dim);

}  // namespace hemivem::detail
