// Polygonal meshes: vertices, counter-clockwise elements with any number of
// vertices, edges with the elements on each side, element geometry.
//
// A Mesh is valid by construction: the constructor checks every rule of
// find_mesh_defects() and throws MeshError naming the first offending element.
#pragma once

#include <Eigen/Core>

#include <array>
#include <map>
#include <span>
#include <string>
#include <vector>

#include <hemivem/error.hpp>

namespace hemivem {

using Vec2 = Eigen::Vector2d;

/// An edge of the mesh. It runs v0 -> v1 in element `left` (counter-clockwise),
/// and v1 -> v0 in element `right`; `right` is -1 on the boundary.
struct MeshEdge {
  int v0 = -1;
  int v1 = -1;
  int left = -1;
  int right = -1;
  bool on_boundary() const noexcept { return right < 0; }
};

/// Axis-aligned rectangle [x0,x1] x [y0,y1].
struct Rectangle {
  double x0 = 0.0, x1 = 1.0, y0 = 0.0, y1 = 1.0;
  double width() const noexcept { return x1 - x0; }
  double height() const noexcept { return y1 - y0; }
};

/// One violation of the mesh rules, tied to an element (or -1 for the mesh as a whole).
struct MeshDefect {
  int element = -1;
  std::string message;
};

/// The largest coordinate magnitude of a mesh vertex: squared lengths and areas of
/// elements, products of two coordinate differences, stay finite in double precision.
inline constexpr double max_mesh_coordinate = 1e150;

/// Every rule a polygonal mesh must satisfy, checked in this order, reporting the first
/// violation found per element (and global violations with element -1):
///   at least one vertex and one element; finite coordinates of magnitude at most
///   max_mesh_coordinate; at least 3 vertices per
///   element; vertex indices in range; no vertex repeated in an element; positive signed
///   area (counter-clockwise orientation; zero area is its own defect); no
///   self-intersection (exact predicates); an area that is a normal double (not below
///   DBL_MIN, which coordinates of about 1e-154 and less give); conformity: each edge in at most two elements
///   and with opposite directions when in two; no hanging vertex (a vertex lying inside
///   a boundary edge it does not belong to).
/// Edges of any positive length, including ~1e-13, are legal. `bodies` (optional, one per
/// vertex) numbers the bodies of a mesh of several (hemivem/mesh/bodies.hpp): vertices of
/// different bodies may coincide, and one body's vertex may lie on another's boundary edge.
std::vector<MeshDefect> find_mesh_defects(const std::vector<Vec2>& vertices,
                                          const std::vector<std::vector<int>>& elements,
                                          std::size_t max_defects = 20, const std::vector<int>& bodies = {});

class Mesh {
 public:
  Mesh() = default;
  /// Builds and validates a mesh; throws MeshError naming the first defect.
  /// `regions` (optional) gives a material region id per element (default 0); `bodies`
  /// (optional) the body of each vertex of a mesh of several bodies (find_mesh_defects).
  Mesh(std::vector<Vec2> vertices, std::vector<std::vector<int>> elements,
       std::vector<int> regions = {}, const std::vector<int>& bodies = {});

  int num_vertices() const noexcept { return static_cast<int>(vertices_.size()); }
  int num_elements() const noexcept { return static_cast<int>(offsets_.empty() ? 0 : offsets_.size() - 1); }
  int num_edges() const noexcept { return static_cast<int>(edges_.size()); }

  const Vec2& vertex(int i) const { return vertices_[static_cast<std::size_t>(i)]; }
  const std::vector<Vec2>& vertices() const noexcept { return vertices_; }

  /// Vertex indices of element e, counter-clockwise.
  std::span<const int> element(int e) const {
    return {element_vertices_.data() + offsets_[e], static_cast<std::size_t>(offsets_[e + 1] - offsets_[e])};
  }
  int element_size(int e) const { return offsets_[e + 1] - offsets_[e]; }
  /// Edge ids of element e; local edge i runs from local vertex i to i+1.
  std::span<const int> element_edges(int e) const {
    return {element_edges_.data() + offsets_[e], static_cast<std::size_t>(offsets_[e + 1] - offsets_[e])};
  }
  std::vector<std::vector<int>> elements() const;

  const std::vector<MeshEdge>& edges() const noexcept { return edges_; }
  const MeshEdge& edge(int i) const { return edges_[static_cast<std::size_t>(i)]; }
  double edge_length(int i) const;
  /// Edges that belong to exactly one element, in edge-id order.
  const std::vector<int>& boundary_edges() const noexcept { return boundary_edges_; }
  /// End points of the boundary edges, sorted.
  std::vector<int> boundary_vertices() const;

  double area(int e) const { return area_[e]; }
  Vec2 centroid(int e) const { return centroid_[e]; }
  /// Largest distance between two vertices of the element.
  double diameter(int e) const { return diameter_[e]; }
  /// Largest element diameter.
  double h() const noexcept { return h_; }
  double min_edge_length() const;
  double total_area() const;
  Rectangle bounding_box() const;

  /// Named sets of edges (e.g. the physical groups of a Gmsh file): boundary parts can be
  /// chosen by name. set_edge_group throws InputError for an edge id out of range;
  /// edge_group throws InputError listing the known names for an unknown one.
  void set_edge_group(const std::string& name, std::vector<int> edges);
  const std::vector<int>& edge_group(const std::string& name) const;
  const std::map<std::string, std::vector<int>>& edge_groups() const noexcept { return edge_groups_; }

  /// The vocabulary of a mesh of either dimension (MeshOf<dim>): cells (the elements),
  /// facets (the edges) and the vertices of a facet.
  int num_cells() const noexcept { return num_elements(); }
  int num_facets() const noexcept { return num_edges(); }
  std::array<int, 2> facet_vertices(int f) const { return {edge(f).v0, edge(f).v1}; }
  const std::vector<int>& boundary_facets() const noexcept { return boundary_edges_; }

  int region(int e) const { return regions_[e]; }
  const std::vector<int>& regions() const noexcept { return regions_; }
  void set_regions(std::vector<int> regions);

 private:
  std::vector<Vec2> vertices_;
  std::vector<int> offsets_;           // CSR of elements: offsets_[e]..offsets_[e+1]
  std::vector<int> element_vertices_;  // vertex ids
  std::vector<int> element_edges_;     // edge ids, same layout
  std::vector<MeshEdge> edges_;
  std::vector<int> boundary_edges_;
  std::vector<double> area_;
  std::vector<Vec2> centroid_;
  std::vector<double> diameter_;
  std::vector<int> regions_;
  std::map<std::string, std::vector<int>> edge_groups_;
  double h_ = 0.0;
};

/// Signed area of a polygon given by its vertices in order (positive when counter-clockwise).
double signed_area(std::span<const Vec2> polygon);

}  // namespace hemivem
