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

#include <hemivem/support/atomic_file.hpp>
#include <hemivem/support/text_lines.hpp>

#include <algorithm>
#include <array>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <istream>
#include <map>
#include <ostream>
#include <string_view>
#include <system_error>
#include <unordered_map>

namespace hemivem {

namespace fs = std::filesystem;

namespace {

using text::Line;
using text::shown;

/// Region ids (volume physical tags) a file may hold.
constexpr long long kMaxRegion = 1000000;

std::string quote(std::string_view s) { return "'" + shown(s) + "'"; }

std::string_view strip_plus(std::string_view t, bool real) {
  if (t.size() >= 2 && t[0] == '+' && ((t[1] >= '0' && t[1] <= '9') || (real && t[1] == '.'))) t.remove_prefix(1);
  return t;
}

bool parse_integer(std::string_view token, long long& value) {
  const std::string_view t = strip_plus(token, false);
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), value);
  return ec == std::errc() && ptr == t.data() + t.size();
}

/// A finite real number (the whole token).
bool parse_real(std::string_view token, double& value) {
  const std::string_view t = strip_plus(token, true);
  const auto [ptr, ec] = std::from_chars(t.data(), t.data() + t.size(), value, std::chars_format::general);
  if (ptr != t.data() + t.size()) return false;
  if (ec == std::errc::result_out_of_range) {
    const std::string copy(t);
    value = std::strtod(copy.c_str(), nullptr);
  } else if (ec != std::errc()) {
    return false;
  }
  return std::isfinite(value);
}

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

/// Element types read: nodes per element and dimension, or 0 nodes when unsupported.
struct ElementType {
  int nodes = 0;
  int dim = -1;
};

ElementType element_type(long long type) {
  switch (type) {
    case 1: return {2, 1};
    case 2: return {3, 2};
    case 3: return {4, 2};
    case 4: return {4, 3};
    case 5: return {8, 3};
    case 6: return {6, 3};
    case 7: return {5, 3};
    case 15: return {1, 0};
    default: return {};
  }
}

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

struct Element {
  std::vector<int> nodes;  // node indices (into nodes_)
  const Shape* shape = nullptr;  // volumes only
  long long tag = 0;
  long long entity = 0;
  int line = 0;
};

struct Node {
  Vec3 x = Vec3::Zero();
  long long tag = 0;
  int tag_line = 0;  // line of the tag
};

class Gmsh3DReader {
 public:
  Gmsh3DReader(std::string data, std::string name) : data_(std::move(data)), name_(std::move(name)) {
    last_line_ = text::split_lines(data_, name_, lines_);
  }

  Mesh3D read() {
    bool format = false;
    while (pos_ < lines_.size()) {
      const Line line = lines_[pos_++];
      text::tokenize(line.text, tokens_);
      const std::string_view section = tokens_[0];
      if (section.front() != '$' || tokens_.size() != 1)
        fail(line, "expected a section header such as $Nodes, found " + quote(line.text));
      if (!format) {
        if (section != "$MeshFormat")
          fail(line, "expected $MeshFormat as the first section, found " + quote(line.text) +
                         " (is this a Gmsh .msh file?)");
        read_format(line);
        format = true;
        continue;
      }
      if (section == "$MeshFormat") {
        fail(line, "a second $MeshFormat section");
      } else if (section == "$PhysicalNames") {
        once(physical_names_line_, line);
        read_physical_names(line);
      } else if (section == "$Entities") {
        once(entities_line_, line);
        read_entities(line);
      } else if (section == "$Nodes") {
        once(nodes_line_, line);
        read_nodes(line);
      } else if (section == "$Elements") {
        if (nodes_line_ == 0) fail(line, "missing $Nodes section: $Elements must follow the $Nodes section");
        once(elements_line_, line);
        read_elements(line);
      } else if (section == "$PartitionedEntities") {
        fail(line, "partitioned meshes are not supported (save the mesh without partitions)");
      } else if (section.substr(0, 4) == "$End") {
        fail(line, quote(section) + " closes no open section");
      } else {
        skip_section(line);
      }
    }
    if (!format)
      fail(last_line_, lines_.empty() ? "the file holds no data: expected $MeshFormat"
                                      : "the file holds no $MeshFormat section");
    if (nodes_line_ == 0) fail(last_line_, "the file has no $Nodes section");
    if (elements_line_ == 0) fail(last_line_, "the file has no $Elements section");
    if (volumes_.empty())
      fail(elements_header_, "the file has no volume elements (4-node tetrahedra, 8-node hexahedra, 6-node prisms or "
                             "5-node pyramids): a plane mesh is read by read_gmsh");
    return build();
  }

