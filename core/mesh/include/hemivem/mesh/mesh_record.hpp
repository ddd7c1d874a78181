// A mesh kept as the lists it is made of, and made again from them to the bit: what a process
// holds of a whole mesh while it solves on its piece of it (hemivem/mesh/mesh_piece.hpp).
#pragma once

#include <map>
#include <string>
#include <vector>

#include <hemivem/mesh/dimension.hpp>

namespace hemivem {

/// A mesh of one body (MeshOf<dim>) as the lists it is made of, without what its constructor
/// derives from them: its vertices; a plane's elements as vertex loops, a solid's faces as
/// vertex loops (each as the mesh stores it) and each cell's faces, in flat arrays; the cells'
/// regions and the facet groups. A plane's edges, a solid's cells' vertex lists, and the areas,
/// normals, volumes, centroids and diameters are not kept. make() builds the mesh again, the
/// same to the bit: the same vertices, cells, facets and their numbers, regions, groups and
/// geometry (the constructor numbers the facets in the order the cells first give them, and a
/// facet is given first by the cell that stores it).
template <int dim>
class MeshRecord {
 public:
  explicit MeshRecord(const MeshOf<dim>& mesh);
  /// The mesh recorded. MeshError as its constructor (not for a record of a valid mesh).
  MeshOf<dim> make() const;

 private:
  std::vector<PointOf<dim>> vertices_;
  std::vector<int> loop_start_, loops_;  ///< each element's (plane) or face's (solid) vertex loop
  std::vector<int> cell_start_, cell_faces_;  ///< a solid's cells' faces (empty in the plane)
  std::vector<int> regions_;
  std::map<std::string, std::vector<int>> groups_;  ///< the facet groups
};

}  // namespace hemivem
