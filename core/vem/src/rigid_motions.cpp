#include <hemivem/vem/rigid_motions.hpp>
#include <hemivem/error.hpp>

#include <Eigen/SVD>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <numeric>
#include <span>
#include <set>
#include <utility>

namespace hemivem {

namespace {

int num_cells(const Mesh& mesh) { return mesh.num_elements(); }
int num_cells(const Mesh3D& mesh) { return mesh.num_cells(); }

std::span<const int> cell_vertices(const Mesh& mesh, int e) { return mesh.element(e); }
std::span<const int> cell_vertices(const Mesh3D& mesh, int c) { return mesh.cell_vertices(c); }

// Each pair of cells sharing a facet (an interior edge, or an interior face).
template <class F>
void for_each_interior_facet(const Mesh& mesh, F&& f) {
  for (const MeshEdge& e : mesh.edges())
    if (!e.on_boundary()) f(e.left, e.right);
}
template <class F>
void for_each_interior_facet(const Mesh3D& mesh, F&& f) {
  for (const MeshFace& face : mesh.faces())
    if (!face.on_boundary()) f(face.inner, face.outer);
}

// The pieces of the mesh: cell -> piece, joined through interior facets (union-find).
template <class M>
std::vector<int> pieces_of_elements(const M& mesh, int* count) {
  std::vector<int> parent(static_cast<std::size_t>(num_cells(mesh)));
  std::iota(parent.begin(), parent.end(), 0);
  auto root = [&](int e) {
    while (parent[static_cast<std::size_t>(e)] != e) e = parent[static_cast<std::size_t>(e)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(e)])];
    return e;
  };
  for_each_interior_facet(mesh, [&](int a, int b) { parent[static_cast<std::size_t>(root(a))] = root(b); });
  std::vector<int> piece(parent.size(), -1), number(parent.size(), -1);
  *count = 0;
  for (int e = 0; e < num_cells(mesh); ++e) {
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
  static_assert(BasicRigidMotions<3>::relative_tolerance == RigidMotions::relative_tolerance);
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
std::string point(const Vec3& p) { return "(" + number(p.x()) + ", " + number(p.y()) + ", " + number(p.z()) + ")"; }

Vec2 perp(const Vec2& v) { return {-v.y(), v.x()}; }

// The unit vectors along the axes.
template <int dim>
Eigen::Matrix<double, dim, 1> axis(int d) {
  return Eigen::Matrix<double, dim, 1>::Unit(d);
}

/// The piece of each body of a mesh whose bodies hold the vertices bodies[b], ...,
/// bodies[b + 1] - 1 (PieceBodies::first_vertex), -1 for a body of none, its pieces being those
/// of `piece` (each cell's) with the smallest vertices `smallest`: empty unless each body holds
/// one piece at most and each piece's cells lie in one body.
template <class M>
std::vector<int> piece_of_each_body(const M& mesh, const std::vector<int>& bodies, const std::vector<int>& piece,
                                    const std::vector<int>& smallest) {
  if (bodies.size() < 2 || bodies.front() != 0 || bodies.back() != mesh.num_vertices() ||
      !std::is_sorted(bodies.begin(), bodies.end()))
    return {};
  std::vector<int> body_piece(bodies.size() - 1, -1);
  std::vector<std::size_t> body_of(smallest.size());
  for (std::size_t p = 0; p < smallest.size(); ++p) {
    const auto b = static_cast<std::size_t>(std::upper_bound(bodies.begin(), bodies.end(), smallest[p]) - bodies.begin() - 1);
    if (body_piece[b] >= 0) return {};
    body_piece[b] = static_cast<int>(p), body_of[p] = b;
  }
  for (int e = 0; e < num_cells(mesh); ++e) {  // each piece's cells within its body
    const std::size_t b = body_of[static_cast<std::size_t>(piece[static_cast<std::size_t>(e)])];
    for (int v : cell_vertices(mesh, e))
      if (v < bodies[b] || v >= bodies[b + 1]) return {};
  }
  return body_piece;
}

}  // namespace

template <int dim>
BasicRigidMotions<dim>::BasicRigidMotions(const MeshType& mesh, const DofMap& dofs, const PieceBodies& piece_bodies)
    : vertices_(mesh.vertices()) {
  const std::vector<int>& bodies = piece_bodies.first_vertex;
  int count = 0;
  const std::vector<int> piece = pieces_of_elements(mesh, &count);
  pieces_.resize(static_cast<std::size_t>(count));
  std::vector<Point> lo(pieces_.size(), Point::Constant(INFINITY)), hi(pieces_.size(), Point::Constant(-INFINITY));
  std::vector<int> vertices(pieces_.size(), 0);
  piece_of_vertex_.assign(static_cast<std::size_t>(mesh.num_vertices()), -1);
  std::set<std::pair<int, int>> also;  // (vertex, a second piece holding it)
  for (int e = 0; e < num_cells(mesh); ++e) {
    const auto p = static_cast<std::size_t>(piece[static_cast<std::size_t>(e)]);
    ++pieces_[p].elements;
    for (int v : cell_vertices(mesh, e)) {
      int& first = piece_of_vertex_[static_cast<std::size_t>(v)];
      if (first < 0) first = static_cast<int>(p);
      else if (first != static_cast<int>(p)) also.emplace(v, static_cast<int>(p));
      if (pieces_[p].first_vertex < 0 || v < pieces_[p].first_vertex) pieces_[p].first_vertex = v;
    }
  }
  // a process's piece of bodies each of which its cells hold in one piece: every vertex of a
  // body lies on that body's piece
  std::vector<int> smallest(pieces_.size());
  for (std::size_t p = 0; p < pieces_.size(); ++p) smallest[p] = pieces_[p].first_vertex;
  const std::vector<int> body_piece = piece_of_each_body(mesh, bodies, piece, smallest);
  const bool by_bodies = !body_piece.empty();
  if (by_bodies) {
    for (std::size_t b = 0; b < body_piece.size(); ++b) {
      for (int v = bodies[b]; v < bodies[b + 1]; ++v) piece_of_vertex_[static_cast<std::size_t>(v)] = body_piece[b];
      if (body_piece[b] < 0) continue;
      Piece& P = pieces_[static_cast<std::size_t>(body_piece[b])];
      P.first_vertex = bodies[b];
      if (piece_bodies.cells.size() == body_piece.size()) P.elements = piece_bodies.cells[b];
    }
    also.clear();
  }
  // each piece's centre and extent: of every vertex of the mesh for one piece, which a process's
  // piece of a generated mesh (hemivem/mesh/box_piece.hpp) holds while its cells are fewer; of
  // every vertex of its body for a piece of bodies; of the vertices its cells hold otherwise. The
  // centre is summed in the order of the vertices, so that a piece of a mesh and the mesh agree.
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const int on = pieces_.size() == 1 && !by_bodies ? 0 : piece_of_vertex_[static_cast<std::size_t>(v)];
    if (on < 0) continue;
    const auto p = static_cast<std::size_t>(on);
    pieces_[p].center += mesh.vertex(v);
    ++vertices[p];
    lo[p] = lo[p].cwiseMin(mesh.vertex(v));
    hi[p] = hi[p].cwiseMax(mesh.vertex(v));
  }
  for (const auto& [v, p] : also) {  // a vertex several pieces hold, in each one's extent
    lo[static_cast<std::size_t>(p)] = lo[static_cast<std::size_t>(p)].cwiseMin(mesh.vertex(v));
    hi[static_cast<std::size_t>(p)] = hi[static_cast<std::size_t>(p)].cwiseMax(mesh.vertex(v));
  }
  for (std::size_t p = 0; p < pieces_.size(); ++p) {
    pieces_[p].center /= std::max(1, vertices[p]);
    pieces_[p].size = (hi[p] - lo[p]).maxCoeff();
    if (!(pieces_[p].size > 0.0) || !std::isfinite(pieces_[p].size)) pieces_[p].size = 1.0;
    pieces_[p].lo = lo[p];
    pieces_[p].hi = hi[p];
  }
  // the constraints: every prescribed component is zero, and pieces agree at shared vertices
  std::vector<Eigen::RowVectorXd> rows;
  for (int v = 0; v < mesh.num_vertices(); ++v)
    for (int d = 0; d < dim; ++d)
      if (dofs.free_index(dim * v + d) < 0) rows.push_back(functional(v, axis<dim>(d)));
  for (const auto& [v, p] : also)
    for (int d = 0; d < dim; ++d) rows.push_back(functional(v, axis<dim>(d)) - functional(v, axis<dim>(d), p));
  const Eigen::Index columns = per_piece * static_cast<Eigen::Index>(pieces_.size());
  Eigen::MatrixXd M(static_cast<Eigen::Index>(rows.size()), columns);
  for (std::size_t i = 0; i < rows.size(); ++i) M.row(static_cast<Eigen::Index>(i)) = rows[i];
  const Eigen::MatrixXd free = null_space(M, columns);
  basis_ = free.cols() > 0 ? readable(free) : Eigen::MatrixXd(columns, 0);
}

