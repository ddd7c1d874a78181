// Reader of Gmsh meshes, MSH format 4.1 ASCII (see gmsh.hpp).
//
// Supported subset of the format:
//   * $MeshFormat "4.1 0 <data-size>" (ASCII only; binary files and other versions are
//     rejected with a message saying how to re-export);
//   * $PhysicalNames (optional): "dim tag "name"" lines;
//   * $Entities (optional; Gmsh always writes it): the physical tags of every point, curve
//     and surface entity (volumes are skipped);
//   * $Nodes (required): entity blocks of node tags (any positive tags, not necessarily
//     contiguous) and coordinates "x y z" (plus the parametric coordinates when the block
//     is parametric, which are ignored); z must be 0 up to 1e-10 times the largest |x|, |y|;
//   * $Elements (required): entity blocks of 2-node lines (type 1), 3-node triangles
//     (type 2), 4-node quadrangles (type 3) and points (type 15). Every other type (higher
//     order, volume elements) is rejected naming the type;
//   * any other section ($Comments, $Periodic, $NodeData, ...) is skipped, except
//     $PartitionedEntities (partitioned meshes are rejected).
// The file is read line by line, as Gmsh writes it: one node tag, one coordinate triple and
// one element per line. Blank lines are ignored.
//
// The mesh: the nodes used by surface elements become the vertices, numbered 0, 1, ... in
// their order in $Nodes (nodes used by no surface element, such as the geometry's points,
// are dropped); triangles and quadrangles become the elements in their order in $Elements,
// turned counter-clockwise when given clockwise. The region of an element is the tag of its
// surface physical group as the file writes it (1 ... 1000000; a larger tag is refused); 0
// when its surface has none; when its surface is in several surface groups, the first one
// listed for the surface in $Entities counts. Every 1D physical
// group becomes an edge group named by $PhysicalNames (or by its tag, as a decimal string,
// when unnamed) holding the mesh edges of the line elements of its curves (sorted, without
// repeats); every line element must lie on a mesh edge. Point elements and 0D groups are
// ignored.
//
// As for .poly2d, every count is checked against the lines the file actually holds before
// anything is sized from it, and every error names "path:line".
#include <hemivem/mesh/gmsh.hpp>

#include "cell_topology.hpp"
#include "gmsh_sections.hpp"

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <istream>
#include <map>
#include <memory>
#include <string_view>

namespace hemivem {

namespace fs = std::filesystem;

namespace {

using detail::GmshElement;
using detail::GmshNode;
using text::Line;

std::string unsupported_type_name(long long type) {
  switch (type) {
    case 4: return "4-node tetrahedron";
    case 5: return "8-node hexahedron";
    case 6: return "6-node prism";
    case 7: return "5-node pyramid";
    case 8: return "3-node second-order line";
    case 9: return "6-node second-order triangle";
    case 10: return "9-node second-order quadrangle";
    case 11: return "10-node second-order tetrahedron";
    case 16: return "8-node second-order quadrangle";
    case 20: return "9-node third-order incomplete triangle";
    case 21: return "10-node third-order triangle";
    case 26: return "4-node third-order line";
    default: return "";
  }
}

class GmshReader final : detail::GmshSections {
 public:
  GmshReader(std::istream& in, std::string name)
      : GmshSections(in, std::move(name),
                     {2, max_mesh_coordinate, "1e150 (element areas would overflow)"}) {}

  Mesh read() {
    read_sections();
    check_plane();
    return build();
  }

  /// The pieces `turn` asks for, made in turn from one reading.
  void read_pieces(const detail::PiecesInTurn<Mesh>& turn, HeldPoints held) {
    read_sections();
    check_plane();
    build_pieces(turn, held);
  }

  /// The file read (its sections and checks), its mesh not made: its number of vertices, of
  /// which piece() makes the piece around any.
  int read_lists() {
    read_sections();
    check_plane();
    return vertex_count();
  }

  /// After read_lists: the piece around the vertices `owned` flags (MeshLists::piece).
  MeshPieceRead<Mesh> piece(const std::vector<char>& owned, HeldPoints held) const {
    PieceLists<Mesh> lists;
    build_pieces(detail::piece_of({.owned = &owned}, lists), held);
    return made(std::move(lists));
  }
  /// After read_lists: the lists of the pieces `turn` asks for (MeshLists::pieces).
  void pieces(const detail::PiecesInTurn<Mesh>& turn, HeldPoints held) const { build_pieces(turn, held); }

  /// The piece of `lists` (make_piece), a defect of its elements named as read_gmsh names the
  /// whole mesh's first.
  MeshPieceRead<Mesh> made(PieceLists<Mesh> lists) const {
    return made_piece(std::move(lists), [&] { name_defect(); });
  }

  /// After the file is read: throws the whole mesh's first defect as read_gmsh names it, if it
  /// has one.
  void name_defect() const {
    std::vector<int> vertex_of;
    const std::vector<Vec2> all = surface_vertices(vertex_of);
    (void)surface_mesh(all, surface_elements(all, vertex_of), top_numbers());
  }

