// Reader and writer of 3D Gmsh meshes, MSH format 4.1 ASCII (see gmsh3d.hpp).
//
// Supported subset of the format (as the 2D reader, gmsh.cpp, with volumes):
//   * $MeshFormat "4.1 0 <data-size>" (ASCII only; binary files and other versions are
//     rejected with a message saying how to re-export);
//   * $PhysicalNames (optional): "dim tag "name"" lines;
//   * $Entities (optional; Gmsh always writes it): the physical tags of every point, curve,
//     surface and volume entity;
//   * $Nodes (required): entity blocks of node tags (any positive tags, not necessarily
//     contiguous) and coordinates "x y z" (plus parametric coordinates, ignored);
//   * $Elements (required): entity blocks of 4-node tetrahedra (type 4), 8-node hexahedra (5),
//     6-node prisms (6), 5-node pyramids (7), 3-node triangles (2), 4-node quadrangles (3),
//     2-node lines (1) and points (15). Every other type (higher order, polygons) is rejected
//     naming the type;
//   * any other section is skipped, except $PartitionedEntities (partitioned meshes are
//     rejected).
// The file is read line by line, as Gmsh writes it: one node tag, one coordinate triple and
// one element per line. Blank lines are ignored.
//
// The mesh: the nodes used by volume elements become the vertices, numbered 0, 1, ... in their
// order in $Nodes (nodes of no volume element are dropped); the volume elements become the
// cells in their order in $Elements, their faces taken from Gmsh's node ordering of each type
// and turned outward (all reversed when the element's nodes give a negative volume). The
// region of a cell is the tag of its volume's physical group (1 ... 1000000; the first listed
// for the volume in $Entities when it has several), 0 when the volume has none. Every 2D
// physical group becomes a face group named by $PhysicalNames (or by its tag, as a decimal
// string, when unnamed) holding the mesh faces of the triangles and quadrangles of its
// surfaces, matched by their vertex sets; a surface element of a physical surface that is no
// face of the mesh is an error. Surface elements outside physical surfaces, lines and points
// are ignored.
//
// Every count is checked against the lines the file actually holds before anything is sized
// from it, and every error names "path:line".
#include <hemivem/mesh/gmsh3d.hpp>

#include "cell_topology.hpp"
#include "gmsh_sections.hpp"

#include <hemivem/support/atomic_file.hpp>

#include <algorithm>
#include <charconv>
#include <fstream>
#include <memory>
#include <istream>
#include <map>
#include <ostream>
#include <string_view>
#include <system_error>

namespace hemivem {

namespace fs = std::filesystem;

namespace {

using detail::GmshElement;
using detail::kGmshMaxRegion;
using text::Line;
using text::quote;

// ---- element shapes --------------------------------------------------------------------

/// A Gmsh volume element: its type, node count and faces as loops of its nodes (Gmsh's node
/// ordering), outward for an element of positive orientation.
struct Shape {
  int type = 0;
  const char* name = "";
  std::vector<std::vector<int>> faces;
  int nodes() const {
    int n = 0;
    for (const auto& f : faces)
      for (int v : f) n = std::max(n, v + 1);
    return n;
  }
};

// Gmsh's reference elements: tetrahedron 0 (0,0,0), 1 (1,0,0), 2 (0,1,0), 3 (0,0,1);
// hexahedron 0 ... 3 the bottom square counter-clockwise seen from above, 4 ... 7 above them;
// prism 0, 1, 2 the bottom triangle counter-clockwise seen from above, 3, 4, 5 above them;
// pyramid 0 ... 3 the base counter-clockwise seen from the apex 4.
const Shape kTetrahedron{4, "tetrahedron", {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}}};
const Shape kHexahedron{
    5, "hexahedron", {{0, 3, 2, 1}, {0, 1, 5, 4}, {0, 4, 7, 3}, {1, 2, 6, 5}, {2, 3, 7, 6}, {4, 5, 6, 7}}};
const Shape kPrism{6, "prism", {{0, 2, 1}, {3, 4, 5}, {0, 1, 4, 3}, {0, 3, 5, 2}, {1, 2, 5, 4}}};
const Shape kPyramid{7, "pyramid", {{0, 3, 2, 1}, {0, 1, 4}, {1, 2, 4}, {2, 3, 4}, {3, 0, 4}}};

const Shape* volume_shape(long long type) {
  switch (type) {
    case 4: return &kTetrahedron;
    case 5: return &kHexahedron;
    case 6: return &kPrism;
    case 7: return &kPyramid;
    default: return nullptr;
  }
}

/// " (<its shape>)" of a volume element, as an error names it.
std::string volume_label(const GmshElement& e) { return " (" + std::string(volume_shape(e.type)->name) + ")"; }

std::string unsupported_type_name(long long type) {
  switch (type) {
    case 8: return "3-node second-order line";
    case 9: return "6-node second-order triangle";
    case 10: return "9-node second-order quadrangle";
    case 11: return "10-node second-order tetrahedron";
    case 12: return "27-node second-order hexahedron";
    case 13: return "18-node second-order prism";
    case 14: return "14-node second-order pyramid";
    case 16: return "8-node second-order quadrangle";
    case 17: return "20-node second-order hexahedron";
    case 18: return "15-node second-order prism";
    case 19: return "13-node second-order pyramid";
    case 20: return "9-node third-order incomplete triangle";
    case 21: return "10-node third-order triangle";
    case 26: return "4-node third-order line";
    case 29: return "20-node third-order tetrahedron";
    default: return "";
  }
}

class Gmsh3DReader final : detail::GmshSections {
 public:
  Gmsh3DReader(std::istream& in, std::string name)
      : GmshSections(in, std::move(name), {3, 1e100, "1e100 (cell volumes would overflow)"}) {}

