// The sections of a Gmsh MSH 4.1 ASCII file, as the readers of plane meshes (gmsh.cpp) and of
// solid meshes (gmsh3d.cpp) both read them: $MeshFormat, $PhysicalNames, $Entities, $Nodes
// and the framing of $Elements (block headers, node tags, counts), with every other section
// skipped and $PartitionedEntities refused. A reader derives from GmshSections, says how it
// refuses the element types it does not read, calls read_sections() and builds its mesh from
// what was read.
//
// The regions of a mesh are the physical tags of the entities of its top dimension (surfaces
// in a plane mesh, volumes in a solid one); the groups are those of the dimension below.
// Elements of these two dimensions are kept; points (and lines in a solid mesh) are only
// checked.
#pragma once

#include <hemivem/error.hpp>
#include <hemivem/mesh/mesh_piece.hpp>
#include <hemivem/support/text_lines.hpp>

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <iterator>
#include <map>
#include <span>
#include <string>
#include <string_view>
#include <unordered_map>
#include <utility>
#include <vector>

namespace hemivem::detail {

/// Region ids (physical tags of the entities of the top dimension) a file may hold.
inline constexpr long long kGmshMaxRegion = 1000000;

struct GmshNode {
  double x = 0, y = 0, z = 0;
  long long tag = 0;
  int tag_line = 0;  // line of the tag
  int line = 0;      // line of the coordinates
};

/// An element as read: a view of what GmshElements holds of it.
struct GmshElement {
  std::span<const int> nodes;  // node indices (into nodes_)
  long long type = 0;
  long long tag = 0;
  long long entity = 0;
  int line = 0;
};

/// Elements in flat arrays, their node indices one after another: about 25 bytes each beside
/// their nodes' 4, where a list of nodes each took a vector's 24 and its allocation's 16 more.
class GmshElements {
 public:
  std::size_t size() const noexcept { return type_.size(); }
  bool empty() const noexcept { return type_.empty(); }
  GmshElement operator[](std::size_t k) const {
    const auto from = static_cast<std::size_t>(start_[k]);
    return {std::span<const int>(nodes_).subspan(from, static_cast<std::size_t>(start_[k + 1]) - from), type_[k], tag_[k],
            entity_[k], line_[k]};
  }
  /// Room for `elements` more elements of `nodes` nodes in all: exactly, or twice what is held
  /// where that is more, so that many small blocks grow the arrays as a vector grows.
  void reserve_more(std::size_t elements, std::size_t nodes) {
    grow(start_, elements);
    grow(tag_, elements);
    grow(entity_, elements);
    grow(line_, elements);
    grow(type_, elements);
    grow(nodes_, nodes);
  }
  void push_back(std::span<const int> nodes, long long type, long long tag, long long entity, int line) {
    nodes_.insert(nodes_.end(), nodes.begin(), nodes.end());
    start_.push_back(static_cast<int>(nodes_.size()));
    type_.push_back(static_cast<std::int8_t>(type));
    tag_.push_back(tag);
    entity_.push_back(entity);
    line_.push_back(line);
  }

  /// Each element in order, by value.
  class const_iterator {
   public:
    using value_type = GmshElement;
    using reference = GmshElement;
    using difference_type = std::ptrdiff_t;
    using iterator_category = std::input_iterator_tag;
    const_iterator(const GmshElements* elements, std::size_t k) : elements_(elements), k_(k) {}
    GmshElement operator*() const { return (*elements_)[k_]; }
    const_iterator& operator++() {
      ++k_;
      return *this;
    }
    bool operator==(const const_iterator& other) const { return k_ == other.k_; }

   private:
    const GmshElements* elements_;
    std::size_t k_;
  };
  const_iterator begin() const { return {this, 0}; }
  const_iterator end() const { return {this, size()}; }

 private:
  template <class T>
  static void grow(std::vector<T>& v, std::size_t more) {
    if (v.size() + more > v.capacity()) v.reserve(std::max(v.size() + more, 2 * v.capacity()));
  }
  std::vector<int> start_{0}, nodes_;
  std::vector<long long> tag_, entity_;
  std::vector<int> line_;
  std::vector<std::int8_t> type_;  // the types kept are below 16
};

class GmshSections {
 public:
  /// What the mesh of a reader is made of.
  struct Dialect {
    int region_dim = 2;         ///< 2 (plane meshes) or 3 (solid meshes); $Entities above it are skipped
    double max_coordinate = 0;  ///< the largest |coordinate| read
    std::string too_large;      ///< said of a larger one: "1e150 (element areas would overflow)"
  };

  GmshSections(const GmshSections&) = delete;
  GmshSections& operator=(const GmshSections&) = delete;

 protected:
  /// Reads `in` (which must outlive read_sections(), and is not read after it) line by line.
  GmshSections(std::istream& in, std::string name, Dialect dialect);
  ~GmshSections() = default;

  /// Throws the InputError (at the line `block`) for an element type the reader does not read.
  [[noreturn]] virtual void refuse_element_type(int block, long long type) const = 0;

  /// Reads every section of the file; throws InputError without $MeshFormat, $Nodes or $Elements.
  void read_sections();

  std::string where(int line) const { return name_ + ":" + std::to_string(line); }
  [[noreturn]] void fail(int line, const std::string& message) const;
  [[noreturn]] void fail(const text::Line& line, const std::string& message) const { fail(line.number, message); }

