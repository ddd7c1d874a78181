// Where one body lies in a mesh of several.
#pragma once

#include <string>

namespace hemivem {

/// One body of a mesh of several (a scene's [[body]]): its name, and its vertices and cells, each
/// a consecutive range of the mesh's; its cells' regions are its own shifted by first_region.
struct BodyRange {
  std::string name;
  int first_vertex = 0, vertices = 0;
  int first_cell = 0, cells = 0;
  int first_region = 0;
  bool has_vertex(int v) const noexcept { return v >= first_vertex && v < first_vertex + vertices; }
  bool operator==(const BodyRange&) const = default;
};

}  // namespace hemivem
