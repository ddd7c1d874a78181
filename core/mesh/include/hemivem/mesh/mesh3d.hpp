// Polyhedral meshes: vertices, planar polygonal faces, cells bounded by faces (any number of
// faces, convex or not), with the cells on each side of a face and the geometry of faces and
// cells (docs/three-dimensions.md).
//
// A Mesh3D is valid by construction: the constructor checks every rule of
// find_mesh3d_defects() and throws MeshError naming the first offending cell (or face).
#pragma once

#include <Eigen/Core>
#include <Eigen/Geometry>

#include <functional>
#include <map>
#include <span>
#include <string>
#include <vector>

#include <hemivem/error.hpp>

namespace hemivem {

using Vec3 = Eigen::Vector3d;

/// Axis-aligned box [x0,x1] x [y0,y1] x [z0,z1].
struct Box {
  double x0 = 0.0, x1 = 1.0, y0 = 0.0, y1 = 1.0, z0 = 0.0, z1 = 1.0;
  double size(int axis) const noexcept { return axis == 0 ? x1 - x0 : axis == 1 ? y1 - y0 : z1 - z0; }
  double lower(int axis) const noexcept { return axis == 0 ? x0 : axis == 1 ? y0 : z0; }
  double upper(int axis) const noexcept { return axis == 0 ? x1 : axis == 1 ? y1 : z1; }
};

/// A cell given by its faces, each a loop of vertex ids, counter-clockwise seen from outside
/// the cell (its normal by the right-hand rule points out of the cell).
using CellFaces = std::vector<std::vector<int>>;

/// A face of the mesh. Its vertex loop is counter-clockwise seen from outside `inner` (the
/// normal points from `inner` to `outer`); `outer` is -1 on the boundary.
struct MeshFace {
  std::vector<int> vertices;
  int inner = -1;
  int outer = -1;
  bool on_boundary() const noexcept { return outer < 0; }
};

/// One violation of the mesh rules, tied to a cell (or -1 for the mesh as a whole or a face).
struct Mesh3DDefect {
  int cell = -1;
  std::string message;
};

/// How far a vertex of a face may lie off the face's plane, relative to the face's diameter.
inline constexpr double face_planarity_tolerance = 1e-8;

/// Every rule a polyhedral mesh must satisfy, reporting the first violation found per cell
/// (and global violations with cell -1):
///   at least one vertex and one cell; finite coordinates of magnitude at most 1e100; at least 4
///   faces per cell and 3 vertices per face; vertex indices in range; no vertex repeated in a
///   face; each face planar within face_planarity_tolerance of its diameter and of positive
///   area; a closed cell (each edge of its faces used once in each direction: the faces are
///   consistently oriented); positive volume (outward orientation; zero volume is its own
///   defect); conformity: each face (as a set of vertices) in at most two cells, with
///   opposite orientations when in two; no hanging vertex (a vertex lying inside an edge of a
///   boundary face it does not belong to: every boundary edge in exactly two boundary faces).
std::vector<Mesh3DDefect> find_mesh3d_defects(const std::vector<Vec3>& vertices, const std::vector<CellFaces>& cells,
                                              std::size_t max_defects = 20);

class Mesh3D {
 public:
  Mesh3D() = default;
  /// Builds and validates a mesh; throws MeshError naming the first defect. A face shared by
  /// two cells is given by both (with opposite orientations) and stored once. `regions`
  /// (optional) gives a material region id per cell (default 0).
  Mesh3D(std::vector<Vec3> vertices, std::vector<CellFaces> cells, std::vector<int> regions = {});

  int num_vertices() const noexcept { return static_cast<int>(vertices_.size()); }
  int num_cells() const noexcept { return static_cast<int>(cell_faces_.size()); }
  int num_faces() const noexcept { return static_cast<int>(faces_.size()); }

  const Vec3& vertex(int i) const { return vertices_[static_cast<std::size_t>(i)]; }
  const std::vector<Vec3>& vertices() const noexcept { return vertices_; }

  const MeshFace& face(int f) const { return faces_[static_cast<std::size_t>(f)]; }
  const std::vector<MeshFace>& faces() const noexcept { return faces_; }
  /// Face ids of cell c.
  const std::vector<int>& cell_faces(int c) const { return cell_faces_[static_cast<std::size_t>(c)]; }
  /// The sorted vertex ids of cell c.
  const std::vector<int>& cell_vertices(int c) const { return cell_vertices_[static_cast<std::size_t>(c)]; }
  /// Cell c's faces as loops of vertex ids, each counter-clockwise seen from outside c.
  CellFaces cell(int c) const;
  /// Cell c's faces as loops of positions in cell_vertices(c), outward as cell().
  std::vector<std::vector<int>> local_faces(int c) const;
  /// local_faces(c) into `faces`, whose vectors keep their capacity (no allocation once they
  /// have grown to the cell's size).
  void local_faces(int c, std::vector<std::vector<int>>& faces) const;

