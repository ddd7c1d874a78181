// Helpers shared by the test programs.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace hemivem::test {

/// The shared folder (meshes, paper), or an empty path when it is absent.
std::filesystem::path shared_dir();
/// The *.poly2d files under shared/meshes, sorted; empty when shared/ is absent.
std::vector<std::filesystem::path> shared_meshes();
/// tests/data
std::filesystem::path data_dir();

}  // namespace hemivem::test