template <int dim>
Eigen::RowVectorXd BasicRigidMotions<dim>::functional(int v, const Point& direction) const {
  return functional(v, direction, piece_of_vertex_.at(static_cast<std::size_t>(v)));
}

template <int dim>
Eigen::RowVectorXd BasicRigidMotions<dim>::functional(int v, const Point& direction, int piece) const {
  Eigen::RowVectorXd row = Eigen::RowVectorXd::Zero(per_piece * static_cast<Eigen::Index>(pieces_.size()));
  if (piece < 0) return row;
  const Piece& P = pieces_[static_cast<std::size_t>(piece)];
  const Point arm = (vertices_[static_cast<std::size_t>(v)] - P.center) / P.size;
  if constexpr (dim == 2) {
    row.template segment<3>(3 * piece) << direction.x(), direction.y(), direction.dot(perp(arm));
  } else {  // d . (omega x arm) = omega . (arm x d)
    row.template segment<3>(6 * piece) = direction.transpose();
    row.template segment<3>(6 * piece + 3) = arm.cross(direction).transpose();
  }
  return row;
}

template <int dim>
BasicRigidMotions<dim> BasicRigidMotions<dim>::without(const Eigen::MatrixXd& constraint) const {
  BasicRigidMotions r = *this;
  if (empty()) return r;
  const Eigen::MatrixXd keep = null_space(constraint * basis_, basis_.cols());
  r.basis_ = keep.cols() > 0 ? readable(basis_ * keep) : Eigen::MatrixXd(basis_.rows(), 0);
  return r;
}

