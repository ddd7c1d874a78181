#include <hemivem/vem/rigid_motions.hpp>
#include <hemivem/error.hpp>

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <set>
#include <utility>

namespace hemivem {

namespace {

// The pieces of the mesh: element -> piece, joined through interior edges (union-find).
std::vector<int> pieces_of_elements(const Mesh& mesh, int* count) {
  std::vector<int> parent(static_cast<std::size_t>(mesh.num_elements()));
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int e) {
    while (parent[static_cast<std::size_t>(e)] != e) e = parent[static_cast<std::size_t>(e)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(e)])];
    return e;
  };
  for (const MeshEdge& e : mesh.edges())
    if (!e.on_boundary()) parent[static_cast<std::size_t>(root(e.left))] = root(e.right);
  std::vector<int> piece(parent.size(), -1), number(parent.size(), -1);
  *count = 0;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    int& n = number[static_cast<std::size_t>(root(e))];
    if (n < 0) n = (*count)++;
    piece[static_cast<std::size_t>(e)] = n;
  }
  return piece;
}

// The null space of M (columns of the result), a singular value at most tol * max(1, sigma_max)
// counting as zero. M's rows are expected to have entries of order 1.
Eigen::MatrixXd null_space(const Eigen::MatrixXd& M, Eigen::Index columns) {
  if (M.rows() == 0) return Eigen::MatrixXd::Identity(columns, columns);
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(M, Eigen::ComputeFullV);
  const Eigen::VectorXd& sigma = svd.singularValues();
  const double bound = RigidMotions::relative_tolerance * std::max(1.0, sigma.size() ? sigma(0) : 0.0);
  Eigen::Index rank = 0;
  while (rank < sigma.size() && sigma(rank) > bound) ++rank;
  return svd.matrixV().rightCols(columns - rank);
}

// The columns of B (a basis) brought to a readable form: the reduced row echelon form of B^T
// with partial pivoting, each motion scaled to a largest coefficient of 1, and entries below
// 1e-12 of it set to 0 (so that a pure translation reads as one).
Eigen::MatrixXd readable(const Eigen::MatrixXd& B) {
  Eigen::MatrixXd R = B.transpose();
  Eigen::Index row = 0;
  for (Eigen::Index col = 0; col < R.cols() && row < R.rows(); ++col) {
    Eigen::Index pivot = row;
    const double best = R.col(col).segment(row, R.rows() - row).cwiseAbs().maxCoeff(&pivot);
    if (!(best > 1e-10)) continue;
    pivot += row;
    R.row(row).swap(R.row(pivot));
    R.row(row) /= R(row, col);
    for (Eigen::Index r = 0; r < R.rows(); ++r)
      if (r != row) R.row(r) -= R(r, col) * R.row(row);
    ++row;
  }
  for (Eigen::Index r = 0; r < R.rows(); ++r) {
    const double m = R.row(r).cwiseAbs().maxCoeff();
    if (m > 0.0) R.row(r) /= m;
    for (Eigen::Index c = 0; c < R.cols(); ++c)
      if (std::abs(R(r, c)) < 1e-12) R(r, c) = 0.0;
  }
  return R.transpose();
}

std::string number(double x) {
  if (std::abs(x) < 1e-300) x = 0.0;
  char buffer[32];
  std::snprintf(buffer, sizeof buffer, "%.4g", x);
  return buffer;
}

std::string point(const Vec2& p) { return "(" + number(p.x()) + ", " + number(p.y()) + ")"; }

Vec2 perp(const Vec2& v) { return {-v.y(), v.x()}; }

}  // namespace

