// Gmsh files as scenes meet them: telling a file of a solid (volume elements, read by read_gmsh3d
// of hemivem/mesh/gmsh3d.hpp) from one of a plane body (read by read_gmsh).
#pragma once

#include <filesystem>

namespace hemivem {

/// 3 when the Gmsh 4.1 ASCII file `path` has an element block of dimension 3 (volume elements)
/// in its $Elements section, else 2 (also when it is not a regular file, cannot be read or is not
/// such a file: the two-dimensional reader then says what is wrong with it). Reads the lines up
/// to the end of $Elements, looking only at section headers and block headers.
int gmsh_file_dimension(const std::filesystem::path& path);

}  // namespace hemivem
