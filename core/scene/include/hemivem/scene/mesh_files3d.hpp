// Gmsh files of solid domains as scenes and the command meet them: telling a file of volume
// elements from one of surfaces, and reading and writing 3D meshes (hemivem/mesh/gmsh3d.hpp)
// where this build has that reader and writer.
#pragma once

#include <filesystem>

#include <hemivem/mesh/mesh3d.hpp>

namespace hemivem {

/// Whether this build reads and writes three-dimensional Gmsh files (read_gmsh3d, write_gmsh3d).
bool gmsh3d_built();

/// 3 when the Gmsh 4.1 ASCII file `path` has an element block of dimension 3 (volume elements)
/// in its $Elements section, else 2 (also when it is not a regular file, cannot be read or is not
/// such a file: the two-dimensional reader then says what is wrong with it). Reads the lines up
/// to the end of $Elements, looking only at section headers and block headers.
int gmsh_file_dimension(const std::filesystem::path& path);

/// read_gmsh3d(path); an InputError naming the file when this build has no 3D Gmsh reader.
Mesh3D read_mesh3d_file(const std::filesystem::path& path);

/// write_gmsh3d(mesh, ...) into `path`, written atomically (write_file_atomically: a failure
/// leaves no half-written file); an InputError naming the file when this build has no 3D Gmsh
/// writer.
void write_mesh3d_file(const Mesh3D& mesh, const std::filesystem::path& path);

}  // namespace hemivem