 private:
  // ---- lines and tokens

  std::string where(int line) const { return name_ + ":" + std::to_string(line); }
  [[noreturn]] void fail(int line, const std::string& message) const { throw InputError(message, where(line)); }
  [[noreturn]] void fail(const Line& line, const std::string& message) const { fail(line.number, message); }

  void once(int& seen, const Line& line) {
    if (seen != 0)
      fail(line, "a second " + std::string(line.text) + " section (the first is at line " + std::to_string(seen) + ")");
    seen = line.number;
  }

  std::size_t lines_left() const { return lines_.size() - std::min(pos_, lines_.size()); }

  /// The next data line of the section opened at `header`, tokenized; `what` says what was expected.
  const Line& data_line(const Line& header, const std::string& what) {
    const std::string opened = std::string(header.text) + " (line " + std::to_string(header.number) + ")";
    if (pos_ >= lines_.size()) fail(last_line_, "the file ends inside " + opened + " while expecting " + what);
    const Line& line = lines_[pos_];
    if (line.text.front() == '$') fail(line, "expected " + what + " in " + opened + ", found " + quote(line.text));
    ++pos_;
    text::tokenize(line.text, tokens_);
    return line;
  }

  void end_section(const Line& header) {
    const std::string end = "$End" + std::string(header.text.substr(1));
    if (pos_ >= lines_.size())
      fail(last_line_, "the file ends before " + end + " (closing line " + std::to_string(header.number) + ")");
    const Line& line = lines_[pos_++];
    if (line.text != end)
      fail(line, "expected " + end + " (closing line " + std::to_string(header.number) + "), found " +
                     quote(line.text));
  }

  void skip_section(const Line& header) {
    const std::string end = "$End" + std::string(header.text.substr(1));
    while (pos_ < lines_.size())
      if (lines_[pos_++].text == end) return;
    fail(last_line_, "the file ends before " + end + " (closing line " + std::to_string(header.number) + ")");
  }

  long long integer(const Line& line, std::size_t i, const std::string& what) {
    long long v = 0;
    if (i >= tokens_.size()) fail(line, "missing " + what + " in " + quote(line.text));
    if (!parse_integer(tokens_[i], v)) fail(line, "bad " + what + " " + quote(tokens_[i]) + " (expected an integer)");
    return v;
  }

  /// A count: non-negative and at most INT_MAX.
  long long count(const Line& line, std::size_t i, const std::string& what) {
    const long long n = integer(line, i, what);
    if (n < 0) fail(line, what + " " + std::to_string(n) + " is negative");
    if (n > INT_MAX) fail(line, what + " " + std::to_string(n) + " is too large (at most " + std::to_string(INT_MAX) + ")");
    return n;
  }

  void expect_tokens(const Line& line, std::size_t n, const std::string& what) {
    if (tokens_.size() != n)
      fail(line, what + " has " + std::to_string(tokens_.size()) + " values, expected " + std::to_string(n) +
                     " (found " + quote(line.text) + ")");
  }

  // ---- sections