 private:
  [[noreturn]] void refuse_element_type(int block, long long type) const override {
    const std::string name = unsupported_type_name(type);
    fail(block, "element type " + std::to_string(type) + (name.empty() ? "" : " (" + name + ")") +
                    " is not supported: only 2-node lines (1), 3-node triangles (2), 4-node quadrangles (3) and "
                    "points (15) are read" +
                    (type == 4 || type == 5 || type == 6 || type == 7 ? " (the mesh must be plane)"
                                                                      : " (save a first-order mesh)"));
  }

  // ---- the mesh

  void check_plane() const {
    double scale = 0.0;
    for (const GmshNode& n : nodes_) scale = std::max({scale, std::abs(n.x), std::abs(n.y)});
    const double tol = 1e-10 * scale;
    for (const GmshNode& n : nodes_)
      if (std::abs(n.z) > tol) {
        char buf[64];
        std::snprintf(buf, sizeof buf, "%.17g", n.z);
        fail(n.line, "node " + std::to_string(n.tag) + " has z = " + buf +
                         ": only plane meshes (z = 0) are read");
      }
  }

  Mesh build() {
    std::vector<int> vertex_of;
    std::vector<Vec2> vertices = surface_vertices(vertex_of);
    std::vector<std::vector<int>> elements = surface_elements(vertices, vertex_of);
    Mesh mesh = surface_mesh(std::move(vertices), std::move(elements), top_numbers());
    add_edge_groups(mesh, vertex_of);
    return mesh;
  }

  /// The lists of the pieces `turn` asks for (PieceLists), made of the surface elements' edges
  /// without the whole mesh, the edges they share found once.
  void build_pieces(const detail::PiecesInTurn<Mesh>& turn, HeldPoints held) const {
    std::vector<int> vertex_of;
    std::vector<Vec2> vertices = surface_vertices(vertex_of);
    std::vector<std::vector<int>> elements = surface_elements(vertices, vertex_of);
    std::vector<int> regions;
    for (std::size_t k = 0; k < elements.size(); ++k) regions.push_back(region_of(top_[k].entity));
    auto cells = std::make_unique<const detail::CellTopology>(
        detail::plane_topology(static_cast<int>(vertices.size()), elements));
    std::vector<int> grouped;  // the edges of the physical lines' elements
    std::vector<GroupedFacet> lines;
    for (const GmshElement& l : below_) {
      const int a = vertex_of[static_cast<std::size_t>(l.nodes[0])], b = vertex_of[static_cast<std::size_t>(l.nodes[1])];
      const int f = a < 0 || b < 0 ? -1 : cells->find_facet({a, b});
      if (f < 0) fail_not_an_edge(l);
      const std::vector<int>* tags = groups_of(l.entity);
      if (tags && !tags->empty()) grouped.push_back(f);
      if (tags) lines.push_back({tags, {std::min(a, b), std::max(a, b)}, cells->facet_cells(f)});
    }
    detail::make_pieces(std::move(cells), vertices, regions, grouped, held, turn,
                        [&](PieceLists<Mesh>& lists, const std::vector<char>& kept, bool last) {
                          lists.cells.reserve(lists.piece.cells.size());
                          for (int c : lists.piece.cells) {
                            auto& e = elements[static_cast<std::size_t>(c)];
                            lists.cells.push_back(last ? std::move(e) : e);
                            lists.regions.push_back(regions[static_cast<std::size_t>(c)]);
                          }
                          lists.groups = piece_groups(lines, kept);  // as add_edge_groups gives them
                          lists.vertices = last ? std::move(vertices) : vertices;
                        });
  }

  /// Vertices: the nodes of surface elements, in $Nodes order; `vertex_of` receives the vertex
  /// of each node (-1 for the others).
  std::vector<Vec2> surface_vertices(std::vector<int>& vertex_of) const {
    vertex_of = vertex_numbers();
    std::vector<Vec2> vertices;
    vertices.reserve(static_cast<std::size_t>(numbered(vertex_of)));
    for (std::size_t i = 0; i < nodes_.size(); ++i)
      if (vertex_of[i] >= 0) vertices.emplace_back(nodes_[i].x, nodes_[i].y);
    return vertices;
  }

  /// The surface elements' vertices, each made counter-clockwise.
  std::vector<std::vector<int>> surface_elements(const std::vector<Vec2>& vertices, const std::vector<int>& vertex_of) const {
    std::vector<std::vector<int>> elements;
    elements.reserve(top_.size());
    for (const GmshElement& s : top_) {
      std::vector<int> e;
      std::vector<Vec2> p;
      for (int n : s.nodes) {
        e.push_back(vertex_of[static_cast<std::size_t>(n)]);
        p.push_back(vertices[static_cast<std::size_t>(e.back())]);
      }
      if (signed_area(p) < 0) std::reverse(e.begin(), e.end());
      elements.push_back(std::move(e));
    }
    return elements;
  }

