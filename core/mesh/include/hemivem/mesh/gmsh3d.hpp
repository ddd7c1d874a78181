// Reading and writing Gmsh meshes (.msh, format 4.1 ASCII) of solid domains
// (docs/three-dimensions.md).
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>

#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/mesh/mesh_piece.hpp>

namespace hemivem {

/// Reads a 3D Gmsh 4.1 ASCII mesh: its volume elements (4-node tetrahedra, 8-node hexahedra,
/// 6-node prisms, 5-node pyramids) become the cells, each face oriented outward; the cell region
/// is the tag of the element's volume physical group (0 when there is none); every 2D physical
/// group (a physical surface) becomes a named face group (Mesh3D::face_group) holding the mesh
/// faces on its surfaces, by its name when the file names it (else its tag as text). Throws
/// InputError naming the file and line of any defect.
Mesh3D read_gmsh3d(const std::filesystem::path& path);
/// The same from a stream; `name` is used in messages in place of a path.
Mesh3D read_gmsh3d(std::istream& in, const std::string& name);

/// The piece of the file's mesh (as read_gmsh3d reads it) that process `rank` of `size` keeps
/// (MeshPieceRead), made without making the whole mesh: the file is read whole, its elements
/// kept as lists of nodes, and only the piece's cells become a mesh. The errors of read_gmsh3d
/// that the piece's cells or the file's elements show; a defect of cells outside the piece is
/// another process's to find. The piece holds the cells around the vertex nearest each of the
/// points `held` (read_gmsh_piece). Given `pick`, a mesh of one connected body holds of its
/// boundary and groups the cells of the facets it picks alone (BoundaryPick).
MeshPieceRead<Mesh3D> read_gmsh3d_piece(const std::filesystem::path& path, int rank, int size, HeldPoints held = {},
                                        const BoundaryPick<Mesh3D>& pick = {});
MeshPieceRead<Mesh3D> read_gmsh3d_piece(std::istream& in, const std::string& name, int rank, int size,
                                        HeldPoints held = {});
/// Collective over `processes`: this process's piece of the file's mesh, as read_gmsh3d_piece
/// reads process rank() of size()'s, with the file read by the first process alone. It reads
/// the file once and chooses every process's piece in turn from that reading (the facets its
/// elements share found once), each sent to its process as the lists its mesh is made of
/// (PieceLists), and each process makes its own piece's mesh; the other processes never open
/// the file, and hold their piece alone. A defect of the file is found by the first, a defect
/// of the cells by the processes whose pieces hold it and named by the first as read_gmsh3d
/// names it; the first throws that error, every other process InputError "process 0 stopped:
/// <that error>" (piece_made_by_first).
MeshPieceRead<Mesh3D> read_gmsh3d_piece(const std::filesystem::path& path, const RowDistribution& processes,
                                        HeldPoints held = {}, const BoundaryPick<Mesh3D>& pick = {});

/// The file's mesh (as read_gmsh3d reads it) as lists (MeshLists) of which a process makes the
/// piece around any of its vertices, by read_gmsh3d_piece's rule (read_gmsh_lists).
MeshLists<Mesh3D> read_gmsh3d_lists(const std::filesystem::path& path);
MeshLists<Mesh3D> read_gmsh3d_lists(std::istream& in, const std::string& name);

/// Writes a Gmsh 4.1 ASCII mesh that read_gmsh3d reads back to the same mesh: tetrahedra,
/// hexahedra, prisms and pyramids (with the vertex orders Gmsh uses); each region a volume
/// physical group; each face group a physical surface by its name. InputError for a cell of
/// another shape (a Voronoi polyhedron: Gmsh has no polyhedron element) naming it.
void write_gmsh3d(const Mesh3D& mesh, std::ostream& out);
void write_gmsh3d(const Mesh3D& mesh, const std::filesystem::path& path);

}  // namespace hemivem