  Mesh3D read() {
    read_volumes();
    return build();
  }

  /// The pieces `turn` asks for, made in turn from one reading.
  void read_pieces(const detail::PiecesInTurn<Mesh3D>& turn, HeldPoints held) {
    read_volumes();
    build_pieces(turn, held);
  }

  /// The file read (its sections and checks), its mesh not made: its number of vertices, of
  /// which piece() makes the piece around any.
  int read_lists() {
    read_volumes();
    return vertex_count();
  }

  /// After read_lists: the piece around the vertices `owned` flags (MeshLists::piece).
  MeshPieceRead<Mesh3D> piece(const std::vector<char>& owned, HeldPoints held) {
    PieceLists<Mesh3D> lists;
    build_pieces(detail::piece_of({.owned = &owned}, lists), held);
    return made(std::move(lists));
  }
  /// After read_lists: the lists of the pieces `turn` asks for (MeshLists::pieces).
  void pieces(const detail::PiecesInTurn<Mesh3D>& turn, HeldPoints held) { build_pieces(turn, held); }

  /// The piece of `lists` (make_piece), a defect of its cells named as read_gmsh3d names the
  /// whole mesh's first.
  MeshPieceRead<Mesh3D> made(PieceLists<Mesh3D> lists) {
    return made_piece(std::move(lists), [&] { name_defect(); }, volume_label);
  }

  /// After the file is read: throws the whole mesh's first defect as read_gmsh3d names it, if
  /// it has one.
  void name_defect() { (void)mesh_of(volume_vertices(), top_numbers()); }

 private:
  /// The file's sections, which must hold volume elements.
  void read_volumes() {
    read_sections();
    if (top_.empty())
      fail(elements_header_, "the file has no volume elements (4-node tetrahedra, 8-node hexahedra, 6-node prisms or "
                             "5-node pyramids): a plane mesh is read by read_gmsh");
  }

  [[noreturn]] void refuse_element_type(int block, long long type) const override {
    const std::string name = unsupported_type_name(type);
    fail(block, "element type " + std::to_string(type) + (name.empty() ? "" : " (" + name + ")") +
                    " is not supported: only 4-node tetrahedra (4), 8-node hexahedra (5), 6-node prisms (6), 5-node "
                    "pyramids (7), 3-node triangles (2), 4-node quadrangles (3), 2-node lines (1) and points (15) are "
                    "read (save a first-order mesh)");
  }

  // ---- the mesh

  Mesh3D build() {
    Mesh3D mesh = mesh_of(volume_vertices(), top_numbers());
    add_face_groups(mesh);
    return mesh;
  }

