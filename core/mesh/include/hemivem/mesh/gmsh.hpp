// Reading Gmsh meshes (.msh, format 4.1 ASCII) of plane domains.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>

#include <hemivem/mesh/mesh.hpp>

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

}  // namespace hemivem
