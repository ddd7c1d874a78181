// Reading and writing meshes in the plain `.poly2d` format (docs/reference/poly2d.md):
//
//   # comment lines start with '#'; blank lines are ignored
//   vertices NV
//   x y                  (NV lines)
//   elements NE
//   k i1 ... ik          (NE lines, 0-based, counter-clockwise)
//   boundary NB          (optional)
//   i                    (NB lines)
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh_piece.hpp>

namespace hemivem {

struct Poly2dMesh {
  Mesh mesh;
  /// The optional `boundary` list of the file, as written (informational only: the
  /// boundary of a Mesh is always the set of edges that belong to one element).
  std::vector<int> boundary_list;
  /// Comment lines of the file, without the leading '#'.
  std::vector<std::string> comments;
};

/// Reads and validates a .poly2d file. Every violation (syntax, counts, index
/// ranges, non-finite coordinates, any rule of find_mesh_defects) throws InputError
/// (MeshError for mesh rules) whose where() is "path:line" and whose message names the
/// element or vertex concerned.
Poly2dMesh read_poly2d(const std::filesystem::path& path);
/// The same from a stream; `name` is used in messages in place of a path.
Poly2dMesh read_poly2d(std::istream& in, const std::string& name);

/// The piece of a .poly2d file's mesh that process `rank` of `size` keeps, read without making
/// the whole mesh, by read_gmsh_piece's rule (hemivem/mesh/mesh_piece.hpp; the file has no
/// groups or regions). The file's errors are read_poly2d's; a defect of the elements, those the
/// piece shows, named as read_poly2d names the whole mesh's first.
MeshPieceRead<Mesh> read_poly2d_piece(const std::filesystem::path& path, int rank, int size, HeldPoints held = {},
                                      const BoundaryPick<Mesh>& pick = {});
MeshPieceRead<Mesh> read_poly2d_piece(std::istream& in, const std::string& name, int rank, int size,
                                      HeldPoints held = {});
/// Collective over `processes`: this process's piece, as read_poly2d_piece reads process rank() of
/// size()'s, with the file read by the first process alone and every piece made there in turn
/// from one reading and sent to its process (as read_gmsh3d_piece across processes).
MeshPieceRead<Mesh> read_poly2d_piece(const std::filesystem::path& path, const RowDistribution& processes, HeldPoints held = {},
                                      const BoundaryPick<Mesh>& pick = {});

/// The .poly2d file's mesh as lists (MeshLists) of which a process makes the piece around any
/// of its vertices, by read_poly2d_piece's rule (read_gmsh_lists).
MeshLists<Mesh> read_poly2d_lists(const std::filesystem::path& path);
MeshLists<Mesh> read_poly2d_lists(std::istream& in, const std::string& name);

/// Writes a mesh (coordinates with %.17g, so they read back to the same doubles),
/// the boundary vertex list, and the given comment lines. The file is written to a
/// temporary name in the same folder and renamed, so no partial file is left behind.
void write_poly2d(const std::filesystem::path& path, const Mesh& mesh,
                  const std::vector<std::string>& comments = {});
void write_poly2d(std::ostream& out, const Mesh& mesh, const std::vector<std::string>& comments = {});

}  // namespace hemivem