  /// Vertices: the nodes of volume elements, in $Nodes order (vertex_of_ their numbers).
  std::vector<Vec3> volume_vertices() {
    vertex_of_ = vertex_numbers();
    std::vector<Vec3> vertices;
    vertices.reserve(static_cast<std::size_t>(numbered(vertex_of_)));
    for (std::size_t i = 0; i < nodes_.size(); ++i)
      if (vertex_of_[i] >= 0) vertices.emplace_back(nodes_[i].x, nodes_[i].y, nodes_[i].z);
    return vertices;
  }

  /// The mesh of every vertex and the volume elements `elements` (increasing); a mesh error
  /// names the Gmsh element and its line.
  Mesh3D mesh_of(std::vector<Vec3> vertices, const std::vector<int>& elements) const {
    std::vector<CellFaces> cells;
    std::vector<int> regions;
    cells.reserve(elements.size());
    regions.reserve(elements.size());
    for (int k : elements) {
      const GmshElement& e = top_[static_cast<std::size_t>(k)];
      cells.push_back(cell_of(e, vertices));
      regions.push_back(region_of(e.entity));
    }
    try {
      return Mesh3D(std::move(vertices), std::move(cells), std::move(regions));
    } catch (const MeshError& err) {
      const int c = err.element();
      rethrow_at_element(MeshError(err.detail(), c >= 0 && static_cast<std::size_t>(c) < elements.size() ? elements[static_cast<std::size_t>(c)] : -1),
                         volume_label);
    }
  }

  /// The lists of the pieces `turn` asks for (PieceLists), made of the volume elements' faces
  /// without the whole mesh, the facets they share found once.
  void build_pieces(const detail::PiecesInTurn<Mesh3D>& turn, HeldPoints held) {
    std::vector<Vec3> vertices = volume_vertices();
    // each element's corners, its vertices in Gmsh's order, its faces its shape's
    detail::CellShapes shapes;
    std::vector<int> shape_of_type(8, -1), shape_of, corner_start{0}, corners, regions;
    std::size_t num_corners = 0;
    for (const GmshElement& e : top_) num_corners += e.nodes.size();
    shape_of.reserve(top_.size());
    corner_start.reserve(top_.size() + 1);
    corners.reserve(num_corners);
    regions.reserve(top_.size());
    for (const GmshElement& e : top_) {
      int& shape = shape_of_type[static_cast<std::size_t>(e.type)];
      if (shape < 0) shape = shapes.add(volume_shape(e.type)->faces);
      shape_of.push_back(shape);
      for (int n : e.nodes) corners.push_back(vertex_of_[static_cast<std::size_t>(n)]);
      corner_start.push_back(static_cast<int>(corners.size()));
      regions.push_back(region_of(e.entity));
    }
    auto cells = std::make_unique<const detail::CellTopology>(3, static_cast<int>(vertices.size()), std::move(shapes),
                                                              std::move(shape_of), std::move(corner_start),
                                                              std::move(corners));
    std::vector<int> grouped;  // the faces of the physical surfaces' elements
    std::vector<GroupedFacet> faces;
    for (const GmshElement& s : below_)
      if (const std::vector<int>* tags = groups_of(s.entity); tags && !tags->empty()) {
        std::vector<int> key = vertices_of_element(s);
        const int f = std::find(key.begin(), key.end(), -1) != key.end() ? -1 : cells->find_facet(key);
        if (f < 0) fail_not_a_face(s);
        grouped.push_back(f);
        std::sort(key.begin(), key.end());
        faces.push_back({tags, std::move(key), cells->facet_cells(f)});
      }
    // whether each element's faces are reversed, found once for the pieces that hold it
    std::vector<signed char> reversed(top_.size(), -1);
    detail::make_pieces(std::move(cells), vertices, regions, grouped, held, turn,
                        [&](PieceLists<Mesh3D>& lists, const std::vector<char>& kept, bool last) {
                          lists.cells.reserve(lists.piece.cells.size());
                          lists.regions.reserve(lists.piece.cells.size());
                          for (int k : lists.piece.cells) {
                            const GmshElement& e = top_[static_cast<std::size_t>(k)];
                            lists.cells.push_back(cell_of(e, vertices, &reversed[static_cast<std::size_t>(k)]));
                            lists.regions.push_back(regions[static_cast<std::size_t>(k)]);
                          }
                          lists.groups = piece_groups(faces, kept);  // as add_face_groups gives them
                          lists.vertices = last ? std::move(vertices) : vertices;
                        });
  }