  void read_format(const Line& header) {
    const Line& line = data_line(header, "the format line '4.1 0 8'");
    if (tokens_.size() != 3) fail(line, "expected the format line '4.1 0 8', found " + quote(line.text));
    if (tokens_[0] != "4.1")
      fail(line, "MSH format version " + quote(tokens_[0]) +
                     " is not supported: only version 4.1 is read (save with Mesh.MshFileVersion = 4.1)");
    if (tokens_[1] == "1") fail(line, "binary MSH files are not supported: save the mesh as ASCII (Mesh.Binary = 0)");
    if (tokens_[1] != "0") fail(line, "bad file type " + quote(tokens_[1]) + " (expected 0, ASCII)");
    long long size = 0;
    if (!parse_integer(tokens_[2], size)) fail(line, "bad data size " + quote(tokens_[2]) + " (expected 8)");
    end_section(header);
  }

  void read_physical_names(const Line& header) {
    const Line& cl = data_line(header, "the number of physical names");
    expect_tokens(cl, 1, "the count line of $PhysicalNames");
    const long long n = count(cl, 0, "physical name count");
    for (long long i = 0; i < n; ++i) {
      const Line& line = data_line(header, std::to_string(n) + " physical name lines 'dim tag \"name\"' (found " +
                                               std::to_string(i) + ")");
      if (tokens_.size() < 3) fail(line, "expected a physical name 'dim tag \"name\"', found " + quote(line.text));
      const long long dim = integer(line, 0, "physical group dimension");
      const long long tag = integer(line, 1, "physical group tag");
      if (dim < 0 || dim > 3) fail(line, "physical group dimension " + std::to_string(dim) + " is not 0, 1, 2 or 3");
      if (tag < INT_MIN || tag > INT_MAX) fail(line, "physical group tag " + std::to_string(tag) + " is out of range");
      // The name is everything between the first and the last double quote.
      const std::size_t open = line.text.find('"');
      const std::size_t close = line.text.rfind('"');
      if (open == std::string_view::npos || close == open ||
          open != static_cast<std::size_t>(tokens_[2].data() - line.text.data()))
        fail(line, "the physical name of group " + std::to_string(tag) + " is not in double quotes (found " +
                       quote(line.text) + ")");
      if (close != line.text.size() - 1)
        fail(line, "unexpected content after the physical name: " + quote(line.text.substr(close + 1)));
      const auto key = std::make_pair(static_cast<int>(dim), static_cast<int>(tag));
      if (!physical_names_.emplace(key, std::string(line.text.substr(open + 1, close - open - 1))).second)
        fail(line, "physical group " + std::to_string(tag) + " of dimension " + std::to_string(dim) + " is named twice");
    }
    end_section(header);
  }