RigidMotions::RigidMotions(const Mesh& mesh, const DofMap& dofs) : vertices_(mesh.vertices()) {
  int count = 0;
  const std::vector<int> piece = pieces_of_elements(mesh, &count);
  pieces_.resize(static_cast<std::size_t>(count));
  std::vector<Vec2> lo(pieces_.size(), Vec2::Constant(INFINITY)), hi(pieces_.size(), Vec2::Constant(-INFINITY));
  std::vector<int> vertices(pieces_.size(), 0);
  piece_of_vertex_.assign(static_cast<std::size_t>(mesh.num_vertices()), -1);
  std::set<std::pair<int, int>> also;  // (vertex, a second piece holding it)
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto p = static_cast<std::size_t>(piece[static_cast<std::size_t>(e)]);
    ++pieces_[p].elements;
    for (int v : mesh.element(e)) {
      int& first = piece_of_vertex_[static_cast<std::size_t>(v)];
      if (first < 0) {
        first = static_cast<int>(p);
        pieces_[p].center += mesh.vertex(v);
        ++vertices[p];
      } else if (first != static_cast<int>(p)) {
        also.emplace(v, static_cast<int>(p));
      }
      lo[p] = lo[p].cwiseMin(mesh.vertex(v));
      hi[p] = hi[p].cwiseMax(mesh.vertex(v));
    }
  }
  for (std::size_t p = 0; p < pieces_.size(); ++p) {
    pieces_[p].center /= std::max(1, vertices[p]);
    pieces_[p].size = (hi[p] - lo[p]).maxCoeff();
    if (!(pieces_[p].size > 0.0) || !std::isfinite(pieces_[p].size)) pieces_[p].size = 1.0;
  }
  // the constraints: every prescribed component is zero, and pieces agree at shared vertices
  std::vector<Eigen::RowVectorXd> rows;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    for (int d = 0; d < 2; ++d)
      if (dofs.free_index[static_cast<std::size_t>(2 * v + d)] < 0)
        rows.push_back(functional(v, d == 0 ? Vec2(1, 0) : Vec2(0, 1)));
  for (const auto& [v, p] : also)
    for (const Vec2& d : {Vec2(1, 0), Vec2(0, 1)}) rows.push_back(functional(v, d) - functional(v, d, p));
  const Eigen::Index columns = 3 * static_cast<Eigen::Index>(pieces_.size());
  Eigen::MatrixXd M(static_cast<Eigen::Index>(rows.size()), columns);
  for (std::size_t i = 0; i < rows.size(); ++i) M.row(static_cast<Eigen::Index>(i)) = rows[i];
  const Eigen::MatrixXd free = null_space(M, columns);
  basis_ = free.cols() > 0 ? readable(free) : Eigen::MatrixXd(columns, 0);
}

Eigen::RowVectorXd RigidMotions::functional(int v, const Vec2& direction) const {
  return functional(v, direction, piece_of_vertex_.at(static_cast<std::size_t>(v)));
}

Eigen::RowVectorXd RigidMotions::functional(int v, const Vec2& direction, int piece) const {
  Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(3 * static_cast<Eigen::Index>(pieces_.size()));
  if (piece < 0) return row;
  const Piece& P = pieces_[static_cast<std::size_t>(piece)];
  const Vec2 arm = perp((vertices_[static_cast<std::size_t>(v)] - P.center) / P.size);
  row.segment<3>(3 * piece) << direction.x(), direction.y(), direction.dot(arm);
  return row;
}

RigidMotions RigidMotions::without(const Eigen::MatrixXd& constraint) const {
  RigidMotions r = *this;
  if (empty()) return r;
  const Eigen::MatrixXd keep = null_space(constraint * basis_, basis_.cols());
  r.basis_ = keep.cols() > 0 ? readable(basis_ * keep) : Eigen::MatrixXd(basis_.rows(), 0);
  return r;
}

Vec2 RigidMotions::displacement(int k, int v) const {
  const int p = piece_of_vertex_.at(static_cast<std::size_t>(v));
  if (p < 0) return Vec2::Zero();
  const Piece& P = pieces_[static_cast<std::size_t>(p)];
  const Eigen::Vector3d c = basis_.col(k).segment<3>(3 * p);
  return Vec2(c(0), c(1)) + c(2) * perp((vertices_[static_cast<std::size_t>(v)] - P.center) / P.size);
}

Eigen::MatrixXd RigidMotions::nodal() const {
  Eigen::MatrixXd U(2 * static_cast<Eigen::Index>(vertices_.size()), size());
  for (int k = 0; k < size(); ++k)
    for (int v = 0; v < static_cast<int>(vertices_.size()); ++v) U.col(k).segment<2>(2 * v) = displacement(k, v);
  return U;
}

std::string RigidMotions::describe(int k) const {
  std::string text;
  for (std::size_t p = 0; p < pieces_.size(); ++p) {
    const Eigen::Vector3d c = basis_.col(k).segment<3>(3 * static_cast<Eigen::Index>(p));
    if (c.cwiseAbs().maxCoeff() == 0.0) continue;
    const Piece& P = pieces_[p];
    const Vec2 t(c(0), c(1));
    std::string what;
    if (c(2) == 0.0) {
      what = "translation along " + point(t.normalized());
    } else {
      // the centre of rotation: the point the motion t + theta (x - center)^perp / size leaves still
      what = "rotation about " + point(P.center + P.size * Vec2(-t.y(), t.x()) / c(2));
    }
    const std::string of = pieces_.size() == 1 ? "of the body"
                                               : "of the piece of " + std::to_string(P.elements) +
                                                     " elements around " + point(P.center);
    text += (text.empty() ? "" : " with a ") + what + " " + of;
  }
  return text;
}

}  // namespace hemivem