  /// Faces in exactly one cell, in face-id order.
  const std::vector<int>& boundary_faces() const noexcept { return boundary_faces_; }
  /// The vertices of the boundary faces, sorted.
  std::vector<int> boundary_vertices() const;

  double volume(int c) const { return volume_[static_cast<std::size_t>(c)]; }
  Vec3 centroid(int c) const { return centroid_[static_cast<std::size_t>(c)]; }
  /// Largest distance between two vertices of the cell.
  double diameter(int c) const { return diameter_[static_cast<std::size_t>(c)]; }
  /// Largest cell diameter.
  double h() const noexcept { return h_; }
  double total_volume() const;
  Box bounding_box() const;

  /// Area, centroid and unit normal (pointing out of face(f).inner) of face f.
  double face_area(int f) const { return face_area_[static_cast<std::size_t>(f)]; }
  Vec3 face_centroid(int f) const { return face_centroid_[static_cast<std::size_t>(f)]; }
  Vec3 face_normal(int f) const { return face_normal_[static_cast<std::size_t>(f)]; }

  /// Named sets of faces (e.g. the physical surfaces of a Gmsh file). set_face_group throws
  /// InputError for a face id out of range; face_group throws InputError listing the known
  /// names for an unknown one.
  void set_face_group(const std::string& name, std::vector<int> faces);
  const std::vector<int>& face_group(const std::string& name) const;
  const std::map<std::string, std::vector<int>>& face_groups() const noexcept { return face_groups_; }

  /// The vocabulary of a mesh of either dimension (MeshOf<dim>): cells, facets (the faces)
  /// and the vertices of a facet.
  int num_facets() const noexcept { return num_faces(); }
  const std::vector<int>& facet_vertices(int f) const { return face(f).vertices; }
  const std::vector<int>& boundary_facets() const noexcept { return boundary_faces_; }

  int region(int c) const { return regions_[static_cast<std::size_t>(c)]; }
  const std::vector<int>& regions() const noexcept { return regions_; }
  void set_regions(std::vector<int> regions);

 private:
  std::vector<Vec3> vertices_;
  std::vector<MeshFace> faces_;
  std::vector<std::vector<int>> cell_faces_;
  std::vector<std::vector<int>> cell_vertices_;
  std::vector<int> boundary_faces_;
  std::vector<double> volume_, diameter_, face_area_;
  std::vector<Vec3> centroid_, face_centroid_, face_normal_;
  std::vector<int> regions_;
  std::map<std::string, std::vector<int>> face_groups_;
  double h_ = 0.0;
};

/// The Euclidean length of v without overflow or underflow in its squares: sqrt(|v|^2) where
/// |v|^2 is a normal number (bit for bit v.norm()), else computed on v scaled by a power of two,
/// so that lengths from 1e-154 to 1e154 and beyond, and areas of faces of any size the mesh
/// allows, keep full precision.
double scale_free_norm(const Vec3& v);

/// The area vector of a planar polygon, (1/2) sum_i z_i x z_{i+1}: its length is the area and
/// its direction the normal of the counter-clockwise loop.
Vec3 polygon_area_vector(std::span<const Vec3> polygon);
/// The area-weighted centroid of a planar polygon (a fan of triangles from its vertex mean).
Vec3 polygon_centroid(std::span<const Vec3> polygon);

/// Boundary faces (ids) whose every vertex satisfies `keep`.
std::vector<int> select_boundary_faces(const Mesh3D& mesh, const std::function<bool(const Vec3&)>& keep);
/// The boundary faces of a named face group; InputError when the group is unknown or holds a
/// face that is not on the boundary.
std::vector<int> select_boundary_faces(const Mesh3D& mesh, const std::string& group);
/// The boundary faces on a side of a box: "x0" (x = x0), "x1", "y0", "y1", "z0", "z1", and
/// "bottom" (z0) and "top" (z1), within relative_tolerance * the largest side of the box.
/// InputError for any other name.
std::vector<int> select_box_side(const Mesh3D& mesh, const Box& box, const std::string& side,
                                 double relative_tolerance = 1e-8);

}  // namespace hemivem