  void read_entities(const Line& header) {
    const Line& cl = data_line(header, "the entity counts 'numPoints numCurves numSurfaces numVolumes'");
    expect_tokens(cl, 4, "the count line of $Entities");
    long long n[4];
    for (int d = 0; d < 4; ++d) n[d] = count(cl, static_cast<std::size_t>(d), "entity count");
    static const char* const kind[4] = {"point", "curve", "surface", "volume"};
    for (int d = 0; d < 4; ++d) {
      for (long long i = 0; i < n[d]; ++i) {
        const Line& line = data_line(header, std::to_string(n[d]) + " " + kind[d] + " entity lines (found " +
                                                 std::to_string(i) + ")");
        const std::string what = std::string(kind[d]) + " ";
        const long long tag = integer(line, 0, what + "tag");
        // point: tag x y z; others: tag minX minY minZ maxX maxY maxZ
        const std::size_t at = d == 0 ? 4 : 7;
        const long long np = integer(line, at, "number of physical tags of " + what + std::to_string(tag));
        if (np < 0 || static_cast<unsigned long long>(np) > tokens_.size())
          fail(line, what + std::to_string(tag) + " declares " + std::to_string(np) + " physical tags; the line holds " +
                         std::to_string(tokens_.size()) + " values");
        std::size_t expected = at + 1 + static_cast<std::size_t>(np);
        if (d > 0) {
          const long long nb = integer(line, expected, "number of bounding entities of " + what + std::to_string(tag));
          if (nb < 0 || static_cast<unsigned long long>(nb) > tokens_.size())
            fail(line, what + std::to_string(tag) + " declares " + std::to_string(nb) +
                           " bounding entities; the line holds " + std::to_string(tokens_.size()) + " values");
          expected += 1 + static_cast<std::size_t>(nb);
        }
        if (tokens_.size() != expected)
          fail(line, what + std::to_string(tag) + " has " + std::to_string(tokens_.size()) +
                         " values where its counts give " + std::to_string(expected));
        std::vector<int> tags;
        for (long long k = 0; k < np; ++k) {
          const long long p = integer(line, at + 1 + static_cast<std::size_t>(k), "physical tag");
          if (p < INT_MIN || p > INT_MAX) fail(line, "physical tag " + std::to_string(p) + " is out of range");
          if (d == 3 && (p < 1 || p > kMaxRegion))
            fail(line, "physical volume tag " + std::to_string(p) +
                           " cannot be a region id: volume tags are kept as region ids, from 1 to " +
                           std::to_string(kMaxRegion));
          tags.push_back(static_cast<int>(p));
        }
        if (!entity_physicals_[d].emplace(tag, std::move(tags)).second)
          fail(line, what + "entity " + std::to_string(tag) + " is listed twice");
      }
    }
    end_section(header);
  }

  void read_nodes(const Line& header) {
    const Line& hl = data_line(header, "'numEntityBlocks numNodes minNodeTag maxNodeTag'");
    expect_tokens(hl, 4, "the count line of $Nodes");
    const long long blocks = count(hl, 0, "node block count");
    const long long total = count(hl, 1, "node count");
    integer(hl, 2, "minimum node tag");
    integer(hl, 3, "maximum node tag");
    if (static_cast<unsigned long long>(total) > lines_left())
      fail(hl, "the node count " + std::to_string(total) + " exceeds what the rest of the file can hold");
    nodes_.reserve(static_cast<std::size_t>(total));
    long long read = 0;
    for (long long b = 0; b < blocks; ++b) {
      const Line& bl = data_line(header, std::to_string(blocks) + " node blocks (found " + std::to_string(b) +
                                             "): 'entityDim entityTag parametric numNodesInBlock'");
      expect_tokens(bl, 4, "a node block header");
      const long long dim = integer(bl, 0, "entity dimension");
      integer(bl, 1, "entity tag");
      const long long parametric = integer(bl, 2, "parametric flag");
      const long long n = count(bl, 3, "node count of the block");
      if (dim < 0 || dim > 3) fail(bl, "entity dimension " + std::to_string(dim) + " is not 0, 1, 2 or 3");
      if (parametric != 0 && parametric != 1)
        fail(bl, "the parametric flag is " + std::to_string(parametric) + ", not 0 or 1");
      if (read + n > total)
        fail(bl, "the node blocks hold more nodes than the " + std::to_string(total) + " declared at line " +
                     std::to_string(hl.number));
      const std::size_t first = nodes_.size();
      for (long long i = 0; i < n; ++i) {
        const Line& line = data_line(header, std::to_string(n) + " node tags of the block at line " +
                                                 std::to_string(bl.number) + " (found " + std::to_string(i) + ")");
        expect_tokens(line, 1, "a node tag line");
        const long long tag = integer(line, 0, "node tag");
        if (tag <= 0) fail(line, "node tag " + std::to_string(tag) + " is not positive");
        const auto [it, fresh] = node_index_.emplace(tag, static_cast<int>(nodes_.size()));
        if (!fresh)
          fail(line, "node tag " + std::to_string(tag) + " appears twice (first at line " +
                         std::to_string(nodes_[static_cast<std::size_t>(it->second)].tag_line) + ")");
        nodes_.push_back({Vec3::Zero(), tag, line.number});
      }
      const std::size_t values = 3 + (parametric == 1 ? static_cast<std::size_t>(dim) : 0);
      for (long long i = 0; i < n; ++i) {
        Node& node = nodes_[first + static_cast<std::size_t>(i)];
        const std::string what = "node " + std::to_string(node.tag);
        const Line& line = data_line(header, std::to_string(n) + " node coordinate lines of the block at line " +
                                                 std::to_string(bl.number) + " (found " + std::to_string(i) + ")");
        expect_tokens(line, values, "the coordinate line of " + what);
        for (int k = 0; k < 3; ++k) {
          double c = 0.0;
          if (!parse_real(tokens_[static_cast<std::size_t>(k)], c))
            fail(line, what + " has a " + "xyz"[k] + " coordinate " + quote(tokens_[static_cast<std::size_t>(k)]) +
                           " that is not a finite number");
          if (std::abs(c) > 1e100)
            fail(line, what + " has a " + "xyz"[k] + " coordinate " + quote(tokens_[static_cast<std::size_t>(k)]) +
                           " of magnitude above 1e100 (cell volumes would overflow)");
          node.x[k] = c;
        }
      }
      read += n;
    }
    if (read != total)
      fail(hl, "$Nodes declares " + std::to_string(total) + " nodes but its blocks hold " + std::to_string(read));
    end_section(header);
  }