  /// The faces of a volume element, outward: as Gmsh's node ordering gives them, all reversed
  /// when its volume is negative. Given `reversed` (-1: not yet known), whether they are is
  /// read from it, or found and kept there.
  CellFaces cell_of(const GmshElement& e, const std::vector<Vec3>& vertices, signed char* reversed = nullptr) const {
    CellFaces faces;
    for (const auto& f : volume_shape(e.type)->faces) {
      std::vector<int> loop;
      for (int k : f) loop.push_back(vertex_of_[static_cast<std::size_t>(e.nodes[static_cast<std::size_t>(k)])]);
      faces.push_back(std::move(loop));
    }
    signed char found = -1;
    if (reversed == nullptr) reversed = &found;
    if (*reversed < 0) {
      const Vec3& o = vertices[static_cast<std::size_t>(faces[0][0])];
      double volume = 0.0;
      std::vector<Vec3> z;
      for (const auto& loop : faces) {
        z.clear();
        for (int v : loop) z.push_back(vertices[static_cast<std::size_t>(v)] - o);
        volume += polygon_area_vector(z).dot(polygon_centroid(z));
      }
      *reversed = volume < 0.0 ? 1 : 0;
    }
    if (*reversed == 1)
      for (auto& loop : faces) std::reverse(loop.begin(), loop.end());
    return faces;
  }

  /// The vertices of an element's nodes (-1 for a node of no volume element).
  std::vector<int> vertices_of_element(const GmshElement& s) const {
    std::vector<int> key;
    for (int n : s.nodes) key.push_back(vertex_of_[static_cast<std::size_t>(n)]);
    return key;
  }

  [[noreturn]] void fail_not_a_face(const GmshElement& s) const {
    std::string node_tags;
    for (int n : s.nodes) {
      node_tags += ' ';
      node_tags += std::to_string(nodes_[static_cast<std::size_t>(n)].tag);
    }
    fail(s.line, "surface element " + std::to_string(s.tag) + " (nodes" + node_tags +
                     ") of a physical surface is not a face of the volume mesh");
  }

  /// Face groups from the 2D physical groups, named by $PhysicalNames or else by tag.
  void add_face_groups(Mesh3D& mesh) const {
    std::map<std::vector<int>, int> face_of;  // sorted vertices -> face
    for (int f = 0; f < mesh.num_faces(); ++f) {
      std::vector<int> key = mesh.face(f).vertices;
      std::sort(key.begin(), key.end());
      face_of.emplace(std::move(key), f);
    }
    std::map<int, std::vector<int>> group_faces = empty_groups();  // 2D physical tag -> faces
    for (const GmshElement& s : below_) {
      const std::vector<int>* tags = groups_of(s.entity);
      if (!tags || tags->empty()) continue;
      std::vector<int> key = vertices_of_element(s);
      std::sort(key.begin(), key.end());
      const auto it = std::find(key.begin(), key.end(), -1) != key.end() ? face_of.end() : face_of.find(key);
      if (it == face_of.end()) fail_not_a_face(s);
      for (int t : *tags) group_faces[t].push_back(it->second);
    }
    std::map<std::string, int> names;
    for (auto& [tag, faces] : group_faces) mesh.set_face_group(group_name(tag, names), std::move(faces));
  }