  /// The mesh of the surface elements `numbers` (increasing; `elements` their vertices), with
  /// the region of each: the tag of its entity's first physical group, as written in the file
  /// (0 without one); a mesh error names the Gmsh element and its line.
  Mesh surface_mesh(std::vector<Vec2> vertices, std::vector<std::vector<int>> elements, const std::vector<int>& numbers) const {
    std::vector<int> regions;
    regions.reserve(numbers.size());
    for (int k : numbers) regions.push_back(region_of(top_[static_cast<std::size_t>(k)].entity));
    try {
      return Mesh(std::move(vertices), std::move(elements), std::move(regions));
    } catch (const MeshError& err) {
      const int c = err.element();
      rethrow_at_element(MeshError(err.detail(), c >= 0 && static_cast<std::size_t>(c) < numbers.size() ? numbers[static_cast<std::size_t>(c)] : -1));
    }
  }

  [[noreturn]] void fail_not_an_edge(const GmshElement& l) const {
    fail(l.line, "line element " + std::to_string(l.tag) + " (nodes " + std::to_string(nodes_[static_cast<std::size_t>(l.nodes[0])].tag) + " " +
                     std::to_string(nodes_[static_cast<std::size_t>(l.nodes[1])].tag) + ") is not an edge of the surface mesh");
  }

  /// The edges of each 1D physical group (by tag), from the line elements of its entities;
  /// a line element that is no edge of the mesh is an error.
  std::map<int, std::vector<int>> group_edges(const Mesh& mesh, const std::vector<int>& vertex_of) const {
    std::map<std::pair<int, int>, int> edge_of;
    for (int i = 0; i < mesh.num_edges(); ++i) {
      const auto& ed = mesh.edge(i);
      edge_of.emplace(std::minmax(ed.v0, ed.v1), i);
    }
    std::map<int, std::vector<int>> group_edges = empty_groups();  // 1D physical tag -> edges
    for (const GmshElement& l : below_) {
      const std::size_t n0 = static_cast<std::size_t>(l.nodes[0]), n1 = static_cast<std::size_t>(l.nodes[1]);
      const int a = vertex_of[n0];
      const int b = vertex_of[n1];
      const auto it = a < 0 || b < 0 ? edge_of.end() : edge_of.find(std::minmax(a, b));
      if (it == edge_of.end()) fail_not_an_edge(l);
      if (const std::vector<int>* tags = groups_of(l.entity))
        for (int t : *tags) group_edges[t].push_back(it->second);
    }
    return group_edges;
  }

  /// Edge groups from the 1D physical groups, named by $PhysicalNames or else by tag.
  void add_edge_groups(Mesh& mesh, const std::vector<int>& vertex_of) const {
    std::map<std::string, int> names;
    for (auto& [tag, edges] : group_edges(mesh, vertex_of)) {
      std::string name = group_name(tag, names);
      std::sort(edges.begin(), edges.end());
      edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
      mesh.set_edge_group(name, std::move(edges));
    }
  }
};

}  // namespace

Mesh read_gmsh(const fs::path& path) {
  std::ifstream in = text::open_for_reading(path, "mesh file");
  return read_gmsh(in, path.string());
}

Mesh read_gmsh(std::istream& in, const std::string& name) {
  return GmshReader(in, name).read();
}

MeshPieceRead<Mesh> read_gmsh_piece(const fs::path& path, int rank, int size, HeldPoints held, const BoundaryPick<Mesh>& pick) {
  std::ifstream in = text::open_for_reading(path, "mesh file");
  return detail::read_own_piece<Mesh, GmshReader>(in, path.string(), rank, size, held, pick);
}

MeshPieceRead<Mesh> read_gmsh_piece(std::istream& in, const std::string& name, int rank, int size, HeldPoints held) {
  return detail::read_own_piece<Mesh, GmshReader>(in, name, rank, size, held);
}

MeshPieceRead<Mesh> read_gmsh_piece(const fs::path& path, const RowDistribution& processes, HeldPoints held,
                                   const BoundaryPick<Mesh>& pick) {
  return detail::read_piece_by_first<Mesh, GmshReader>(path, processes, held, pick);
}

MeshLists<Mesh> read_gmsh_lists(const fs::path& path) {
  std::ifstream in = text::open_for_reading(path, "mesh file");
  return read_gmsh_lists(in, path.string());
}

MeshLists<Mesh> read_gmsh_lists(std::istream& in, const std::string& name) {
  auto reader = std::make_shared<GmshReader>(in, name);
  const int vertices = reader->read_lists();
  return {vertices, [reader](const std::vector<char>& owned, HeldPoints held) { return reader->piece(owned, held); },
          [reader](int size, const std::function<std::vector<char>(int)>& owned, HeldPoints held,
                   const PieceDelivery<Mesh>& deliver) {
            reader->pieces(detail::pieces_around<Mesh>(size, owned, deliver), held);
          },
          [reader] { reader->name_defect(); }};
}

}  // namespace hemivem