  void read_elements(const Line& header) {
    const Line& hl = data_line(header, "'numEntityBlocks numElements minElementTag maxElementTag'");
    expect_tokens(hl, 4, "the count line of $Elements");
    elements_header_ = hl.number;
    const long long blocks = count(hl, 0, "element block count");
    const long long total = count(hl, 1, "element count");
    integer(hl, 2, "minimum element tag");
    integer(hl, 3, "maximum element tag");
    if (static_cast<unsigned long long>(total) > lines_left())
      fail(hl, "the element count " + std::to_string(total) + " exceeds what the rest of the file can hold");
    long long read = 0;
    for (long long b = 0; b < blocks; ++b) {
      const Line& bl = data_line(header, std::to_string(blocks) + " element blocks (found " + std::to_string(b) +
                                             "): 'entityDim entityTag elementType numElementsInBlock'");
      expect_tokens(bl, 4, "an element block header");
      const long long dim = integer(bl, 0, "entity dimension");
      const long long entity = integer(bl, 1, "entity tag");
      const long long type = integer(bl, 2, "element type");
      const long long n = count(bl, 3, "element count of the block");
      const ElementType et = element_type(type);
      if (et.nodes == 0) {
        const std::string name = unsupported_type_name(type);
        fail(bl, "element type " + std::to_string(type) + (name.empty() ? "" : " (" + name + ")") +
                     " is not supported: only 4-node tetrahedra (4), 8-node hexahedra (5), 6-node prisms (6), 5-node "
                     "pyramids (7), 3-node triangles (2), 4-node quadrangles (3), 2-node lines (1) and points (15) are "
                     "read (save a first-order mesh)");
      }
      if (dim != et.dim)
        fail(bl, "element type " + std::to_string(type) + " is of dimension " + std::to_string(et.dim) +
                     " but its block is on an entity of dimension " + std::to_string(dim));
      if (read + n > total)
        fail(bl, "the element blocks hold more elements than the " + std::to_string(total) + " declared at line " +
                     std::to_string(hl.number));
      if (dim > 1 && entities_line_ != 0 && !entity_physicals_[dim].count(entity))
        fail(bl, std::string(dim == 2 ? "surface" : "volume") + " entity " + std::to_string(entity) +
                     " is not in $Entities");
      const std::size_t nn = static_cast<std::size_t>(et.nodes);
      for (long long i = 0; i < n; ++i) {
        const Line& line = data_line(header, std::to_string(n) + " element lines of the block at line " +
                                                 std::to_string(bl.number) + " (found " + std::to_string(i) + ")");
        const long long tag = integer(line, 0, "element tag");
        const std::string what = "element " + std::to_string(tag);
        if (tokens_.size() != nn + 1)
          fail(line, what + " (type " + std::to_string(type) + ") lists " + std::to_string(tokens_.size() - 1) +
                         " node tags, expected " + std::to_string(nn));
        std::vector<int> ids(nn);
        for (std::size_t k = 0; k < nn; ++k) {
          const long long t = integer(line, k + 1, "node tag of " + what);
          const auto it = node_index_.find(t);
          if (it == node_index_.end())
            fail(line, what + " refers to node tag " + std::to_string(t) + ", which is not in $Nodes");
          ids[k] = it->second;
        }
        if (dim == 3) volumes_.push_back({std::move(ids), volume_shape(type), tag, entity, line.number});
        else if (dim == 2) surfaces_.push_back({std::move(ids), nullptr, tag, entity, line.number});
      }
      read += n;
    }
    if (read != total)
      fail(hl, "$Elements declares " + std::to_string(total) + " elements but its blocks hold " + std::to_string(read));
    end_section(header);
  }