  std::vector<int> vertex_of_;
};

// ---- writing ---------------------------------------------------------------------------

/// A cell's nodes in Gmsh's order for its shape, or an empty list when the cell is no
/// tetrahedron, hexahedron, prism or pyramid.
struct GmshCell {
  const Shape* shape = nullptr;
  std::vector<int> nodes;
};

/// True when `loop` is a rotation of `ref`.
bool same_loop(const std::vector<int>& loop, const std::vector<int>& ref) {
  if (loop.size() != ref.size()) return false;
  const auto at = std::find(loop.begin(), loop.end(), ref[0]);
  if (at == loop.end()) return false;
  const std::size_t s = static_cast<std::size_t>(at - loop.begin()), n = loop.size();
  for (std::size_t i = 0; i < n; ++i)
    if (loop[(s + i) % n] != ref[i]) return false;
  return true;
}

/// True when the faces of `shape` on `nodes` are exactly the faces of the cell (as oriented loops).
bool matches(const Shape& shape, const std::vector<int>& nodes, const CellFaces& faces) {
  if (faces.size() != shape.faces.size()) return false;
  std::vector<char> used(faces.size(), 0);
  for (const auto& f : shape.faces) {
    std::vector<int> ref;
    for (int k : f) ref.push_back(nodes[static_cast<std::size_t>(k)]);
    bool found = false;
    for (std::size_t i = 0; i < faces.size() && !found; ++i)
      if (!used[i] && same_loop(faces[i], ref)) used[i] = found = true;
    if (!found) return false;
  }
  return true;
}

GmshCell gmsh_cell(const CellFaces& faces) {
  int triangles = 0, quads = 0;
  for (const auto& f : faces) {
    triangles += f.size() == 3 ? 1 : 0;
    quads += f.size() == 4 ? 1 : 0;
  }
  const int n = static_cast<int>(faces.size());
  // the neighbour of v (along an edge of the cell) that is not in `face`
  auto across = [&](int v, const std::vector<int>& face) {
    int found = -1;
    for (const auto& f : faces)
      for (std::size_t k = 0; k < f.size(); ++k) {
        const int a = f[k], b = f[(k + 1) % f.size()];
        const int w = a == v ? b : b == v ? a : -1;
        if (w >= 0 && std::find(face.begin(), face.end(), w) == face.end()) {
          if (found >= 0 && found != w) return -2;
          found = w;
        }
      }
    return found;
  };
  auto first_of_size = [&](std::size_t size) -> const std::vector<int>& {
    return *std::find_if(faces.begin(), faces.end(), [&](const auto& f) { return f.size() == size; });
  };
  GmshCell out;
  if (n == 4 && triangles == 4) {
    // the first face (a, b, c) is Gmsh's face (0, 2, 1); node 3 is the other vertex
    const auto& f = faces[0];
    int d = -1;
    for (int v : faces[1])
      if (std::find(f.begin(), f.end(), v) == f.end()) d = v;
    out = {&kTetrahedron, {f[0], f[2], f[1], d}};
  } else if (n == 6 && quads == 6) {
    const auto& f = faces[0];  // Gmsh's face (0, 3, 2, 1)
    const std::vector<int> bottom{f[0], f[3], f[2], f[1]};
    out = {&kHexahedron, bottom};
    for (int v : bottom) out.nodes.push_back(across(v, f));
  } else if (n == 5 && triangles == 2 && quads == 3) {
    const auto& f = first_of_size(3);  // Gmsh's face (0, 2, 1)
    const std::vector<int> bottom{f[0], f[2], f[1]};
    out = {&kPrism, bottom};
    for (int v : bottom) out.nodes.push_back(across(v, f));
  } else if (n == 5 && triangles == 4 && quads == 1) {
    const auto& f = first_of_size(4);  // Gmsh's face (0, 3, 2, 1)
    out = {&kPyramid, {f[0], f[3], f[2], f[1]}};
    out.nodes.push_back(across(f[0], f));
  }
  if (out.shape && (std::any_of(out.nodes.begin(), out.nodes.end(), [](int v) { return v < 0; }) ||
                    !matches(*out.shape, out.nodes, faces)))
    out = {};
  return out;
}

std::string number(double x) {
  char buf[32];
  const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, x);
  return std::string(buf, ec == std::errc() ? end : buf);
}

void check_group_name(const std::string& name) {
  for (const char c : name)
    if (c == '"' || static_cast<unsigned char>(c) < 0x20 || c == 0x7f)
      throw InputError("the face group name " + quote(name) +
                       " cannot be a Gmsh physical name (it holds a double quote or a control character)");
}

