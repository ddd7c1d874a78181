// Reader and writer of the `.poly2d` mesh format (see mesh_io.hpp).
//
// The reader takes the whole input into memory, splits it into numbered lines and
// then walks the significant (non-blank, non-comment) lines section by section.
// Every count is checked against what the file actually holds before anything is
// sized from it, so an absurd count costs nothing. Mesh rules are checked by the
// Mesh constructor (find_mesh_defects); its error is re-thrown with the line of the
// offending element.
#include <hemivem/support/atomic_file.hpp>
#include <hemivem/mesh/poly2d.hpp>

#include <hemivem/support/text_lines.hpp>

#include "cell_topology.hpp"

#include <algorithm>
#include <charconv>
#include <climits>
#include <cmath>
#include <fstream>
#include <istream>
#include <memory>
#include <ostream>
#include <string_view>
#include <system_error>


namespace hemivem {

namespace fs = std::filesystem;

namespace {

using text::kWhitespace;
using text::quote;
using text::shown;

bool is_keyword(std::string_view t) { return t == "vertices" || t == "elements" || t == "boundary"; }

using text::Parse;
using text::parse_integer;
using text::parse_real;

using text::Line;

class Poly2dReader {
 public:
  /// Reads `in` line by line, on construction (a stream of no more than the file's lines is held).
  Poly2dReader(std::istream& in, std::string name) : name_(std::move(name)) {
    text::LineStream lines(in, name_, "mesh", '#', &comments_);
    lines_ = &lines;
    last_line_ = lines.last_line();
    empty_ = lines.total() == 0;
    read_lists(boundary_list_);
    lines_ = nullptr;
  }

  Poly2dMesh read() {
    Poly2dMesh out;
    out.boundary_list = std::move(boundary_list_);
    out.mesh = mesh_of(std::move(vertices_), std::move(elements_));
    out.comments = std::move(comments_);
    return out;
  }

  /// The lists of the pieces `turn` asks for, chosen among the elements' edges (found once)
  /// without the whole mesh; the file's cells kept.
  void read_pieces(const detail::PiecesInTurn<Mesh>& turn, HeldPoints held) {
    taken_ = take_cells();
    detail::make_plane_pieces(taken_, held, turn);
  }

  /// The vertices and elements read, taken, the mesh not made (for piece).
  detail::PlaneCells take_cells() {
    return {std::move(vertices_), std::move(elements_)};
  }

  /// The piece of the mesh of `cells` (take_cells') that `who` keeps, chosen among the
  /// elements' edges without the whole mesh.
  MeshPieceRead<Mesh> piece(const detail::PlaneCells& cells, const detail::PieceOwner& who, HeldPoints held) const {
    PieceLists<Mesh> lists;
    detail::make_plane_pieces(cells, held, detail::piece_of(who, lists));
    return made(cells, std::move(lists));
  }

  /// The piece of `lists` (make_piece) of the mesh of `cells` (of the file's cells kept), a
  /// defect of its elements named as read_poly2d names the whole mesh's first.
  MeshPieceRead<Mesh> made(const detail::PlaneCells& cells, PieceLists<Mesh> lists) const {
    try {
      return make_piece(std::move(lists));
    } catch (const MeshError&) {
      (void)mesh_of(cells.vertices, cells.elements);
      throw;
    }
  }
  MeshPieceRead<Mesh> made(PieceLists<Mesh> lists) const { return made(taken_, std::move(lists)); }

  /// After read_pieces: throws the whole mesh's first defect as read_poly2d names it, if it has
  /// one.
  void name_defect() const { name_defect(taken_); }
  /// The same of the mesh of `cells` (take_cells').
  void name_defect(const detail::PlaneCells& cells) const { (void)mesh_of(cells.vertices, cells.elements); }

 private:
  /// Reads the vertices, the elements and the optional boundary list.
  void read_lists(std::vector<int>& boundary_list) {
    vheader_ = expect_header("vertices", "NV", "vertex count");
    const int nv = header_count_;
    vertices_ = read_vertices(nv, vheader_);
    eheader_ = expect_header("elements", "NE", "element count");
    elements_ = read_elements(header_count_, nv, eheader_, element_lines_);
    if (lines_->next(line_)) {
      lines_->put_back();
      boundary_list = read_boundary(nv);
    }
  }

  /// The mesh of the elements, or its first defect at the line of its element.
  Mesh mesh_of(std::vector<Vec2> vertices, std::vector<std::vector<int>> elements) const {
    const bool none = vertices.empty();
    try {
      return Mesh(std::move(vertices), std::move(elements));
    } catch (const MeshError& err) {
      const int e = err.element();
      int line = eheader_;
      if (e >= 0 && static_cast<std::size_t>(e) < element_lines_.size())
        line = element_lines_[static_cast<std::size_t>(e)];
      else if (none)
        line = vheader_;
      throw MeshError(err.detail(), e, where(line));
    }
  }