template <int dim>
auto BasicRigidMotions<dim>::displacement(int k, int v) const -> Point {
  const int p = piece_of_vertex_.at(static_cast<std::size_t>(v));
  if (p < 0) return Point::Zero();
  const Piece& P = pieces_[static_cast<std::size_t>(p)];
  const Eigen::Matrix<double, per_piece, 1> c = basis_.col(k).template segment<per_piece>(per_piece * p);
  const Point arm = (vertices_[static_cast<std::size_t>(v)] - P.center) / P.size;
  if constexpr (dim == 2)
    return Vec2(c(0), c(1)) + c(2) * perp(arm);
  else
    return c.template head<3>() + c.template tail<3>().cross(arm);
}

template <int dim>
Eigen::MatrixXd BasicRigidMotions<dim>::nodal() const {
  Eigen::MatrixXd U(dim * static_cast<Eigen::Index>(vertices_.size()), size());
  for (int k = 0; k < size(); ++k)
    for (int v = 0; v < static_cast<int>(vertices_.size()); ++v)
      U.col(k).template segment<dim>(dim * v) = displacement(k, v);
  return U;
}

namespace {

// One piece's motion in words: (t, theta) in a plane, (t, omega) in a solid, in the piece's
// scaled coordinates about its centre.
std::string motion_words(const Eigen::Vector3d& c, const Vec2& center, double size) {
  const Vec2 t(c(0), c(1));
  if (c(2) == 0.0) return "translation along " + point(Vec2(t.normalized()));
  // the centre of rotation: the point the motion t + theta (x - center)^perp / size leaves still
  return "rotation about " + point(Vec2(center + size * Vec2(-t.y(), t.x()) / c(2)));
}

std::string motion_words(const Eigen::Matrix<double, 6, 1>& c, const Vec3& center, double size) {
  const Vec3 t = c.head<3>(), omega = c.tail<3>();
  if (omega.cwiseAbs().maxCoeff() == 0.0) return "translation along " + point(Vec3(t.normalized()));
  // the axis: along omega, through the point nearest the centre that moves along it only
  const double w2 = omega.squaredNorm();
  const Vec3 through = center + size * omega.cross(t) / w2;
  std::string words = "rotation about the axis " + point(Vec3(omega.normalized())) + " through " + point(through);
  if (std::abs(t.dot(omega)) > 1e-12 * t.norm() * std::sqrt(w2)) words += " with a slide along it";
  return words;
}

}  // namespace

