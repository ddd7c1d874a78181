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

#include <hemivem/support/text_lines.hpp>

#include <algorithm>
#include <cerrno>
#include <charconv>
#include <climits>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <istream>
#include <map>
#include <set>
#include <string_view>
#include <system_error>
#include <unordered_map>

namespace hemivem {

namespace fs = std::filesystem;

namespace {

using text::shown;


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

using text::Line;

/// Element types: nodes per element and dimension, or 0 nodes when unsupported.
struct ElementType {
  int nodes = 0;
  int dim = -1;
};

ElementType element_type(long long type) {
  switch (type) {
    case 1: return {2, 1};
    case 2: return {3, 2};
    case 3: return {4, 2};
    case 15: return {1, 0};
    default: return {};
  }
}

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

struct SurfaceElement {
  std::vector<int> nodes;  // node indices (into nodes_)
  long long tag = 0;
  long long entity = 0;
  int line = 0;
};

struct LineElement {
  int n0 = 0, n1 = 0;
  long long tag = 0;
  long long entity = 0;
  int line = 0;
};

struct Node {
  double x = 0, y = 0, z = 0;
  long long tag = 0;
  int tag_line = 0;  // line of the tag
  int line = 0;      // line of the coordinates
};

class GmshReader {
 public:
  GmshReader(std::string data, std::string name) : data_(std::move(data)), name_(std::move(name)) { split(); }