  /// The `nv` lines `x y` after the header `vertices NV`.
  std::vector<Vec2> read_vertices(int nv, int vheader) {
    std::vector<Vec2> vertices;
    vertices.reserve(bounded(nv));
    for (int i = 0; i < nv; ++i) {
      const Line& line = data_line(i, nv, "vertex", "vertices", vheader);
      if (tokens_.size() != 2)
        fail(line, "vertex " + std::to_string(i) + " has " + std::to_string(tokens_.size()) +
                       (tokens_.size() == 1 ? " value" : " values") +
                       "; a vertex line holds exactly 2 coordinates 'x y' (found " + quote(line.text) + ")");
      Vec2 p;
      for (int c = 0; c < 2; ++c) p[c] = coordinate(i, c, line);
      vertices.push_back(p);
    }
    return vertices;
  }

  /// Coordinate `c` (0: x, 1: y) of vertex `i`, from tokens_: a finite double of magnitude at
  /// most max_mesh_coordinate.
  double coordinate(int i, int c, const Line& line) const {
    const std::string what = "vertex " + std::to_string(i) + " has " + (c == 0 ? "an x" : "a y") + " coordinate ";
    double v = 0.0;
    switch (parse_real(tokens_[c], v)) {
      case Parse::bad: fail(line, what + quote(tokens_[c]) + " that is not a number");
      case Parse::out_of_range: fail(line, what + quote(tokens_[c]) + " outside the range of double");
      case Parse::ok: break;
    }
    if (!std::isfinite(v)) fail(line, what + quote(tokens_[c]) + " that is not finite");
    if (std::abs(v) > max_mesh_coordinate)
      fail(line, what + quote(tokens_[c]) + " of magnitude above 1e150 (element areas would overflow)");
    return v;
  }

  /// The `ne` lines `k v1 ... vk` after the header `elements NE`; `element_lines` receives
  /// the line of each.
  std::vector<std::vector<int>> read_elements(int ne, int nv, int eheader, std::vector<int>& element_lines) {
    std::vector<std::vector<int>> elements;
    elements.reserve(bounded(ne));
    element_lines.reserve(bounded(ne));
    long long total_indices = 0;
    for (int e = 0; e < ne; ++e) {
      const Line& line = data_line(e, ne, "element", "elements", eheader);
      elements.push_back(element(e, nv, line, total_indices));
      element_lines.push_back(line.number);
    }
    return elements;
  }

  /// The vertex indices of element `e`, from tokens_; `total_indices` counts those of all
  /// elements so far.
  std::vector<int> element(int e, int nv, const Line& line, long long& total_indices) const {
    const std::string el = "element " + std::to_string(e);
    long long k = 0;
    if (parse_integer(tokens_[0], k) != Parse::ok)
      fail(line, el + " has a bad vertex count " + quote(tokens_[0]) + " (expected an integer k >= 3)");
    if (k < 3)
      throw MeshError(el + " has " + std::to_string(k) + (k == 1 ? " vertex" : " vertices") +
                          "; an element needs at least 3",
                      e, where(line));
    const std::size_t listed = tokens_.size() - 1;
    if (static_cast<unsigned long long>(k) != listed)
      fail(line, el + " declares " + std::to_string(k) + " vertices but lists " + std::to_string(listed) +
                     (listed == 1 ? " index" : " indices"));
    total_indices += k;
    if (total_indices > INT_MAX)
      fail(line, "the elements hold more than " + std::to_string(INT_MAX) + " vertex indices in total");
    std::vector<int> ids;
    ids.reserve(listed);
    for (std::size_t j = 1; j < tokens_.size(); ++j) {
      long long v = 0;
      const Parse r = parse_integer(tokens_[j], v);
      if (r == Parse::bad)
        fail(line, el + " has a bad vertex index " + quote(tokens_[j]) + " (expected an integer)");
      if (r == Parse::out_of_range || v < 0 || v >= nv)
        throw MeshError(el + " has vertex index " + shown(tokens_[j]) + " out of range [0, " +
                            std::to_string(nv) + ")",
                        e, where(line));
      ids.push_back(static_cast<int>(v));
    }
    return ids;
  }