  // ---- the mesh

  Mesh3D build() {
    // vertices: the nodes of volume elements, in $Nodes order
    vertex_of_.assign(nodes_.size(), -1);
    for (const auto& e : volumes_)
      for (int n : e.nodes) vertex_of_[static_cast<std::size_t>(n)] = 0;
    std::vector<Vec3> vertices;
    for (std::size_t i = 0; i < nodes_.size(); ++i)
      if (vertex_of_[i] == 0) {
        vertex_of_[i] = static_cast<int>(vertices.size());
        vertices.push_back(nodes_[i].x);
      }
    std::vector<CellFaces> cells;
    std::vector<int> regions;
    cells.reserve(volumes_.size());
    regions.reserve(volumes_.size());
    for (const auto& e : volumes_) {
      cells.push_back(cell_of(e, vertices));
      regions.push_back(region_of(e.entity));
    }
    Mesh3D mesh;
    try {
      mesh = Mesh3D(std::move(vertices), std::move(cells), std::move(regions));
    } catch (const MeshError& err) {
      const int c = err.element();
      if (c >= 0 && static_cast<std::size_t>(c) < volumes_.size()) {
        const auto& e = volumes_[static_cast<std::size_t>(c)];
        throw MeshError("Gmsh element " + std::to_string(e.tag) + " (" + e.shape->name + "): " + err.detail(), c,
                        where(e.line));
      }
      throw MeshError(err.detail(), c, where(elements_header_));
    }
    add_face_groups(mesh);
    return mesh;
  }

  /// The faces of a volume element, outward: as Gmsh's node ordering gives them, all reversed
  /// when its volume is negative.
  CellFaces cell_of(const Element& e, const std::vector<Vec3>& vertices) const {
    CellFaces faces;
    for (const auto& f : e.shape->faces) {
      std::vector<int> loop;
      for (int k : f) loop.push_back(vertex_of_[static_cast<std::size_t>(e.nodes[static_cast<std::size_t>(k)])]);
      faces.push_back(std::move(loop));
    }
    const Vec3& o = vertices[static_cast<std::size_t>(faces[0][0])];
    double volume = 0.0;
    std::vector<Vec3> z;
    for (const auto& loop : faces) {
      z.clear();
      for (int v : loop) z.push_back(vertices[static_cast<std::size_t>(v)] - o);
      volume += polygon_area_vector(z).dot(polygon_centroid(z));
    }
    if (volume < 0.0)
      for (auto& loop : faces) std::reverse(loop.begin(), loop.end());
    return faces;
  }

