// The loops over elements that every assembly shares, in 2D and 3D: the element matrices in
// parallel, visited in element order, and the pattern of the global stiffness.
#pragma once

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
  constexpr int chunk = 4096;
  std::vector<std::size_t> offset(chunk + 1);
  std::vector<double> matrices;
  std::vector<int> dof;
  for (int begin = 0; begin < num_elements; begin += chunk) {
    const int end = std::min(num_elements, begin + chunk);
    offset[0] = 0;
    for (int e = begin; e < end; ++e) {
      const auto n = static_cast<std::size_t>(Dim) * std::size(vertices_of(e));
      offset[static_cast<std::size_t>(e - begin) + 1] = offset[static_cast<std::size_t>(e - begin)] + n * n;
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

/// The pattern of a stiffness matrix over the dofs with index[d] >= 0 (index: dof Dim v + c ->
/// row and column; increasing in d): the column of dof d holds every dof of every vertex
/// sharing an element with d's vertex, rows increasing; values zero.
template <int Dim, class Vertices>
SparseMatrix stiffness_pattern(int num_vertices, int num_elements, Vertices&& vertices_of, const std::vector<int>& index,
                               int size) {
  const int nv = num_vertices;
  // the elements of each vertex (compressed rows)
  std::vector<int> first(static_cast<std::size_t>(nv) + 1, 0), elements;
  for (int e = 0; e < num_elements; ++e)
    for (int v : vertices_of(e)) ++first[static_cast<std::size_t>(v) + 1];
  for (int v = 0; v < nv; ++v) first[static_cast<std::size_t>(v) + 1] += first[static_cast<std::size_t>(v)];
  elements.resize(static_cast<std::size_t>(first[static_cast<std::size_t>(nv)]));
  {
    std::vector<int> fill(first.begin(), first.end() - 1);
    for (int e = 0; e < num_elements; ++e)
      for (int v : vertices_of(e)) elements[static_cast<std::size_t>(fill[static_cast<std::size_t>(v)]++)] = e;
  }
  // per vertex its neighbours (itself included), sorted; then the columns of its dofs
  std::vector<int> outer(static_cast<std::size_t>(size) + 1, 0), inner, neighbours;
  std::vector<int> seen(static_cast<std::size_t>(nv), -1);
  inner.reserve(static_cast<std::size_t>(size) * 9 * Dim);
  int column = 0;
  for (int v = 0; v < nv; ++v) {
    neighbours.clear();
    for (int k = first[static_cast<std::size_t>(v)]; k < first[static_cast<std::size_t>(v) + 1]; ++k)
      for (int w : vertices_of(elements[static_cast<std::size_t>(k)]))
        if (seen[static_cast<std::size_t>(w)] != v) {
          seen[static_cast<std::size_t>(w)] = v;
          neighbours.push_back(w);
        }
    std::sort(neighbours.begin(), neighbours.end());
    for (int c = 0; c < Dim; ++c) {
      if (index[static_cast<std::size_t>(Dim * v + c)] < 0) continue;
      for (int w : neighbours)
        for (int r = 0; r < Dim; ++r) {
          const int row = index[static_cast<std::size_t>(Dim * w + r)];
          if (row >= 0) inner.push_back(row);
        }
      outer[static_cast<std::size_t>(++column)] = static_cast<int>(inner.size());
    }
  }
  return pattern_matrix(size, size, outer, inner, 0.0);
}

/// The stored entry (row, column) of a compressed matrix whose pattern holds it.
inline double& stored(SparseMatrix& A, int row, int column) {
  const int* begin = A.innerIndexPtr() + A.outerIndexPtr()[column];
  const int* end = A.innerIndexPtr() + A.outerIndexPtr()[column + 1];
  return A.valuePtr()[std::lower_bound(begin, end, row) - A.innerIndexPtr()];
}

/// A = K on the free dofs of `dofs` and b -= K u_prescribed, element by element into A's pattern
/// (`visit` of for_each_element_matrix).
struct FreeSystemAssembler {
  LinearSystem& sys;
  void operator()(const std::vector<int>& dof, const Eigen::Map<const Eigen::MatrixXd>& K) const {
    const std::vector<int>& free_index = sys.dofs.free_index;
    for (std::size_t j = 0; j < dof.size(); ++j) {
      const int fj = free_index[static_cast<std::size_t>(dof[j])];
      const double uj = sys.dofs.prescribed(dof[j]);
      for (std::size_t i = 0; i < dof.size(); ++i) {
        const int fi = free_index[static_cast<std::size_t>(dof[i])];
        if (fi < 0) continue;
        const double k = K(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j));
        if (fj >= 0)
          stored(sys.A, fi, fj) += k;
        else if (uj != 0.0)
          sys.b(fi) -= k * uj;
      }
    }
  }
};

/// The dof map of `ndof` dofs with `fixed[d]` set where dof d is prescribed.
DofMap dof_map_of(std::vector<char> fixed, Eigen::VectorXd prescribed);

}  // namespace hemivem::detail