  /// The optional list `boundary NB` and its NB vertex indices, which must end the file.
  std::vector<int> read_boundary(int nv) {
    lines_->next(line_);
    tokenize(line_.text);
    if (tokens_[0] != "boundary")
      fail(line_, "unexpected content after the element list: " + quote(line_.text) +
                      " (expected 'boundary NB' or the end of the file)");
    lines_->put_back();
    const int bheader = expect_header("boundary", "NB", "boundary count");
    const int nb = header_count_;
    std::vector<int> boundary_list;
    boundary_list.reserve(bounded(nb));
    for (int b = 0; b < nb; ++b) {
      const Line& bl = data_line(b, nb, "boundary", "boundary", bheader);
      const std::string entry = "boundary entry " + std::to_string(b);
      if (tokens_.size() != 1)
        fail(bl, entry + " has " + std::to_string(tokens_.size()) +
                     " values; a boundary line holds exactly one vertex index (found " + quote(bl.text) + ")");
      long long v = 0;
      const Parse r = parse_integer(tokens_[0], v);
      if (r == Parse::bad) fail(bl, entry + " has a bad vertex index " + quote(tokens_[0]) + " (expected an integer)");
      if (r == Parse::out_of_range || v < 0 || v >= nv)
        fail(bl, entry + " has vertex index " + shown(tokens_[0]) + " out of range [0, " +
                     std::to_string(nv) + ")");
      boundary_list.push_back(static_cast<int>(v));
    }
    if (lines_->next(line_))
      fail(line_, "unexpected content after the boundary list: " + quote(line_.text) + " (the file should end here)");
    return boundary_list;
  }

  void tokenize(std::string_view line) { text::tokenize(line, tokens_); }

  std::string where(int line) const { return name_ + ":" + std::to_string(line); }
  std::string where(const Line& line) const { return where(line.number); }
  [[noreturn]] void fail(int line, const std::string& message) const { throw InputError(message, where(line)); }
  [[noreturn]] void fail(const Line& line, const std::string& message) const { fail(line.number, message); }

  /// A capacity to reserve for `count` records: never more than the lines left.
  std::size_t bounded(int count) const {
    return std::min(static_cast<std::size_t>(count), lines_->remaining());
  }

  /// Reads the header line `keyword N`, stores N in header_count_ and returns its line's number.
  int expect_header(std::string_view keyword, std::string_view count_name, const std::string& count_what) {
    std::string form(1, '\'');
    form.append(keyword).append(" ").append(count_name).append("'");
    if (!lines_->next(line_))
      fail(last_line_, empty_ ? "the file holds no data: expected the header " + form
                              : "the file ends before the header " + form);
    const Line& line = line_;
    tokenize(line.text);
    if (tokens_[0] != keyword)
      fail(line, "expected the header " + form + ", found " + quote(line.text));
    if (tokens_.size() == 1) fail(line, "the header " + form + " has no count");
    if (tokens_.size() > 2) fail(line, "the header " + form + " has extra content after the count: " + quote(line.text));
    long long n = 0;
    switch (parse_integer(tokens_[1], n)) {
      case Parse::bad:
        fail(line, "bad " + count_what + " " + quote(tokens_[1]) + " (expected a non-negative integer)");
      case Parse::out_of_range:
        n = LLONG_MAX;
        break;
      case Parse::ok:
        break;
    }
    if (n < 0) fail(line, count_what + " " + shown(tokens_[1]) + " is negative");
    if (n > INT_MAX)
      fail(line, count_what + " " + shown(tokens_[1]) + " is too large (at most " + std::to_string(INT_MAX) + ")");
    header_count_ = static_cast<int>(n);
    return line.number;
  }

  /// The next line of a list of `count` records, tokenized into tokens_, or an error at
  /// the line where the list runs out.
  const Line& data_line(int index, int count, const std::string& record, const std::string& section, int header) {
    const std::string expected = "expected " + std::to_string(count) + " " + record + " lines after '" + section +
                                 " " + std::to_string(count) + "' (line " + std::to_string(header) + ")";
    if (!lines_->next(line_)) fail(last_line_, expected + ", but the file ends after " + std::to_string(index));
    tokenize(line_.text);
    if (is_keyword(tokens_[0]))
      fail(line_, expected + ", but the list ends after " + std::to_string(index) + " (found " + quote(line_.text) + ")");
    return line_;
  }