  Mesh read() {
    bool format = false;
    while (pos_ < lines_.size()) {
      const Line line = lines_[pos_++];
      tokenize(line.text);
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
    check_plane();
    return build();
  }

 private:
  // ---- lines and tokens

  void split() { last_line_ = text::split_lines(data_, name_, lines_); }
  void tokenize(std::string_view line) { text::tokenize(line, tokens_); }

  std::string where(int line) const { return name_ + ":" + std::to_string(line); }
  [[noreturn]] void fail(int line, const std::string& message) const { throw InputError(message, where(line)); }
  [[noreturn]] void fail(const Line& line, const std::string& message) const { fail(line.number, message); }

  void once(int& seen, const Line& line) {
    if (seen != 0)
      fail(line, "a second " + std::string(line.text) + " section (the first is at line " + std::to_string(seen) + ")");
    seen = line.number;
  }

  std::size_t lines_left() const { return lines_.size() - std::min(pos_, lines_.size()); }

  /// The next data line of `section` (opened at `header`), tokenized; `what` says what was expected.
  const Line& data_line(const Line& header, const std::string& what) {
    const std::string opened = std::string(header.text) + " (line " + std::to_string(header.number) + ")";
    if (pos_ >= lines_.size()) fail(last_line_, "the file ends inside " + opened + " while expecting " + what);
    const Line& line = lines_[pos_];
    if (line.text.front() == '$')
      fail(line, "expected " + what + " in " + opened + ", found " + quote(line.text));
    ++pos_;
    tokenize(line.text);
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
    while (pos_ < lines_.size()) {
      if (lines_[pos_++].text == end) return;
    }
    fail(last_line_, "the file ends before " + end + " (closing line " + std::to_string(header.number) + ")");
  }

  long long integer(const Line& line, std::size_t i, const std::string& what) {
    long long v = 0;
    if (i >= tokens_.size()) fail(line, "missing " + what + " in " + quote(line.text));
    if (!parse_integer(tokens_[i], v)) fail(line, "bad " + what + " " + quote(tokens_[i]) + " (expected an integer)");
    return v;
  }

  /// A count that must be non-negative and not larger than `limit` (the lines left, or a
  /// bound derived from them), so nothing is ever sized from an absurd count.
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
    if (tokens_[1] == "1")
      fail(line, "binary MSH files are not supported: save the mesh as ASCII (Mesh.Binary = 0)");
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
      if (open == std::string_view::npos || close == open || open != static_cast<std::size_t>(tokens_[2].data() - line.text.data()))
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
        const std::string what = std::string(kind[d]) + " entity line";
        const Line& line = data_line(header, std::to_string(n[d]) + " " + kind[d] + " entity lines (found " +
                                                 std::to_string(i) + ")");
        if (d == 3) continue;  // volumes: not used
        const long long tag = integer(line, 0, std::string(kind[d]) + " tag");
        // point: tag x y z; others: tag minX minY minZ maxX maxY maxZ
        const std::size_t at = d == 0 ? 4 : 7;
        const long long np = integer(line, at, "number of physical tags of " + std::string(kind[d]) + " " +
                                                   std::to_string(tag));
        if (np < 0 || static_cast<unsigned long long>(np) > tokens_.size())
          fail(line, std::string(kind[d]) + " " + std::to_string(tag) + " declares " + std::to_string(np) +
                         " physical tags; the line holds " + std::to_string(tokens_.size()) + " values");
        std::size_t expected = at + 1 + static_cast<std::size_t>(np);
        if (d > 0) {
          const long long nb = integer(line, expected, "number of bounding entities of " + std::string(kind[d]) +
                                                            " " + std::to_string(tag));
          if (nb < 0 || static_cast<unsigned long long>(nb) > tokens_.size())
            fail(line, std::string(kind[d]) + " " + std::to_string(tag) + " declares " + std::to_string(nb) +
                           " bounding entities; the line holds " + std::to_string(tokens_.size()) + " values");
          expected += 1 + static_cast<std::size_t>(nb);
        }
        if (tokens_.size() != expected)
          fail(line, std::string(kind[d]) + " " + std::to_string(tag) + " has " + std::to_string(tokens_.size()) +
                         " values where its counts give " + std::to_string(expected));
        std::vector<int> tags;
        for (long long k = 0; k < np; ++k) {
          const long long p = integer(line, at + 1 + static_cast<std::size_t>(k), "physical tag");
          if (p < INT_MIN || p > INT_MAX) fail(line, "physical tag " + std::to_string(p) + " is out of range");
          if (d == 2 && (p < 1 || p > 1000000))
            fail(line, "physical surface tag " + std::to_string(p) +
                           " cannot be a region id: surface tags are kept as region ids, from 1 to 1000000");
          tags.push_back(static_cast<int>(p));
        }
        if (!entity_physicals_[d].emplace(tag, std::move(tags)).second)
          fail(line, std::string(kind[d]) + " entity " + std::to_string(tag) + " is listed twice");
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
    // Each node takes two lines.
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
      if (parametric != 0 && parametric != 1) fail(bl, "the parametric flag is " + std::to_string(parametric) + ", not 0 or 1");
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
        nodes_.push_back({0, 0, 0, tag, line.number, line.number});
      }
      const std::size_t values = 3 + (parametric == 1 ? static_cast<std::size_t>(dim) : 0);
      for (long long i = 0; i < n; ++i) {
        Node& node = nodes_[first + static_cast<std::size_t>(i)];
        const std::string what = "node " + std::to_string(node.tag);
        const Line& line = data_line(header, std::to_string(n) + " node coordinate lines of the block at line " +
                                                 std::to_string(bl.number) + " (found " + std::to_string(i) + ")");
        expect_tokens(line, values, "the coordinate line of " + what);
        double c[3];
        for (int k = 0; k < 3; ++k) {
          if (!parse_real(tokens_[static_cast<std::size_t>(k)], c[k]))
            fail(line, what + " has a " + "xyz"[k] + " coordinate " + quote(tokens_[static_cast<std::size_t>(k)]) +
                           " that is not a finite number");
          if (std::abs(c[k]) > max_mesh_coordinate)
            fail(line, what + " has a " + "xyz"[k] + " coordinate " + quote(tokens_[static_cast<std::size_t>(k)]) +
                           " of magnitude above 1e150 (element areas would overflow)");
        }
        node.x = c[0];
        node.y = c[1];
        node.z = c[2];
        node.line = line.number;
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
                     " is not supported: only 2-node lines (1), 3-node triangles (2), 4-node quadrangles (3) and "
                     "points (15) are read" +
                     (type == 4 || type == 5 || type == 6 || type == 7 ? " (the mesh must be plane)"
                                                                       : " (save a first-order mesh)"));
      }
      if (dim != et.dim)
        fail(bl, "element type " + std::to_string(type) + " is of dimension " + std::to_string(et.dim) +
                     " but its block is on an entity of dimension " + std::to_string(dim));
      if (read + n > total)
        fail(bl, "the element blocks hold more elements than the " + std::to_string(total) + " declared at line " +
                     std::to_string(hl.number));
      if (dim > 0 && entities_line_ != 0 && !entity_physicals_[dim].count(entity))
        fail(bl, std::string(dim == 1 ? "curve" : "surface") + " entity " + std::to_string(entity) +
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
        if (dim == 2) {
          surfaces_.push_back({std::move(ids), tag, entity, line.number});
        } else if (dim == 1) {
          lines_elements_.push_back({ids[0], ids[1], tag, entity, line.number});
        }
      }
      read += n;
    }
    if (read != total)
      fail(hl, "$Elements declares " + std::to_string(total) + " elements but its blocks hold " + std::to_string(read));
    elements_header_ = hl.number;
    end_section(header);
  }

  // ---- the mesh

  void check_plane() const {
    double scale = 0.0;
    for (const Node& n : nodes_) scale = std::max({scale, std::abs(n.x), std::abs(n.y)});
    const double tol = 1e-10 * scale;
    for (const Node& n : nodes_)
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
    Mesh mesh = surface_mesh(std::move(vertices), vertex_of);
    add_edge_groups(mesh, vertex_of);
    return mesh;
  }

  /// Vertices: the nodes of surface elements, in $Nodes order; `vertex_of` receives the vertex
  /// of each node (-1 for the others).
  std::vector<Vec2> surface_vertices(std::vector<int>& vertex_of) const {
    vertex_of.assign(nodes_.size(), -1);
    for (const auto& s : surfaces_)
      for (int n : s.nodes) vertex_of[static_cast<std::size_t>(n)] = 0;
    std::vector<Vec2> vertices;
    for (std::size_t i = 0; i < nodes_.size(); ++i)
      if (vertex_of[i] == 0) {
        vertex_of[i] = static_cast<int>(vertices.size());
        vertices.emplace_back(nodes_[i].x, nodes_[i].y);
      }
    return vertices;
  }

  /// The region of each surface element: the tag of its entity's first physical group, as
  /// written in the file (0 without one).
  std::vector<int> surface_regions() const {
    auto region_of = [&](long long entity) {
      const auto it = entity_physicals_[2].find(entity);
      if (it == entity_physicals_[2].end() || it->second.empty()) return 0;
      return it->second.front();
    };
    std::vector<int> regions;
    regions.reserve(surfaces_.size());
    for (const auto& s : surfaces_) regions.push_back(region_of(s.entity));
    return regions;
  }

  /// The mesh of the surface elements, each made counter-clockwise; a mesh error names the
  /// Gmsh element and its line.
  Mesh surface_mesh(std::vector<Vec2> vertices, const std::vector<int>& vertex_of) const {
    std::vector<std::vector<int>> elements;
    elements.reserve(surfaces_.size());
    for (const auto& s : surfaces_) {
      std::vector<int> e;
      std::vector<Vec2> p;
      for (int n : s.nodes) {
        e.push_back(vertex_of[static_cast<std::size_t>(n)]);
        p.push_back(vertices[static_cast<std::size_t>(e.back())]);
      }
      if (signed_area(p) < 0) std::reverse(e.begin(), e.end());
      elements.push_back(std::move(e));
    }
    try {
      return Mesh(std::move(vertices), std::move(elements), surface_regions());
    } catch (const MeshError& err) {
      const int e = err.element();
      if (e >= 0 && static_cast<std::size_t>(e) < surfaces_.size()) {
        const auto& s = surfaces_[static_cast<std::size_t>(e)];
        throw MeshError("Gmsh element " + std::to_string(s.tag) + ": " + err.detail(), e, where(s.line));
      }
      throw MeshError(err.detail(), e, where(elements_header_));
    }
  }

  /// The edges of each 1D physical group (by tag), from the line elements of its entities;
  /// a line element that is no edge of the mesh is an error.
  std::map<int, std::vector<int>> group_edges(const Mesh& mesh, const std::vector<int>& vertex_of) const {
    std::map<std::pair<int, int>, int> edge_of;
    for (int i = 0; i < mesh.num_edges(); ++i) {
      const auto& ed = mesh.edge(i);
      edge_of.emplace(std::minmax(ed.v0, ed.v1), i);
    }
    std::map<int, std::vector<int>> group_edges;  // 1D physical tag -> edges
    for (const auto& [key, name] : physical_names_)
      if (key.first == 1) group_edges[key.second];
    for (const auto& [entity, tags] : entity_physicals_[1])
      for (int t : tags) group_edges[t];
    for (const auto& l : lines_elements_) {
      const int a = vertex_of[static_cast<std::size_t>(l.n0)];
      const int b = vertex_of[static_cast<std::size_t>(l.n1)];
      const auto it = a < 0 || b < 0 ? edge_of.end() : edge_of.find(std::minmax(a, b));
      if (it == edge_of.end())
        fail(l.line, "line element " + std::to_string(l.tag) + " (nodes " + std::to_string(nodes_[static_cast<std::size_t>(l.n0)].tag) +
                         " " + std::to_string(nodes_[static_cast<std::size_t>(l.n1)].tag) +
                         ") is not an edge of the surface mesh");
      const auto ent = entity_physicals_[1].find(l.entity);
      if (ent == entity_physicals_[1].end()) continue;
      for (int t : ent->second) group_edges[t].push_back(it->second);
    }
    return group_edges;
  }

  /// Edge groups from the 1D physical groups, named by $PhysicalNames or else by tag.
  void add_edge_groups(Mesh& mesh, const std::vector<int>& vertex_of) const {
    std::map<std::string, int> names;
    for (auto& [tag, edges] : group_edges(mesh, vertex_of)) {
      const auto named = physical_names_.find({1, tag});
      const std::string name = named != physical_names_.end() ? named->second : std::to_string(tag);
      if (const auto [it, fresh] = names.emplace(name, tag); !fresh)
        fail(physical_names_line_ != 0 ? physical_names_line_ : last_line_,
             "the 1D physical groups " + std::to_string(it->second) + " and " + std::to_string(tag) +
                 " have the same name " + quote(name));
      std::sort(edges.begin(), edges.end());
      edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
      mesh.set_edge_group(name, std::move(edges));
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
  std::vector<SurfaceElement> surfaces_;
  std::vector<LineElement> lines_elements_;
};

}  // namespace

Mesh read_gmsh(const fs::path& path) {
  std::ifstream in = text::open_for_reading(path, "mesh file");
  return read_gmsh(in, path.string());
}

Mesh read_gmsh(std::istream& in, const std::string& name) {
  return GmshReader(text::read_all(in, name, "mesh"), name).read();
}

}  // namespace hemivem