  /// The vertex of each node: the nodes of the elements of the top dimension, numbered 0, 1,
  /// ... in $Nodes order; -1 for the other nodes.
  std::vector<int> vertex_numbers() const;
  /// How many nodes vertex_numbers numbers.
  int vertex_count() const { return numbered(vertex_numbers()); }
  /// How many nodes `vertex_of` (vertex_numbers) numbers.
  static int numbered(const std::vector<int>& vertex_of) {
    return static_cast<int>(std::count_if(vertex_of.begin(), vertex_of.end(), [](int v) { return v >= 0; }));
  }
  /// Throws `err` (from the mesh constructor, about an element of top_ or none) again naming
  /// the Gmsh element ("Gmsh element <tag><label>: ...") at its line, else at the $Elements
  /// count line.
  [[noreturn]] void rethrow_at_element(const MeshError& err,
                                       std::string (*label)(const GmshElement&) = nullptr) const;
  /// The piece of `lists` (make_piece); a defect of its cells named as the whole reader names
  /// the whole mesh's first (name_defect() throws it), else at the piece's cell's element.
  template <class MeshType, class NameDefect>
  MeshPieceRead<MeshType> made_piece(PieceLists<MeshType> lists, NameDefect&& name_defect,
                                     std::string (*label)(const GmshElement&) = nullptr) const {
    const std::vector<int> cells = lists.piece.cells;
    try {
      return make_piece(std::move(lists));
    } catch (const MeshError& err) {
      name_defect();
      const auto c = static_cast<std::size_t>(err.element());
      rethrow_at_element(MeshError(err.detail(), err.element() >= 0 && c < cells.size() ? cells[c] : -1), label);
    }
  }
  /// A facet of an element of below_ in a group: the element's groups, the facet's vertices,
  /// increasing, and its cells (the second -1 on the boundary).
  struct GroupedFacet {
    const std::vector<int>* tags;
    std::vector<int> key;
    std::array<int, 2> cells;
  };
  /// A piece's facet groups (PieceLists::groups): every group (empty_groups) in the order of
  /// the tags, named (group_name), each with the facets of `facets` that a cell `kept` flags
  /// holds, in their order.
  std::vector<std::pair<std::string, FacetKeys>> piece_groups(const std::vector<GroupedFacet>& facets,
                                                              const std::vector<char>& kept) const;
  /// The numbers of the elements of top_: 0, 1, ..., top_.size() - 1.
  std::vector<int> top_numbers() const;
  /// The region of an entity of the top dimension: its first physical tag, 0 without one.
  int region_of(long long entity) const;
  /// Every group (physical tag of dimension region_dim - 1) named in $PhysicalNames or given
  /// to an entity, with no members yet.
  std::map<int, std::vector<int>> empty_groups() const;
  /// The groups of an entity of dimension region_dim - 1; null when $Entities does not list it.
  const std::vector<int>* groups_of(long long entity) const;
  /// The name of the group `tag`: its physical name, else its tag; InputError when an earlier
  /// group (in `names`, name -> tag, where it is added) has the same name.
  std::string group_name(int tag, std::map<std::string, int>& names) const;

  int last_line_ = 1;
  int elements_header_ = 0;  // the count line of $Elements
  std::vector<GmshNode> nodes_;
  /// The elements on entities of the top dimension (top_) and of the one below (below_), in file order.
  GmshElements top_, below_;

 private:
  std::size_t lines_left() const { return lines_->remaining(); }
  void once(int& seen, const text::Line& line);
  const text::Line& data_line(const text::Line& header, const std::string& what);
  void end_section(const text::Line& header);
  void skip_section(const text::Line& header);
  long long integer(const text::Line& line, std::size_t i, const std::string& what);
  long long count(const text::Line& line, std::size_t i, const std::string& what);
  void expect_tokens(const text::Line& line, std::size_t n, const std::string& what);

  /// The words of $Nodes or $Elements in messages: "node", "Node", "a", the third value of a
  /// block header ("parametric") and what it is ("parametric flag").
  struct BlockWords {
    std::string noun, Noun, article, kind_field, kind;
  };
  /// The count line 'numEntityBlocks numNodes minNodeTag maxNodeTag' of $Nodes (opened at
  /// `header`), or its like in $Elements: the block count and the total, which the rest of the
  /// file has lines for.
  struct BlockCounts {
    int line;
    long long blocks, total;
  };
  BlockCounts block_counts(const text::Line& header, const BlockWords& words);
  /// The header 'entityDim entityTag parametric numNodesInBlock' of block `b` of `blocks` (or its
  /// like in $Elements).
  struct BlockHeader {
    int line;
    long long dim, entity, kind, size;
  };
  BlockHeader block_header(const text::Line& header, const BlockWords& words, long long blocks, long long b);

  void read_format(const text::Line& header);
  void read_physical_names(const text::Line& header);
  void read_entities(const text::Line& header);
  void read_nodes(const text::Line& header);
  void read_elements(const text::Line& header);

  std::istream* in_;
  std::string name_;
  Dialect dialect_;
  text::LineStream* lines_ = nullptr;  // while the sections are read
  text::Line line_;                    // the line read last
  std::vector<std::string_view> tokens_;

  int physical_names_line_ = 0, entities_line_ = 0, nodes_line_ = 0, elements_line_ = 0;
  std::map<std::pair<int, int>, std::string> physical_names_;
  std::map<long long, std::vector<int>> entity_physicals_[4];
  std::unordered_map<long long, int> node_index_;
};

}  // namespace hemivem::detail