// The Gmsh element of each cell; InputError for a cell that is no Gmsh element or whose region
// is above the largest volume tag read back as a region.
std::vector<GmshCell> gmsh_cells(const Mesh3D& mesh) {
  const int nc = mesh.num_cells();
  std::vector<GmshCell> cells(static_cast<std::size_t>(nc));
  for (int c = 0; c < nc; ++c) {
    cells[static_cast<std::size_t>(c)] = gmsh_cell(mesh.cell(c));
    if (!cells[static_cast<std::size_t>(c)].shape)
      throw InputError("cell " + std::to_string(c) + " (" + std::to_string(mesh.cell_faces(c).size()) +
                       " faces) is no tetrahedron, hexahedron, prism or pyramid: Gmsh has no polyhedron element");
    if (mesh.region(c) > kGmshMaxRegion)
      throw InputError("cell " + std::to_string(c) + " has region " + std::to_string(mesh.region(c)) +
                       ", above the largest Gmsh volume tag read back as a region (" +
                       std::to_string(kGmshMaxRegion) + ")");
  }
  return cells;
}

// InputError for a face group whose name Gmsh cannot hold or with a face of more than 4 vertices.
void check_face_groups(const Mesh3D& mesh) {
  for (const auto& [name, faces] : mesh.face_groups()) {
    check_group_name(name);
    for (int f : faces)
      if (mesh.face(f).vertices.size() > 4)
        throw InputError("face " + std::to_string(f) + " of face group " + quote(name) + " has " +
                         std::to_string(mesh.face(f).vertices.size()) + " vertices: Gmsh has no polygon element");
  }
}

// The volume entities: one per region, tagged 1, 2, ... in the order of the regions.
std::map<int, int> volume_entities(const Mesh3D& mesh) {
  std::map<int, int> entity_of_region;
  for (int c = 0; c < mesh.num_cells(); ++c) entity_of_region.emplace(mesh.region(c), 0);
  int tag = 0;
  for (auto& [region, entity] : entity_of_region) entity = ++tag;
  return entity_of_region;
}

// $PhysicalNames: each face group a physical surface, tagged 1, 2, ... (none without groups).
void write_physical_names(const Mesh3D& mesh, std::ostream& out) {
  const auto& groups = mesh.face_groups();
  if (groups.empty()) return;
  out << "$PhysicalNames\n" << groups.size() << "\n";
  int g = 0;
  for (const auto& [name, faces] : groups) out << "2 " << ++g << " \"" << name << "\"\n";
  out << "$EndPhysicalNames\n";
}

// $Entities: a surface per face group and a volume per region, each with the mesh's bounding box.
void write_entities(const Mesh3D& mesh, const std::map<int, int>& entity_of_region, std::ostream& out) {
  const Box box = mesh.bounding_box();
  const std::string bounds = number(box.x0) + " " + number(box.y0) + " " + number(box.z0) + " " + number(box.x1) +
                             " " + number(box.y1) + " " + number(box.z1);
  const std::size_t ngroups = mesh.face_groups().size();
  out << "$Entities\n0 0 " << ngroups << " " << entity_of_region.size() << "\n";
  for (std::size_t g = 1; g <= ngroups; ++g) out << g << " " << bounds << " 1 " << g << " 0\n";
  for (const auto& [region, entity] : entity_of_region) {
    out << entity << " " << bounds;
    if (region > 0) out << " 1 " << region;
    else out << " 0";
    out << " 0\n";
  }
  out << "$EndEntities\n";
}

// $Nodes: the vertices in one block, tagged 1, 2, ...
void write_nodes(const Mesh3D& mesh, std::ostream& out) {
  const int nv = mesh.num_vertices();
  out << "$Nodes\n1 " << nv << " 1 " << nv << "\n3 1 0 " << nv << "\n";
  for (int v = 1; v <= nv; ++v) out << v << "\n";
  for (const Vec3& p : mesh.vertices()) out << number(p.x()) << " " << number(p.y()) << " " << number(p.z()) << "\n";
  out << "$EndNodes\n";
}

// One block of $Elements: elements of one dimension, entity and Gmsh type.
struct Block {
  int dim, entity, type;
  std::vector<const std::vector<int>*> elements;
};