template <int dim>
std::string BasicRigidMotions<dim>::describe(int k) const {
  std::string text;
  for (std::size_t p = 0; p < pieces_.size(); ++p) {
    const Eigen::Matrix<double, per_piece, 1> c =
        basis_.col(k).template segment<per_piece>(per_piece * static_cast<Eigen::Index>(p));
    if (c.cwiseAbs().maxCoeff() == 0.0) continue;
    const Piece& P = pieces_[p];
    const std::string of = pieces_.size() == 1 ? "of the body"
                                               : "of the piece of " + std::to_string(P.elements) +
                                                     (dim == 2 ? " elements around " : " cells around ") + point(P.center);
    text += (text.empty() ? "" : " with a ") + motion_words(c, P.center, P.size) + " " + of;
  }
  return text;
}

namespace {

// The motion of coefficient j of a piece: translations along the axes, then rotations.
template <int dim>
const char* axis_motion(Eigen::Index j) {
  static constexpr const char* plane[] = {"translation along x", "translation along y", "rotation"};
  static constexpr const char* solid[] = {"translation along x", "translation along y", "translation along z",
                                          "rotation about x",    "rotation about y",    "rotation about z"};
  return dim == 2 ? plane[j] : solid[j];
}

// "[x0, x1] x [y0, y1]" (x [z0, z1]).
template <class Vector>
std::string box_text(const Vector& lo, const Vector& hi) {
  std::string text;
  for (Eigen::Index d = 0; d < lo.size(); ++d)
    text += (d == 0 ? "[" : " x [") + number(lo(d)) + ", " + number(hi(d)) + "]";
  return text;
}

}  // namespace

template <int dim>
std::string BasicRigidMotions<dim>::describe_by_axes(int k) const {
  std::string text;
  for (std::size_t p = 0; p < pieces_.size(); ++p) {
    const Eigen::Matrix<double, per_piece, 1> c =
        basis_.col(k).template segment<per_piece>(per_piece * static_cast<Eigen::Index>(p));
    Eigen::Index at = 0;
    const double largest = c.cwiseAbs().maxCoeff(&at);
    if (largest == 0.0) continue;
    std::string words = axis_motion<dim>(at);
    if (largest < 0.99 * c.norm()) words += " (combined with others)";
    if (pieces_.size() > 1) {
      const Piece& P = pieces_[p];
      words += " of the piece of " + std::to_string(P.elements) + (dim == 2 ? " element" : " cell") +
               (P.elements == 1 ? "" : "s") + " in " + box_text(P.lo, P.hi) + " (vertex " +
               std::to_string(P.first_vertex) + " at " + point(vertices_[static_cast<std::size_t>(P.first_vertex)]) + ")";
    }
    text += (text.empty() ? "" : " with a ") + words;
  }
  return text;
}

template class BasicRigidMotions<2>;
template class BasicRigidMotions<3>;

int count_pieces(const Mesh& mesh) {
  int count = 0;
  (void)pieces_of_elements(mesh, &count);
  return count;
}
int count_pieces(const Mesh3D& mesh) {
  int count = 0;
  (void)pieces_of_elements(mesh, &count);
  return count;
}

}  // namespace hemivem