  std::string name_;
  text::LineStream* lines_ = nullptr;  // while the file is read
  Line line_;                          // the line read last
  bool empty_ = false;                 // no line but blank ones and comments
  int vheader_ = 0, eheader_ = 0;      // the lines of the headers
  std::vector<int> boundary_list_;
  std::vector<Vec2> vertices_;
  detail::PlaneCells taken_;  // the cells read_pieces took
  std::vector<std::vector<int>> elements_;
  std::vector<int> element_lines_;
  std::vector<std::string> comments_;
  std::vector<std::string_view> tokens_;
  int last_line_ = 1;
  int header_count_ = 0;
};

/// Splits a comment into lines and drops trailing whitespace (which the reader drops too).
void write_comment(std::ostream& out, std::string_view comment) {
  while (true) {
    const std::size_t nl = comment.find_first_of("\r\n");
    std::string_view line = comment.substr(0, nl);
    const std::size_t last = line.find_last_not_of(kWhitespace);
    line = last == std::string_view::npos ? std::string_view() : line.substr(0, last + 1);
    out << '#';
    if (!line.empty()) out << ' ' << line;
    out << '\n';
    if (nl == std::string_view::npos) break;
    comment.remove_prefix(nl + 1);
  }
}

}  // namespace

Poly2dMesh read_poly2d(std::istream& in, const std::string& name) {
  return Poly2dReader(in, name).read();
}

Poly2dMesh read_poly2d(const fs::path& path) {
  std::ifstream in = text::open_for_reading(path, "mesh file");
  return read_poly2d(in, path.string());
}

MeshPieceRead<Mesh> read_poly2d_piece(std::istream& in, const std::string& name, int rank, int size, HeldPoints held) {
  return detail::read_own_piece<Mesh, Poly2dReader>(in, name, rank, size, held);
}

MeshPieceRead<Mesh> read_poly2d_piece(const fs::path& path, const RowDistribution& processes, HeldPoints held,
                                   const BoundaryPick<Mesh>& pick) {
  return detail::read_piece_by_first<Mesh, Poly2dReader>(path, processes, held, pick);
}

MeshPieceRead<Mesh> read_poly2d_piece(const fs::path& path, int rank, int size, HeldPoints held, const BoundaryPick<Mesh>& pick) {
  std::ifstream in = text::open_for_reading(path, "mesh file");
  return detail::read_own_piece<Mesh, Poly2dReader>(in, path.string(), rank, size, held, pick);
}

MeshLists<Mesh> read_poly2d_lists(std::istream& in, const std::string& name) {
  auto reader = std::make_shared<Poly2dReader>(in, name);
  auto cells = std::make_shared<const detail::PlaneCells>(reader->take_cells());
  return {static_cast<int>(cells->vertices.size()),
          [reader, cells](const std::vector<char>& owned, HeldPoints held) {
            return reader->piece(*cells, {.owned = &owned}, held);
          },
          [cells](int size, const std::function<std::vector<char>(int)>& owned, HeldPoints held,
                  const PieceDelivery<Mesh>& deliver) {
            detail::make_plane_pieces(*cells, held, detail::pieces_around<Mesh>(size, owned, deliver));
          },
          [reader, cells] { reader->name_defect(*cells); }};
}

MeshLists<Mesh> read_poly2d_lists(const fs::path& path) {
  std::ifstream in = text::open_for_reading(path, "mesh file");
  return read_poly2d_lists(in, path.string());
}

void write_poly2d(std::ostream& out, const Mesh& mesh, const std::vector<std::string>& comments) {
  if (mesh.num_vertices() == 0 || mesh.num_elements() == 0)
    throw InputError("cannot write an empty mesh (it would not read back)");
  if (!out) throw InputError("cannot write the mesh: the output stream is in a failed state");
  for (const auto& c : comments) write_comment(out, c);
  // Numbers go through to_chars, not the stream or printf, so no locale can change them.
  // Precision 17 in the general format is %.17g: every double reads back unchanged.
  std::string text;
  auto put = [&text](auto value, auto... format) {
    char buf[64];
    const auto r = std::to_chars(buf, buf + sizeof buf, value, format...);
    text.append(buf, r.ptr);
  };
  auto emit = [&](bool force) {
    if (force || text.size() >= (1u << 16)) {
      out.write(text.data(), static_cast<std::streamsize>(text.size()));
      text.clear();
    }
  };
  text += "vertices ";
  put(mesh.num_vertices());
  text += '\n';
  for (const auto& p : mesh.vertices()) {
    put(p.x(), std::chars_format::general, 17);
    text += ' ';
    put(p.y(), std::chars_format::general, 17);
    text += '\n';
    emit(false);
  }
  text += "elements ";
  put(mesh.num_elements());
  text += '\n';
  for (int e = 0; e < mesh.num_elements(); ++e) {
    put(mesh.element_size(e));
    for (int v : mesh.element(e)) {
      text += ' ';
      put(v);
    }
    text += '\n';
    emit(false);
  }
  const std::vector<int> boundary = mesh.boundary_vertices();
  text += "boundary ";
  put(boundary.size());
  text += '\n';
  for (int v : boundary) {
    put(v);
    text += '\n';
    emit(false);
  }
  emit(true);
  out.flush();
  if (!out) throw InputError("writing the mesh failed");
}

void write_poly2d(const fs::path& path, const Mesh& mesh, const std::vector<std::string>& comments) {
  const std::string name = path.string();
  if (path.filename().empty()) throw InputError("cannot write the mesh: the path names no file", name);
  write_file_atomically(path, [&](std::ostream& out) {
    try {
      write_poly2d(out, mesh, comments);
    } catch (const InputError& e) {
      throw InputError(e.detail(), name);
    }
  });
}

}  // namespace hemivem