// The element blocks: runs of cells of one region and shape, in cell order; then the faces of
// each group, triangles and quadrangles.
std::vector<Block> element_blocks(const Mesh3D& mesh, const std::vector<GmshCell>& cells,
                                  const std::map<int, int>& entity_of_region) {
  std::vector<Block> blocks;
  for (int c = 0; c < mesh.num_cells(); ++c) {
    const GmshCell& g = cells[static_cast<std::size_t>(c)];
    const int entity = entity_of_region.at(mesh.region(c));
    if (blocks.empty() || blocks.back().entity != entity || blocks.back().type != g.shape->type)
      blocks.push_back({3, entity, g.shape->type, {}});
    blocks.back().elements.push_back(&g.nodes);
  }
  int g = 0;
  for (const auto& [name, faces] : mesh.face_groups()) {
    ++g;
    for (const int type : {2, 3}) {
      Block b{2, g, type, {}};
      for (int f : faces)
        if (mesh.face(f).vertices.size() == (type == 2 ? 3u : 4u)) b.elements.push_back(&mesh.face(f).vertices);
      if (!b.elements.empty()) blocks.push_back(std::move(b));
    }
  }
  return blocks;
}

// $Elements: the blocks, elements tagged 1, 2, ... across them, vertices numbered from 1.
void write_elements(const std::vector<Block>& blocks, std::ostream& out) {
  std::size_t total = 0;
  for (const Block& b : blocks) total += b.elements.size();
  out << "$Elements\n" << blocks.size() << " " << total << " " << (total > 0 ? 1 : 0) << " " << total << "\n";
  std::size_t element = 0;
  for (const Block& b : blocks) {
    out << b.dim << " " << b.entity << " " << b.type << " " << b.elements.size() << "\n";
    for (const auto* nodes : b.elements) {
      out << ++element;
      for (int v : *nodes) out << " " << v + 1;
      out << "\n";
    }
  }
  out << "$EndElements\n";
}

}  // namespace

Mesh3D read_gmsh3d(const fs::path& path) {
  std::ifstream in = text::open_for_reading(path, "mesh file");
  return read_gmsh3d(in, path.string());
}

Mesh3D read_gmsh3d(std::istream& in, const std::string& name) {
  return Gmsh3DReader(in, name).read();
}

MeshPieceRead<Mesh3D> read_gmsh3d_piece(const fs::path& path, int rank, int size, HeldPoints held, const BoundaryPick<Mesh3D>& pick) {
  std::ifstream in = text::open_for_reading(path, "mesh file");
  return detail::read_own_piece<Mesh3D, Gmsh3DReader>(in, path.string(), rank, size, held, pick);
}

MeshPieceRead<Mesh3D> read_gmsh3d_piece(std::istream& in, const std::string& name, int rank, int size, HeldPoints held) {
  return detail::read_own_piece<Mesh3D, Gmsh3DReader>(in, name, rank, size, held);
}

MeshPieceRead<Mesh3D> read_gmsh3d_piece(const fs::path& path, const RowDistribution& processes, HeldPoints held,
                                   const BoundaryPick<Mesh3D>& pick) {
  return detail::read_piece_by_first<Mesh3D, Gmsh3DReader>(path, processes, held, pick);
}

MeshLists<Mesh3D> read_gmsh3d_lists(const fs::path& path) {
  std::ifstream in = text::open_for_reading(path, "mesh file");
  return read_gmsh3d_lists(in, path.string());
}

MeshLists<Mesh3D> read_gmsh3d_lists(std::istream& in, const std::string& name) {
  auto reader = std::make_shared<Gmsh3DReader>(in, name);
  const int vertices = reader->read_lists();
  return {vertices, [reader](const std::vector<char>& owned, HeldPoints held) { return reader->piece(owned, held); },
          [reader](int size, const std::function<std::vector<char>(int)>& owned, HeldPoints held,
                   const PieceDelivery<Mesh3D>& deliver) {
            reader->pieces(detail::pieces_around<Mesh3D>(size, owned, deliver), held);
          },
          [reader] { reader->name_defect(); }};
}

void write_gmsh3d(const Mesh3D& mesh, std::ostream& out) {
  const std::vector<GmshCell> cells = gmsh_cells(mesh);
  check_face_groups(mesh);
  const std::map<int, int> entity_of_region = volume_entities(mesh);
  out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  write_physical_names(mesh, out);
  write_entities(mesh, entity_of_region, out);
  write_nodes(mesh, out);
  write_elements(element_blocks(mesh, cells, entity_of_region), out);
}

void write_gmsh3d(const Mesh3D& mesh, const fs::path& path) {
  write_file_atomically(path, [&](std::ostream& out) { write_gmsh3d(mesh, out); });
}

}  // namespace hemivem
