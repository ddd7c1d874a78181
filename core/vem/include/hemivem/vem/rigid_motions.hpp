// The rigid motions the Dirichlet conditions leave free: the kernel of the stiffness matrix
// after the prescribed displacements are removed, found from the mesh and the prescribed
// components alone, before anything is factorized.
#pragma once

#include <Eigen/Core>

#include <algorithm>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include <hemivem/mesh/body_range.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/vem/assembly.hpp>

namespace hemivem {

/// The displacements of zero strain energy that the prescribed components of a DofMap leave
/// free. The mesh is cut into pieces, the sets of elements joined through shared edges; a piece
/// deforms with energy under every motion but its rigid ones (u(x) = t + theta (x - c)^perp),
/// and two pieces that share only vertices may still move against each other (a hinge). So the
/// free motions are the piecewise rigid motions that agree at every shared vertex and vanish in
/// every prescribed component: the null space of a small matrix with three columns per piece.
///
/// That null space comes from a singular value decomposition in coordinates scaled by each
/// piece's size, so that the decision does not depend on the units: every constraint row has
/// entries of order 1, and a motion whose constraint residual is at most `relative_tolerance`
/// (1e-8) times max(1, the largest singular value) is free. Supports that hold a
/// motion only through a lever shorter than that fraction of the body's size (collinear within
/// round-off) hold it no better than round-off does.
///
/// In a solid (dim = 3) the pieces are the cells joined through shared faces and each has six
/// rigid motions, u(x) = t + omega x (x - c).
template <int dim>
class BasicRigidMotions {
 public:
  using Point = Eigen::Matrix<double, dim, 1>;
  using MeshType = MeshOf<dim>;
  /// The rigid motions of one piece: 3 in a plane, 6 in a solid.
  static constexpr int per_piece = dim == 2 ? 3 : 6;
  static constexpr double relative_tolerance = 1e-8;

  BasicRigidMotions() = default;
  /// `bodies`: empty, or the mesh is a process's piece of a mesh of those bodies, which holds
  /// every vertex of the whole (BasicElasticityProblem::piece_bodies). Where its cells make one
  /// piece in each body, every vertex of a body lies on its piece, those of none of its cells
  /// too, and the piece's centre, extent, smallest vertex and number of cells are those of the
  /// body (its every vertex, its cells in the whole mesh), so that the motions, what holds them
  /// and how they are named are the whole bodies'. Otherwise a vertex of no cell lies on no piece.
  BasicRigidMotions(const MeshType& mesh, const DofMap& dofs, const PieceBodies& bodies = {});

  /// The number of independent free motions (0: the supports hold the whole mesh).
  int size() const noexcept { return static_cast<int>(basis_.cols()); }
  bool empty() const noexcept { return size() == 0; }
  /// The number of pieces of the mesh (sets of elements joined through shared edges, or of
  /// cells joined through shared faces).
  int num_pieces() const noexcept { return static_cast<int>(pieces_.size()); }

  /// The displacement of vertex v under free motion k (normalised: its largest displacement
  /// over the mesh is of order 1).
  Point displacement(int k, int v) const;
  /// Free motion k in words: "translation along (0, 1)" or "rotation about (0.5, 2)" (in a
  /// solid "rotation about the axis (0, 0, 1) through (0.5, 0.5, 0)"), of "the body" or of
  /// "the piece of N elements around (x, y)" (each moving piece).
  std::string describe(int k) const;
  /// Free motion k by the motions along and about the axes: for each piece it moves, the one
  /// of largest coefficient ("translation along x", "rotation about z"; in a plane "rotation"),
  /// with "(combined with others)" when others take part, and when the mesh has more than one
  /// piece where the piece is: "of the piece of N cells in [x0, x1] x [y0, y1] x [z0, z1]
  /// (vertex v at (x, y, z))" (in a plane "N elements in [x0, x1] x [y0, y1]").
  std::string describe_by_axes(int k) const;
  /// The free motions as nodal displacements (dim num_vertices rows, one column per motion).
  Eigen::MatrixXd nodal() const;

  /// The combinations of the free motions that keep every functional of `constraint` at zero
  /// (its rows, from functional()), with the same relative tolerance: the free motions that
  /// those displacements, held at zero, would not hold.
  BasicRigidMotions without(const Eigen::MatrixXd& constraint) const;
  /// The functional "the displacement at vertex v along the unit vector `direction`" of the
  /// piecewise rigid motions (one row, per_piece coefficients per piece), to build the
  /// constraint of without(). Zero for a vertex of no element.
  Eigen::RowVectorXd functional(int v, const Point& direction) const;

 private:
  struct Piece {
    int elements = 0;
    Point center = Point::Zero();  // the mean of the piece's vertices (of every vertex, for one piece)
    double size = 1.0;             // its largest extent (likewise)
    Point lo = Point::Zero();      // its bounding box (likewise)
    Point hi = Point::Zero();
    int first_vertex = -1;         // its smallest vertex
  };
  std::vector<Piece> pieces_;
  std::vector<Point> vertices_;
  std::vector<int> piece_of_vertex_;  // one piece holding each vertex (-1: no element has it)
  Eigen::MatrixXd basis_;             // per_piece num_pieces x size(): (t, rotation * size) per piece

  Eigen::RowVectorXd functional(int v, const Point& direction, int piece) const;
};
using RigidMotions = BasicRigidMotions<2>;

/// The number of pieces of a mesh: sets of its cells joined through shared facets, those
/// BasicRigidMotions moves (without `bodies`) one by one.
int count_pieces(const Mesh& mesh);
int count_pieces(const Mesh3D& mesh);

/// The rigid motions of a mesh as nodal displacements: the translations along the axes, then the
/// rotations about them through the mean of its vertices (3 in a plane, 6 in a solid). The
/// near-null space of its stiffness, which the full-space route gives its preconditioner.
template <int dim>
class MeshRigidMotions {
 public:
  using Point = Eigen::Matrix<double, dim, 1>;
  static constexpr int count = dim == 2 ? 3 : 6;

  explicit MeshRigidMotions(const MeshOf<dim>& mesh) : mesh_(mesh) {
    for (const auto& v : mesh.vertices()) centre_ += v;
    centre_ /= std::max(mesh.num_vertices(), 1);
  }
  /// The displacement of vertex v under motion k.
  Point at(int k, int v) const {
    const Point x = mesh_.vertices()[static_cast<std::size_t>(v)] - centre_;
    Point m = Point::Zero();
    if (k < dim) {
      m(k) = 1.0;
    } else if constexpr (dim == 2) {
      m = Point(-x(1), x(0));
    } else {
      m = Eigen::Vector3d::Unit(k - dim).cross(Eigen::Vector3d(x));
    }
    return m;
  }

 private:
  const MeshOf<dim>& mesh_;
  Point centre_ = Point::Zero();
};

}  // namespace hemivem