  int region_of(long long entity) const {
    const auto it = entity_physicals_[3].find(entity);
    if (it == entity_physicals_[3].end() || it->second.empty()) return 0;
    return it->second.front();
  }

  /// Face groups from the 2D physical groups, named by $PhysicalNames or else by tag.
  void add_face_groups(Mesh3D& mesh) const {
    std::map<std::vector<int>, int> face_of;  // sorted vertices -> face
    for (int f = 0; f < mesh.num_faces(); ++f) {
      std::vector<int> key = mesh.face(f).vertices;
      std::sort(key.begin(), key.end());
      face_of.emplace(std::move(key), f);
    }
    std::map<int, std::vector<int>> group_faces;  // 2D physical tag -> faces
    for (const auto& [key, name] : physical_names_)
      if (key.first == 2) group_faces[key.second];
    for (const auto& [entity, tags] : entity_physicals_[2])
      for (int t : tags) group_faces[t];
    for (const auto& s : surfaces_) {
      const auto ent = entity_physicals_[2].find(s.entity);
      if (ent == entity_physicals_[2].end() || ent->second.empty()) continue;
      std::vector<int> key;
      for (int n : s.nodes) key.push_back(vertex_of_[static_cast<std::size_t>(n)]);
      std::sort(key.begin(), key.end());
      const auto it = std::find(key.begin(), key.end(), -1) != key.end() ? face_of.end() : face_of.find(key);
      if (it == face_of.end()) {
        std::string tags;
        for (int n : s.nodes) {
          tags += ' ';
          tags += std::to_string(nodes_[static_cast<std::size_t>(n)].tag);
        }
        fail(s.line, "surface element " + std::to_string(s.tag) + " (nodes" + tags +
                         ") of a physical surface is not a face of the volume mesh");
      }
      for (int t : ent->second) group_faces[t].push_back(it->second);
    }
    std::map<std::string, int> names;
    for (auto& [tag, faces] : group_faces) {
      const auto named = physical_names_.find({2, tag});
      const std::string name = named != physical_names_.end() ? named->second : std::to_string(tag);
      if (const auto [it, fresh] = names.emplace(name, tag); !fresh)
        fail(physical_names_line_ != 0 ? physical_names_line_ : last_line_,
             "the 2D physical groups " + std::to_string(it->second) + " and " + std::to_string(tag) +
                 " have the same name " + quote(name));
      mesh.set_face_group(name, std::move(faces));
    }
  }

  std::string data_;
  std::string name_;
  std::vector<Line> lines_;
  std::vector<std::string_view> tokens_;
  std::size_t pos_ = 0;
  int last_line_ = 1;

  int physical_names_line_ = 0, entities_line_ = 0, nodes_line_ = 0, elements_line_ = 0, elements_header_ = 0;
  std::map<std::pair<int, int>, std::string> physical_names_;
  std::map<long long, std::vector<int>> entity_physicals_[4];
  std::vector<Node> nodes_;
  std::unordered_map<long long, int> node_index_;
  std::vector<Element> volumes_, surfaces_;
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

}  // namespace

Mesh3D read_gmsh3d(const fs::path& path) {
  std::ifstream in = text::open_for_reading(path, "mesh file");
  return read_gmsh3d(in, path.string());
}

Mesh3D read_gmsh3d(std::istream& in, const std::string& name) {
  return Gmsh3DReader(text::read_all(in, name, "mesh"), name).read();
}

