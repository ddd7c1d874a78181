// The text of the default scene, scenes/paper-example-4.1.toml, embedded when the library is
// built (core/CMakeLists.txt generates its definition from the file).
#pragma once

#include <string_view>

namespace hemivem::detail {

/// The content of scenes/paper-example-4.1.toml at build time.
std::string_view default_scene_text();

}  // namespace hemivem::detail
