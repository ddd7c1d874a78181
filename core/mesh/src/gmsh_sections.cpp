// The sections of a Gmsh MSH 4.1 ASCII file common to the plane and solid readers (see
// gmsh_sections.hpp, gmsh.cpp and gmsh3d.cpp).
//
// Every count is checked against the lines the file actually holds before anything is sized
// from it, and every error names "path:line".
#include "gmsh_sections.hpp"

#include <algorithm>
#include <climits>
#include <cmath>

namespace hemivem::detail {

using text::Line;
using text::Parse;
using text::quote;

namespace {

const char* const kEntityKind[4] = {"point", "curve", "surface", "volume"};

/// Nodes per element and dimension of a Gmsh element type.
struct ElementType {
  int nodes = 0;
  int dim = -1;
};

/// The element types read, or 0 nodes for the others: 2-node lines (type 1), 3-node triangles
/// (2), 4-node quadrangles (3), points (15) and, in a solid mesh (`region_dim` 3), 4-node
/// tetrahedra (4), 8-node hexahedra (5), 6-node prisms (6) and 5-node pyramids (7).
ElementType element_type(long long type, int region_dim) {
  ElementType t;
  switch (type) {
    case 1: t = {2, 1}; break;
    case 2: t = {3, 2}; break;
    case 3: t = {4, 2}; break;
    case 4: t = {4, 3}; break;
    case 5: t = {8, 3}; break;
    case 6: t = {6, 3}; break;
    case 7: t = {5, 3}; break;
    case 15: t = {1, 0}; break;
    default: break;
  }
  return t.dim <= region_dim ? t : ElementType{};
}

}  // namespace

GmshSections::GmshSections(std::istream& in, std::string name, Dialect dialect)
    : in_(&in), name_(std::move(name)), dialect_(std::move(dialect)) {}

void GmshSections::fail(int line, const std::string& message) const { throw InputError(message, where(line)); }

void GmshSections::read_sections() {
  if (!in_) throw InternalError("the sections of " + name_ + " read twice");
  text::LineStream lines(*in_, name_, "mesh");
  lines_ = &lines;
  last_line_ = lines.last_line();
  const bool empty = lines.total() == 0;
  bool format = false;
  std::string opened;  // the section header's text, held while its section is read
  while (lines_->next(line_)) {
    opened.assign(line_.text);
    const Line line{line_.number, opened};
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
    fail(last_line_, empty ? "the file holds no data: expected $MeshFormat"
                                    : "the file holds no $MeshFormat section");
  if (nodes_line_ == 0) fail(last_line_, "the file has no $Nodes section");
  if (elements_line_ == 0) fail(last_line_, "the file has no $Elements section");
  // what was read is in nodes_, top_ and below_: the stream is left, and the index of the nodes'
  // tags given back (swapped with an empty one: assigning an empty one keeps the storage)
  lines_ = nullptr;
  in_ = nullptr;
  decltype(tokens_)().swap(tokens_);
  decltype(node_index_)().swap(node_index_);
}

// ---- lines and tokens

void GmshSections::once(int& seen, const Line& line) {
  if (seen != 0)
    fail(line, "a second " + std::string(line.text) + " section (the first is at line " + std::to_string(seen) + ")");
  seen = line.number;
}

/// The next data line of the section opened at `header`, tokenized; `what` says what was expected.
const Line& GmshSections::data_line(const Line& header, const std::string& what) {
  const std::string opened = std::string(header.text) + " (line " + std::to_string(header.number) + ")";
  if (!lines_->next(line_)) fail(last_line_, "the file ends inside " + opened + " while expecting " + what);
  if (line_.text.front() == '$') fail(line_, "expected " + what + " in " + opened + ", found " + quote(line_.text));
  text::tokenize(line_.text, tokens_);
  return line_;
}

void GmshSections::end_section(const Line& header) {
  const std::string end = "$End" + std::string(header.text.substr(1));
  if (!lines_->next(line_))
    fail(last_line_, "the file ends before " + end + " (closing line " + std::to_string(header.number) + ")");
  const Line& line = line_;
  if (line.text != end)
    fail(line, "expected " + end + " (closing line " + std::to_string(header.number) + "), found " +
                   quote(line.text));
}

void GmshSections::skip_section(const Line& header) {
  const std::string end = "$End" + std::string(header.text.substr(1));
  while (lines_->next(line_))
    if (line_.text == end) return;
  fail(last_line_, "the file ends before " + end + " (closing line " + std::to_string(header.number) + ")");
}

long long GmshSections::integer(const Line& line, std::size_t i, const std::string& what) {
  long long v = 0;
  if (i >= tokens_.size()) fail(line, "missing " + what + " in " + quote(line.text));
  if (text::parse_integer(tokens_[i], v) != Parse::ok)
    fail(line, "bad " + what + " " + quote(tokens_[i]) + " (expected an integer)");
  return v;
}

/// A count: non-negative and at most INT_MAX (the callers check it further against the lines
/// left, so nothing is ever sized from an absurd count).
long long GmshSections::count(const Line& line, std::size_t i, const std::string& what) {
  const long long n = integer(line, i, what);
  if (n < 0) fail(line, what + " " + std::to_string(n) + " is negative");
  if (n > INT_MAX)
    fail(line, what + " " + std::to_string(n) + " is too large (at most " + std::to_string(INT_MAX) + ")");
  return n;
}

void GmshSections::expect_tokens(const Line& line, std::size_t n, const std::string& what) {
  if (tokens_.size() != n)
    fail(line, what + " has " + std::to_string(tokens_.size()) + " values, expected " + std::to_string(n) +
                   " (found " + quote(line.text) + ")");
}

// ---- sections

void GmshSections::read_format(const Line& header) {
  const Line& line = data_line(header, "the format line '4.1 0 8'");
  if (tokens_.size() != 3) fail(line, "expected the format line '4.1 0 8', found " + quote(line.text));
  if (tokens_[0] != "4.1")
    fail(line, "MSH format version " + quote(tokens_[0]) +
                   " is not supported: only version 4.1 is read (save with Mesh.MshFileVersion = 4.1)");
  if (tokens_[1] == "1") fail(line, "binary MSH files are not supported: save the mesh as ASCII (Mesh.Binary = 0)");
  if (tokens_[1] != "0") fail(line, "bad file type " + quote(tokens_[1]) + " (expected 0, ASCII)");
  long long size = 0;
  if (text::parse_integer(tokens_[2], size) != Parse::ok)
    fail(line, "bad data size " + quote(tokens_[2]) + " (expected 8)");
  end_section(header);
}

void GmshSections::read_physical_names(const Line& header) {
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

void GmshSections::read_entities(const Line& header) {
  const Line& cl = data_line(header, "the entity counts 'numPoints numCurves numSurfaces numVolumes'");
  expect_tokens(cl, 4, "the count line of $Entities");
  long long n[4];
  for (int d = 0; d < 4; ++d) n[d] = count(cl, static_cast<std::size_t>(d), "entity count");
  const int rd = dialect_.region_dim;
  for (int d = 0; d < 4; ++d) {
    for (long long i = 0; i < n[d]; ++i) {
      const Line& line = data_line(header, std::to_string(n[d]) + " " + kEntityKind[d] + " entity lines (found " +
                                               std::to_string(i) + ")");
      if (d > rd) continue;  // above the mesh's dimension: not used
      const std::string what = std::string(kEntityKind[d]) + " ";
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
        if (d == rd && (p < 1 || p > kGmshMaxRegion))
          fail(line, "physical " + what + "tag " + std::to_string(p) + " cannot be a region id: " + what +
                         "tags are kept as region ids, from 1 to " + std::to_string(kGmshMaxRegion));
        tags.push_back(static_cast<int>(p));
      }
      if (!entity_physicals_[d].emplace(tag, std::move(tags)).second)
        fail(line, what + "entity " + std::to_string(tag) + " is listed twice");
    }
  }
  end_section(header);
}

GmshSections::BlockCounts GmshSections::block_counts(const Line& header, const BlockWords& w) {
  const std::string noun = w.noun, Noun = w.Noun;
  const Line& line = data_line(header, "'numEntityBlocks num" + Noun + "s min" + Noun + "Tag max" + Noun + "Tag'");
  expect_tokens(line, 4, "the count line of " + std::string(header.text));
  const long long blocks = count(line, 0, noun + " block count");
  const long long total = count(line, 1, noun + " count");
  integer(line, 2, "minimum " + noun + " tag");
  integer(line, 3, "maximum " + noun + " tag");
  // A node takes two lines, an element one.
  if (static_cast<unsigned long long>(total) > lines_left())
    fail(line, "the " + noun + " count " + std::to_string(total) + " exceeds what the rest of the file can hold");
  return {line.number, blocks, total};
}

GmshSections::BlockHeader GmshSections::block_header(const Line& header, const BlockWords& w, long long blocks,
                                                     long long b) {
  const std::string noun = w.noun;
  const Line& line = data_line(header, std::to_string(blocks) + " " + noun + " blocks (found " + std::to_string(b) +
                                           "): 'entityDim entityTag " + w.kind_field + " num" + w.Noun + "sInBlock'");
  expect_tokens(line, 4, w.article + (" " + noun) + " block header");
  const long long dim = integer(line, 0, "entity dimension");
  const long long entity = integer(line, 1, "entity tag");
  const long long kind = integer(line, 2, w.kind);
  const long long n = count(line, 3, noun + " count of the block");
  return {line.number, dim, entity, kind, n};
}

void GmshSections::read_nodes(const Line& header) {
  static const BlockWords words{"node", "Node", "a", "parametric", "parametric flag"};
  const auto [hl, blocks, total] = block_counts(header, words);
  nodes_.reserve(static_cast<std::size_t>(total));
  long long read = 0;
  for (long long b = 0; b < blocks; ++b) {
    const auto [bl, dim, entity, parametric, n] = block_header(header, words, blocks, b);
    if (dim < 0 || dim > 3) fail(bl, "entity dimension " + std::to_string(dim) + " is not 0, 1, 2 or 3");
    if (parametric != 0 && parametric != 1)
      fail(bl, "the parametric flag is " + std::to_string(parametric) + ", not 0 or 1");
    if (read + n > total)
      fail(bl, "the node blocks hold more nodes than the " + std::to_string(total) + " declared at line " +
                   std::to_string(hl));
    const std::size_t first = nodes_.size();
    for (long long i = 0; i < n; ++i) {
      const Line& line = data_line(header, std::to_string(n) + " node tags of the block at line " +
                                               std::to_string(bl) + " (found " + std::to_string(i) + ")");
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
      GmshNode& node = nodes_[first + static_cast<std::size_t>(i)];
      const std::string what = "node " + std::to_string(node.tag);
      const Line& line = data_line(header, std::to_string(n) + " node coordinate lines of the block at line " +
                                               std::to_string(bl) + " (found " + std::to_string(i) + ")");
      expect_tokens(line, values, "the coordinate line of " + what);
      double c[3];
      for (int k = 0; k < 3; ++k) {
        const std::string_view token = tokens_[static_cast<std::size_t>(k)];
        if (text::parse_real(token, c[k]) != Parse::ok || !std::isfinite(c[k]))
          fail(line, what + " has a " + "xyz"[k] + " coordinate " + quote(token) + " that is not a finite number");
        if (std::abs(c[k]) > dialect_.max_coordinate)
          fail(line, what + " has a " + "xyz"[k] + " coordinate " + quote(token) + " of magnitude above " +
                         dialect_.too_large);
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

void GmshSections::read_elements(const Line& header) {
  static const BlockWords words{"element", "Element", "an", "elementType", "element type"};
  const auto [hl, blocks, total] = block_counts(header, words);
  elements_header_ = hl;
  const int rd = dialect_.region_dim;
  long long read = 0;
  for (long long b = 0; b < blocks; ++b) {
    const auto [bl, dim, entity, type, n] = block_header(header, words, blocks, b);
    const ElementType et = element_type(type, rd);
    if (et.nodes == 0) refuse_element_type(bl, type);
    if (dim != et.dim)
      fail(bl, "element type " + std::to_string(type) + " is of dimension " + std::to_string(et.dim) +
                   " but its block is on an entity of dimension " + std::to_string(dim));
    if (read + n > total)
      fail(bl, "the element blocks hold more elements than the " + std::to_string(total) + " declared at line " +
                   std::to_string(hl));
    // the elements kept: on entities of the top dimension and of the one below
    const bool kept = dim >= rd - 1;
    if (kept && entities_line_ != 0 && !entity_physicals_[dim].count(entity))
      fail(bl, std::string(kEntityKind[dim]) + " entity " + std::to_string(entity) + " is not in $Entities");
    const std::size_t nn = static_cast<std::size_t>(et.nodes);
    GmshElements* into = !kept ? nullptr : dim == rd ? &top_ : &below_;
    if (into) into->reserve_more(static_cast<std::size_t>(n), static_cast<std::size_t>(n) * nn);
    std::vector<int> ids(nn);
    for (long long i = 0; i < n; ++i) {
      const Line& line = data_line(header, std::to_string(n) + " element lines of the block at line " +
                                               std::to_string(bl) + " (found " + std::to_string(i) + ")");
      const long long tag = integer(line, 0, "element tag");
      const std::string what = "element " + std::to_string(tag);
      if (tokens_.size() != nn + 1)
        fail(line, what + " (type " + std::to_string(type) + ") lists " + std::to_string(tokens_.size() - 1) +
                       " node tags, expected " + std::to_string(nn));
      for (std::size_t k = 0; k < nn; ++k) {
        const long long t = integer(line, k + 1, "node tag of " + what);
        const auto it = node_index_.find(t);
        if (it == node_index_.end())
          fail(line, what + " refers to node tag " + std::to_string(t) + ", which is not in $Nodes");
        ids[k] = it->second;
      }
      if (into) into->push_back(ids, type, tag, entity, line.number);
    }
    read += n;
  }
  if (read != total)
    fail(hl, "$Elements declares " + std::to_string(total) + " elements but its blocks hold " + std::to_string(read));
  end_section(header);
}

// ---- the mesh

std::vector<int> GmshSections::vertex_numbers() const {
  std::vector<int> vertex_of(nodes_.size(), -1);
  for (const GmshElement& e : top_)
    for (int n : e.nodes) vertex_of[static_cast<std::size_t>(n)] = 0;
  int vertices = 0;
  for (int& v : vertex_of)
    if (v == 0) v = vertices++;
  return vertex_of;
}

void GmshSections::rethrow_at_element(const MeshError& err, std::string (*label)(const GmshElement&)) const {
  const int e = err.element();
  if (e >= 0 && static_cast<std::size_t>(e) < top_.size()) {
    const GmshElement& element = top_[static_cast<std::size_t>(e)];
    throw MeshError("Gmsh element " + std::to_string(element.tag) + (label ? label(element) : std::string()) + ": " +
                        err.detail(),
                    e, where(element.line));
  }
  throw MeshError(err.detail(), e, where(elements_header_));
}

// ---- regions and groups

std::vector<int> GmshSections::top_numbers() const {
  std::vector<int> all(top_.size());
  for (std::size_t e = 0; e < all.size(); ++e) all[e] = static_cast<int>(e);
  return all;
}

int GmshSections::region_of(long long entity) const {
  const auto& physicals = entity_physicals_[dialect_.region_dim];
  const auto it = physicals.find(entity);
  if (it == physicals.end() || it->second.empty()) return 0;
  return it->second.front();
}

std::vector<std::pair<std::string, FacetKeys>> GmshSections::piece_groups(const std::vector<GroupedFacet>& facets,
                                                                          const std::vector<char>& kept) const {
  std::map<int, FacetKeys> by_tag;
  for (const auto& [tag, none] : empty_groups()) by_tag[tag];
  for (const GroupedFacet& g : facets)
    if (std::any_of(g.cells.begin(), g.cells.end(), [&](int c) { return c >= 0 && kept[static_cast<std::size_t>(c)]; }))
      for (int t : *g.tags) by_tag[t].push_back(g.key);
  std::map<std::string, int> names;
  std::vector<std::pair<std::string, FacetKeys>> out;
  for (auto& [tag, keys] : by_tag) out.emplace_back(group_name(tag, names), std::move(keys));
  return out;
}

std::map<int, std::vector<int>> GmshSections::empty_groups() const {
  const int gd = dialect_.region_dim - 1;
  std::map<int, std::vector<int>> groups;
  for (const auto& [key, name] : physical_names_)
    if (key.first == gd) groups[key.second];
  for (const auto& [entity, tags] : entity_physicals_[gd])
    for (int t : tags) groups[t];
  return groups;
}

const std::vector<int>* GmshSections::groups_of(long long entity) const {
  const auto& physicals = entity_physicals_[dialect_.region_dim - 1];
  const auto it = physicals.find(entity);
  return it == physicals.end() ? nullptr : &it->second;
}

std::string GmshSections::group_name(int tag, std::map<std::string, int>& names) const {
  const int gd = dialect_.region_dim - 1;
  const auto named = physical_names_.find({gd, tag});
  std::string name = named != physical_names_.end() ? named->second : std::to_string(tag);
  if (const auto [it, fresh] = names.emplace(name, tag); !fresh)
    fail(physical_names_line_ != 0 ? physical_names_line_ : last_line_,
         "the " + std::to_string(gd) + "D physical groups " + std::to_string(it->second) + " and " +
             std::to_string(tag) + " have the same name " + quote(name));
  return name;
}

}  // namespace hemivem::detail
