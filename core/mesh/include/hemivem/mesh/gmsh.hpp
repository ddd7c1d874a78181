// Reading Gmsh meshes (.msh, format 4.1 ASCII) of plane domains.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>

#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh_piece.hpp>

namespace hemivem {

/// Reads a 2D Gmsh 4.1 ASCII mesh: its surface elements (3-node triangles and 4-node quadrangles;
/// the format has no polygon type) become the mesh's elements, oriented counter-clockwise; the element
/// region is the tag of the element's surface physical group as written in the file (1 ... 1000000;
/// 0 when there is none); every 1D physical group becomes a named edge group
/// (Mesh::edge_group) holding the mesh edges on its lines. Throws InputError naming the
/// file and line of any defect.
Mesh read_gmsh(const std::filesystem::path& path);
/// The same from a stream; `name` is used in messages in place of a path.
Mesh read_gmsh(std::istream& in, const std::string& name);

/// The piece of the file's mesh (as read_gmsh reads it) that process `rank` of `size` keeps
/// (MeshPieceRead), made without making the whole mesh: the file is read whole, its elements
/// kept as lists of vertices, and only the piece's elements become a mesh. The errors of
/// read_gmsh that the piece's elements or the file's elements show; a defect of elements
/// outside the piece is another process's to find. The piece holds the cells around the vertex
/// nearest each of the points `held` (x, y, and z = 0): the vertex a support at that point holds.
/// Given `pick`, a mesh of one connected body holds of its boundary and groups the cells of the
/// facets it picks alone (BoundaryPick).
MeshPieceRead<Mesh> read_gmsh_piece(const std::filesystem::path& path, int rank, int size, HeldPoints held = {},
                                    const BoundaryPick<Mesh>& pick = {});
MeshPieceRead<Mesh> read_gmsh_piece(std::istream& in, const std::string& name, int rank, int size, HeldPoints held = {});
/// Collective over `processes`: this process's piece, as read_gmsh_piece reads process rank() of
/// size()'s, with the file read by the first process alone and every piece made there in turn
/// from one reading and sent to its process (as read_gmsh3d_piece across processes).
MeshPieceRead<Mesh> read_gmsh_piece(const std::filesystem::path& path, const RowDistribution& processes, HeldPoints held = {},
                                    const BoundaryPick<Mesh>& pick = {});

/// The file's mesh (as read_gmsh reads it) as lists (MeshLists) of which a process makes the
/// piece around any of its vertices, by read_gmsh_piece's rule: a body among several each
/// process reads its piece of. The file is read whole once, its errors read_gmsh_piece's; the
/// mesh's, those each piece shows.
MeshLists<Mesh> read_gmsh_lists(const std::filesystem::path& path);
MeshLists<Mesh> read_gmsh_lists(std::istream& in, const std::string& name);

}  // namespace hemivem