void write_gmsh3d(const Mesh3D& mesh, std::ostream& out) {
  const int nc = mesh.num_cells();
  std::vector<GmshCell> cells(static_cast<std::size_t>(nc));
  for (int c = 0; c < nc; ++c) {
    cells[static_cast<std::size_t>(c)] = gmsh_cell(mesh.cell(c));
    if (!cells[static_cast<std::size_t>(c)].shape)
      throw InputError("cell " + std::to_string(c) + " (" + std::to_string(mesh.cell_faces(c).size()) +
                       " faces) is no tetrahedron, hexahedron, prism or pyramid: Gmsh has no polyhedron element");
    if (mesh.region(c) > kMaxRegion)
      throw InputError("cell " + std::to_string(c) + " has region " + std::to_string(mesh.region(c)) +
                       ", above the largest Gmsh volume tag read back as a region (" + std::to_string(kMaxRegion) + ")");
  }
  for (const auto& [name, faces] : mesh.face_groups()) {
    check_group_name(name);
    for (int f : faces)
      if (mesh.face(f).vertices.size() > 4)
        throw InputError("face " + std::to_string(f) + " of face group " + quote(name) + " has " +
                         std::to_string(mesh.face(f).vertices.size()) + " vertices: Gmsh has no polygon element");
  }

  // volume entities: one per region, tagged 1, 2, ... in the order of the regions
  std::map<int, int> entity_of_region;
  for (int c = 0; c < nc; ++c) entity_of_region.emplace(mesh.region(c), 0);
  int tag = 0;
  for (auto& [region, entity] : entity_of_region) entity = ++tag;
  const Box box = mesh.bounding_box();
  const std::string bounds = number(box.x0) + " " + number(box.y0) + " " + number(box.z0) + " " + number(box.x1) +
                             " " + number(box.y1) + " " + number(box.z1);
  const auto& groups = mesh.face_groups();

  out << "$MeshFormat\n4.1 0 8\n$EndMeshFormat\n";
  if (!groups.empty()) {
    out << "$PhysicalNames\n" << groups.size() << "\n";
    int g = 0;
    for (const auto& [name, faces] : groups) out << "2 " << ++g << " \"" << name << "\"\n";
    out << "$EndPhysicalNames\n";
  }
  out << "$Entities\n0 0 " << groups.size() << " " << entity_of_region.size() << "\n";
  for (std::size_t g = 1; g <= groups.size(); ++g) out << g << " " << bounds << " 1 " << g << " 0\n";
  for (const auto& [region, entity] : entity_of_region) {
    out << entity << " " << bounds;
    if (region > 0) out << " 1 " << region;
    else out << " 0";
    out << " 0\n";
  }
  out << "$EndEntities\n";

  const int nv = mesh.num_vertices();
  out << "$Nodes\n1 " << nv << " 1 " << nv << "\n3 1 0 " << nv << "\n";
  for (int v = 1; v <= nv; ++v) out << v << "\n";
  for (const Vec3& p : mesh.vertices()) out << number(p.x()) << " " << number(p.y()) << " " << number(p.z()) << "\n";
  out << "$EndNodes\n";

  // element blocks: runs of cells of one region and shape, in cell order; then the faces of
  // each group, triangles and quadrangles
  struct Block {
    int dim, entity, type;
    std::vector<const std::vector<int>*> elements;
  };
  std::vector<Block> blocks;
  for (int c = 0; c < nc; ++c) {
    const GmshCell& g = cells[static_cast<std::size_t>(c)];
    const int entity = entity_of_region.at(mesh.region(c));
    if (blocks.empty() || blocks.back().entity != entity || blocks.back().type != g.shape->type)
      blocks.push_back({3, entity, g.shape->type, {}});
    blocks.back().elements.push_back(&g.nodes);
  }
  int g = 0;
  for (const auto& [name, faces] : groups) {
    ++g;
    for (const int type : {2, 3}) {
      Block b{2, g, type, {}};
      for (int f : faces)
        if (mesh.face(f).vertices.size() == (type == 2 ? 3u : 4u)) b.elements.push_back(&mesh.face(f).vertices);
      if (!b.elements.empty()) blocks.push_back(std::move(b));
    }
  }
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

void write_gmsh3d(const Mesh3D& mesh, const fs::path& path) {
  write_file_atomically(path, [&](std::ostream& out) { write_gmsh3d(mesh, out); });
}

}  // namespace hemivem
