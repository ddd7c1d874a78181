// A process's piece of a mesh made whole (hemivem/mesh/mesh_piece.hpp).
#include <hemivem/mesh/mesh_piece.hpp>

#include <hemivem/error.hpp>
#include <hemivem/row_distribution.hpp>
#include <hemivem/mesh/dimension.hpp>
#include <hemivem/support/bytes.hpp>

#include "cell_kernels.hpp"
#include "cell_topology.hpp"
#include "hilbert.hpp"

#include <algorithm>
#include <array>
#include <cstdint>
#include <iterator>
#include <map>
#include <memory>
#include <optional>
#include <string>

namespace hemivem {

namespace {

using detail::CellTopology;

std::span<const int> vertices_of(const Mesh& mesh, int c) { return mesh.element(c); }
std::span<const int> vertices_of(const Mesh3D& mesh, int c) { return mesh.cell_vertices(c); }
std::vector<int> vertices_of(const CellTopology& cells, int c) { return cells.cell_vertices(c); }

/// The two cells of facet f (the second -1 on the boundary; a mesh's: hemivem/mesh/facet_cells.hpp).
std::array<int, 2> facet_cells(const CellTopology& cells, int f) { return cells.facet_cells(f); }

/// A solid facet's vertex loop.
std::span<const int> facet_loop(const Mesh3D& mesh, int f) { return mesh.face(f).vertices; }
std::vector<int> facet_loop(const CellTopology& cells, int f) { return cells.facet_loop(f); }

bool is_plane(const Mesh3D&) { return false; }
bool is_plane(const CellTopology& cells) { return cells.dim() == 2; }

/// Adds to `keep` the cells of paths through the mesh (across facets) that join the kept cells
/// of each connected part of the mesh (a body) into one, so that the kept cells are as many
/// bodies as the mesh holds of them: in each body, one breadth-first search from the part of
/// the kept cells that holds its first kept cell, each other part joined along the path by
/// which the search first reached it.
template <class MeshType>
void join_parts(const MeshType& mesh, std::vector<char>& keep) {
  const auto nc = static_cast<std::size_t>(mesh.num_cells());
  std::vector<int> parent(nc, -2);  // -2: not reached; -1: in the body's first part
  std::vector<int> queue;
  // the searches end once every cell kept at first is reached (the parts all joined)
  const auto kept_at_first = static_cast<std::size_t>(std::count(keep.begin(), keep.end(), 1));
  std::size_t reached = 0;
  // the kept cells reached across kept cells' facets from `from`
  const auto grow_part = [&](std::size_t from) {
    std::vector<int> stack{static_cast<int>(from)};
    while (!stack.empty()) {
      const int c = stack.back();
      stack.pop_back();
      queue.push_back(c);
      for (int f : cell_facets(mesh, c))
        for (int d : facet_cells(mesh, f))
          if (d >= 0 && keep[static_cast<std::size_t>(d)] && parent[static_cast<std::size_t>(d)] == -2) {
            parent[static_cast<std::size_t>(d)] = -1;
            ++reached;
            stack.push_back(d);
          }
    }
  };
  for (std::size_t first = 0; first < nc && reached < kept_at_first; ++first) {
    if (!keep[first] || parent[first] != -2) continue;  // a body's first kept cell not yet reached
    queue.clear();
    parent[first] = -1;
    ++reached;
    grow_part(first);
    for (std::size_t head = 0; head < queue.size() && reached < kept_at_first; ++head) {
      const int c = queue[head];
      for (int f : cell_facets(mesh, c))
        for (int d : facet_cells(mesh, f)) {
          if (d < 0 || parent[static_cast<std::size_t>(d)] != -2) continue;
          parent[static_cast<std::size_t>(d)] = c;
          if (!keep[static_cast<std::size_t>(d)]) {
            queue.push_back(d);
            continue;
          }
          // another part reached: the path to it kept, and with the part joined to the first
          for (int p = c; parent[static_cast<std::size_t>(p)] >= 0;) {
            const int up = parent[static_cast<std::size_t>(p)];
            keep[static_cast<std::size_t>(p)] = 1;
            parent[static_cast<std::size_t>(p)] = -1;
            p = up;
          }
          parent[static_cast<std::size_t>(d)] = -1;
          ++reached;
          grow_part(static_cast<std::size_t>(d));
        }
    }
  }
}

/// How a piece's kept cells are joined into one part in each body, prepared once for a mesh and
/// the cells every piece of it holds (`fixed`, increasing: of the facets every piece holds): the
/// fixed cells joined to one another (join_parts: the spine), and from every cell of a body that
/// holds any, the next cell of a shortest path across facets to the spine (a search from all the
/// spine's cells at once). A piece's kept cells are then joined by its spine and, from the cell of
/// each of its other parts nearest the spine, the path to the first kept cell on the way, which
/// lies nearer (so each part reaches the spine); a body without fixed cells by join_parts. Each
/// piece then costs its own cells' work and one pass over the flags, not a search through the body.
template <class MeshType>
class PieceJoiner {
 public:
  PieceJoiner(const MeshType& mesh, const std::vector<int>& fixed)
      : mesh_(&mesh), spine_(static_cast<std::size_t>(mesh.num_cells()), 0) {
    for (int c : fixed) spine_[static_cast<std::size_t>(c)] = 1;
    join_parts(mesh, spine_);
    distance_.assign(spine_.size(), -1);
    toward_.assign(spine_.size(), -1);
    std::vector<int> queue;
    for (std::size_t c = 0; c < spine_.size(); ++c)
      if (spine_[c]) distance_[c] = 0, queue.push_back(static_cast<int>(c));
    for (std::size_t head = 0; head < queue.size(); ++head) {
      const int c = queue[head];
      for (int f : cell_facets(mesh, c))
        for (int d : facet_cells(mesh, f))
          if (d >= 0 && distance_[static_cast<std::size_t>(d)] < 0) {
            distance_[static_cast<std::size_t>(d)] = distance_[static_cast<std::size_t>(c)] + 1;
            toward_[static_cast<std::size_t>(d)] = c;
            queue.push_back(d);
          }
    }
  }

  /// The spine: the cells every piece keeps.
  const std::vector<char>& spine() const { return spine_; }

  /// Adds to `keep` (which holds the spine) the cells that join its parts in each body.
  void join(std::vector<char>& keep) const {
    const MeshType& mesh = *mesh_;
    std::vector<char> seen(keep.size(), 0), apart(keep.size(), 0);  // apart: of bodies without a spine
    bool any_apart = false;
    std::vector<int> stack;
    for (std::size_t first = 0; first < keep.size(); ++first) {
      if (!keep[first] || seen[first]) continue;
      // the part of `first`: the kept cells reached across kept cells' facets, and its cell nearest the spine
      int nearest = static_cast<int>(first);
      seen[first] = 1;
      stack.assign(1, static_cast<int>(first));
      std::vector<int> part;
      while (!stack.empty()) {
        const int c = stack.back();
        stack.pop_back();
        part.push_back(c);
        if (distance_[static_cast<std::size_t>(c)] < distance_[static_cast<std::size_t>(nearest)]) nearest = c;
        for (int f : cell_facets(mesh, c))
          for (int d : facet_cells(mesh, f))
            if (d >= 0 && keep[static_cast<std::size_t>(d)] && !seen[static_cast<std::size_t>(d)]) {
              seen[static_cast<std::size_t>(d)] = 1;
              stack.push_back(d);
            }
      }
      if (distance_[static_cast<std::size_t>(nearest)] < 0) {  // a body without a spine
        for (int c : part) apart[static_cast<std::size_t>(c)] = 1;
        any_apart = true;
        continue;
      }
      for (int p = toward_[static_cast<std::size_t>(nearest)]; p >= 0 && !keep[static_cast<std::size_t>(p)];
           p = toward_[static_cast<std::size_t>(p)])
        keep[static_cast<std::size_t>(p)] = 1;
    }
    if (!any_apart) return;
    join_parts(mesh, apart);
    for (std::size_t c = 0; c < keep.size(); ++c) keep[c] = keep[c] || apart[c];
  }

 private:
  const MeshType* mesh_;
  std::vector<char> spine_;
  std::vector<int> distance_;  // to the spine across facets; -1 in a body without one
  std::vector<int> toward_;    // the next cell on the way to the spine; -1 in it or without one
};

/// The cells of each vertex: a CellTopology's own, a mesh's counted here.
const VertexCells& cells_of_vertices(const CellTopology& cells) { return cells.vertex_cells(); }
template <class MeshType>
VertexCells cells_of_vertices(const MeshType& mesh) {
  return vertex_cells(mesh.num_vertices(), mesh.num_cells(), [&](int c) { return vertices_of(mesh, c); });
}

/// Adds to `keep` every cell around each edge of the kept cells' surface that is not in two of
/// its faces (two kept cells meeting along an edge alone), until there is none: the kept cells
/// then make a mesh (Mesh3D's rule for the boundary). Nothing to do in the plane.
void close_edges(const Mesh&, std::vector<char>&) {}
template <class SolidCells>
void close_edges(const SolidCells& mesh, std::vector<char>& keep) {
  if (is_plane(mesh)) return;
  const VertexCells& around = cells_of_vertices(mesh);  // a solid mesh's held here while the edges are closed
  for (;;) {
    std::vector<std::uint64_t> edges;  // the edges of the faces on the kept cells' surface
    for (int c = 0; c < mesh.num_cells(); ++c) {
      if (!keep[static_cast<std::size_t>(c)]) continue;
      for (int f : cell_facets(mesh, c)) {
        const auto [a, b] = facet_cells(mesh, f);
        const int other = a == c ? b : a;
        if (other >= 0 && keep[static_cast<std::size_t>(other)]) continue;
        const auto loop = facet_loop(mesh, f);
        for (std::size_t i = 0; i < loop.size(); ++i) {
          const auto u = static_cast<std::uint64_t>(loop[i]), w = static_cast<std::uint64_t>(loop[(i + 1) % loop.size()]);
          edges.push_back(std::min(u, w) << 32 | std::max(u, w));
        }
      }
    }
    std::sort(edges.begin(), edges.end());
    bool added = false;
    for (std::size_t k = 0; k < edges.size();) {
      std::size_t e = k + 1;
      while (e < edges.size() && edges[e] == edges[k]) ++e;
      if (e - k != 2) {  // the cells holding both ends
        const auto a = static_cast<std::size_t>(edges[k] >> 32), b = static_cast<std::size_t>(edges[k] & 0xffffffffu);
        for (const int c : around.of(static_cast<int>(a))) {
          if (keep[static_cast<std::size_t>(c)]) continue;
          const auto vs = vertices_of(mesh, c);
          if (std::binary_search(vs.begin(), vs.end(), static_cast<int>(b))) keep[static_cast<std::size_t>(c)] = 1, added = true;
        }
      }
      k = e;
    }
    if (!added) return;
  }
}

/// The cells of the facets `facets`, increasing. InputError for a facet out of range.
template <class MeshType>
std::vector<int> cells_of_facets(const MeshType& mesh, std::span<const int> facets) {
  std::vector<int> cells;
  for (int f : facets) {
    if (f < 0 || f >= mesh.num_facets())
      throw InputError("a piece of a mesh of " + std::to_string(mesh.num_facets()) + " facets given the facet " +
                       std::to_string(f));
    for (int c : facet_cells(mesh, f))
      if (c >= 0) cells.push_back(c);
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  return cells;
}

/// The piece's cells around the vertices `owned` flags, with the cells every piece holds (of the
/// facets every piece holds, cells_of_facets: `joiner`'s spine).
template <class MeshType>
std::vector<int> cells_around(const MeshType& mesh, const std::vector<char>& owned, const PieceJoiner<MeshType>& joiner) {
  const auto nv = static_cast<std::size_t>(mesh.num_vertices());
  if (owned.size() != nv)
    throw InputError("a piece of a mesh of " + std::to_string(nv) + " vertices given flags for " +
                     std::to_string(owned.size()));
  std::vector<char> keep = joiner.spine();
  // the vertices of the cells holding an owned vertex: a cell holding one of them is in the piece
  const VertexCells& around = cells_of_vertices(mesh);
  std::vector<char> near = owned;
  for (std::size_t v = 0; v < nv; ++v)
    if (owned[v])
      for (int c : around.of(static_cast<int>(v)))
        for (int w : vertices_of(mesh, c)) near[static_cast<std::size_t>(w)] = 1;
  for (std::size_t v = 0; v < nv; ++v)
    if (near[v])
      for (int c : around.of(static_cast<int>(v))) keep[static_cast<std::size_t>(c)] = 1;
  joiner.join(keep);
  close_edges(mesh, keep);
  std::vector<int> out;
  for (int c = 0; c < mesh.num_cells(); ++c)
    if (keep[static_cast<std::size_t>(c)]) out.push_back(c);
  return out;
}

/// The body of each vertex of a plane mesh: the connected part of its cells that holds it (the
/// pieces of a mesh of several bodies, whose vertices may coincide across bodies: Mesh's
/// `bodies`). A solid mesh is told nothing.
std::vector<int> vertex_bodies(const Mesh& mesh) {
  std::vector<int> up(static_cast<std::size_t>(mesh.num_vertices()));
  for (std::size_t v = 0; v < up.size(); ++v) up[v] = static_cast<int>(v);
  const auto at = [&](int v) -> int& { return up[static_cast<std::size_t>(v)]; };
  const auto root = [&](int v) {
    while (at(v) != v) v = at(v) = at(at(v));  // halving the path on the way up
    return v;
  };
  for (int c = 0; c < mesh.num_elements(); ++c) {
    const auto vs = mesh.element(c);
    for (int v : vs) up[static_cast<std::size_t>(root(v))] = root(vs[0]);
  }
  for (std::size_t v = 0; v < up.size(); ++v) up[v] = root(static_cast<int>(v));
  return up;
}
std::vector<int> vertex_bodies(const Mesh3D&) { return {}; }

/// The box of the points (as Mesh::bounding_box and Mesh3D::bounding_box).
Rectangle box_of(const std::vector<Vec2>& p) {
  Rectangle r{p.at(0).x(), p[0].x(), p[0].y(), p[0].y()};
  for (const Vec2& v : p) r = {std::min(r.x0, v.x()), std::max(r.x1, v.x()), std::min(r.y0, v.y()), std::max(r.y1, v.y())};
  return r;
}
Box box_of(const std::vector<Vec3>& p) {
  Vec3 lo = p.at(0), hi = lo;
  for (const Vec3& v : p) lo = lo.cwiseMin(v), hi = hi.cwiseMax(v);
  return {lo.x(), hi.x(), lo.y(), hi.y(), lo.z(), hi.z()};
}

/// What every piece of a mesh holds whatever its vertices, found once for all the pieces made of
/// it: the cells of the facets `facets` (a file's groups), of every boundary facet and of the
/// first facet of each region's first cell; and the whole mesh's sums over its cells
/// (MeshPieceRead's). hold_facets puts a BoundaryPick's facets in place of the first two.
struct WholeRule {
  std::vector<int> cells;  ///< the cells of those facets, increasing
  double cell_vertices = 0, cell_vertices_squared = 0;
  int largest_cell = 0;
  std::vector<int> region_facets;  ///< the first facet of each region's first cell
  std::shared_ptr<const PieceJoiner<CellTopology>> joiner;  ///< of `cells`
};

/// `rule` holding the cells of the facets `facets` and of its regions' first facets alone.
void hold_facets(WholeRule& rule, const CellTopology& cells, std::vector<int> facets) {
  facets.insert(facets.end(), rule.region_facets.begin(), rule.region_facets.end());
  rule.cells = cells_of_facets(cells, facets);
  rule.joiner = std::make_shared<const PieceJoiner<CellTopology>>(cells, rule.cells);
}

WholeRule whole_rule(const CellTopology& cells, const std::vector<int>& regions, std::vector<int> facets) {
  WholeRule rule;
  for (int f = 0; f < cells.num_facets(); ++f)
    if (cells.is_facet(f) && cells.facet_cells(f)[1] < 0) facets.push_back(f);
  std::vector<int> seen;  // a cell of each region
  for (int c = 0; c < cells.num_cells(); ++c) {
    if (const int r = regions[static_cast<std::size_t>(c)]; std::find(seen.begin(), seen.end(), r) == seen.end()) {
      seen.push_back(r);
      rule.region_facets.push_back(cells.cell_facets(c)[0]);
    }
    const auto m = static_cast<double>(cells.cell_vertices(c).size());
    rule.cell_vertices += m;
    rule.cell_vertices_squared += m * m;
    rule.largest_cell = std::max(rule.largest_cell, static_cast<int>(m));
  }
  hold_facets(rule, cells, std::move(facets));
  return rule;
}

/// The piece around the vertices `owned` flags (choose's rule); out.order, first and end left;
/// `kept` flags its cells among the mesh's.
template <class Vec, class MeshType>
detail::FacetKeys choose_around(const CellTopology& cells, const std::vector<Vec>& vertices, const WholeRule& rule,
                                std::vector<char> owned, HeldPoints held, MeshPieceRead<MeshType>& out,
                                std::vector<char>& kept) {
  if (owned.size() != static_cast<std::size_t>(cells.num_vertices()))
    throw InternalError("a piece of a mesh of " + std::to_string(cells.num_vertices()) + " vertices given flags for " +
                        std::to_string(owned.size()));
  out.cell_vertices = rule.cell_vertices;
  out.cell_vertices_squared = rule.cell_vertices_squared;
  out.largest_cell = rule.largest_cell;
  for (const auto& q : held) {  // the nearest vertex, as a support at the point picks it
    constexpr int dim = Vec::RowsAtCompileTime;
    const int nearest = nearest_point<dim>(vertices, Eigen::Map<const Eigen::Vector3d>(q.data()).head<dim>()).first;
    if (nearest >= 0) owned[static_cast<std::size_t>(nearest)] = 1;
  }
  out.cells = cells_around(cells, owned, *rule.joiner);
  out.whole_cells = cells.num_cells();
  kept.assign(static_cast<std::size_t>(cells.num_cells()), 0);
  for (int c : out.cells) kept[static_cast<std::size_t>(c)] = 1;
  detail::FacetKeys cuts;
  for (int c : out.cells)
    for (int f : cells.cell_facets(c)) {
      const std::array<int, 2> two = cells.facet_cells(f);
      const int other = two[0] == c ? two[1] : two[0];
      if (other < 0 || kept[static_cast<std::size_t>(other)]) continue;
      std::vector<int> key = cells.facet_loop(f);
      std::sort(key.begin(), key.end());
      cuts.push_back(std::move(key));
    }
  std::sort(cuts.begin(), cuts.end());
  return cuts;
}

template <class Vec>
std::vector<int> order_of(const std::vector<Vec>& vertices) {
  std::vector<int> order;
  if (!vertices.empty()) {
    const std::vector<std::size_t> perm = detail::hilbert_order(vertices, box_of(vertices));
    order.assign(perm.begin(), perm.end());
  }
  return order;
}

/// choose_around the vertices `who` flags, or of its process's share of them along `order`
/// (the vertices' Hilbert order), which out.order, first and end then tell; `kept` flags its
/// cells.
template <class Vec, class MeshType>
detail::FacetKeys chosen(const CellTopology& cells, const std::vector<Vec>& vertices, const WholeRule& rule,
                         const detail::PieceOwner& who, const std::vector<int>& order, HeldPoints held,
                         MeshPieceRead<MeshType>& out, std::vector<char>& kept) {
  if (who.owned) return choose_around(cells, vertices, rule, *who.owned, held, out, kept);
  if (who.flags) return choose_around(cells, vertices, rule, who.flags(), held, out, kept);
  const int rank = who.rank, size = who.size;
  if (size < 1 || rank < 0 || rank >= size)
    throw InternalError("a piece of a mesh for process " + std::to_string(rank) + " of " + std::to_string(size));
  const auto [first, end] = even_share(cells.num_vertices(), rank, size);
  std::vector<char> owned(static_cast<std::size_t>(cells.num_vertices()), 0);
  for (auto k = first; k < end; ++k) owned[static_cast<std::size_t>(order[static_cast<std::size_t>(k)])] = 1;
  detail::FacetKeys cuts = choose_around(cells, vertices, rule, std::move(owned), held, out, kept);
  out.order = order;
  out.first = static_cast<int>(first);
  out.end = static_cast<int>(end);
  return cuts;
}

std::vector<int> sorted_vertices(const Mesh& mesh, int e) {
  return {std::min(mesh.edge(e).v0, mesh.edge(e).v1), std::max(mesh.edge(e).v0, mesh.edge(e).v1)};
}
std::vector<int> sorted_vertices(const Mesh3D& mesh, int f) {
  std::vector<int> key = mesh.face(f).vertices;
  std::sort(key.begin(), key.end());
  return key;
}
bool on_boundary(const Mesh& mesh, int e) { return mesh.edge(e).right < 0; }
bool on_boundary(const Mesh3D& mesh, int f) { return mesh.face(f).outer < 0; }

template <class MeshType>
void cut_facets_of(MeshPieceRead<MeshType>& out, const detail::FacetKeys& cuts) {
  out.cut_facets.clear();
  for (int f = 0; f < out.mesh.num_facets(); ++f)
    if (on_boundary(out.mesh, f) && std::binary_search(cuts.begin(), cuts.end(), sorted_vertices(out.mesh, f)))
      out.cut_facets.push_back(f);
}

}  // namespace

namespace detail {

namespace {

/// Whether the cells are one body: each reached from the first across the facets they share.
bool one_body(const CellTopology& cells) {
  std::vector<int> up(static_cast<std::size_t>(cells.num_cells()));
  for (std::size_t c = 0; c < up.size(); ++c) up[c] = static_cast<int>(c);
  const auto root = [&](int c) {
    while (up[static_cast<std::size_t>(c)] != c) c = up[static_cast<std::size_t>(c)] = up[static_cast<std::size_t>(up[static_cast<std::size_t>(c)])];
    return c;
  };
  int bodies = cells.num_cells();
  for (int f = 0; f < cells.num_facets(); ++f) {
    if (!cells.is_facet(f)) continue;
    const auto [a, b] = cells.facet_cells(f);
    if (b < 0) continue;
    const int ra = root(a), rb = root(b);
    if (ra != rb) up[static_cast<std::size_t>(ra)] = rb, --bodies;
  }
  return bodies == 1;
}

/// The facets of `cells` that `pick` picks on the piece of no vertex (BoundaryPick) made by
/// `rule` (every boundary facet's and `facets`' cells), or nothing when the cells are not one
/// body or their piece meets a defect (MeshError: the pieces find it).
template <class Vec, class MeshType>
std::optional<std::vector<int>> picked_facets(const CellTopology& cells, const std::vector<Vec>& vertices,
                                              const WholeRule& rule, const BoundaryPick<MeshType>& pick,
                                              const MakePieceLists<MeshType>& make_lists) {
  if (!pick || !one_body(cells)) return std::nullopt;
  const std::vector<char> none(static_cast<std::size_t>(cells.num_vertices()), 0);
  PieceLists<MeshType> sides;
  std::vector<char> kept;
  sides.cuts = chosen(cells, vertices, rule, PieceOwner{.owned = &none}, {}, {}, sides.piece, kept);
  make_lists(sides, kept, false);
  MeshPieceRead<MeshType> made;
  try {
    made = make_piece(std::move(sides));
  } catch (const MeshError&) {
    return std::nullopt;
  }
  std::vector<int> facets;
  for (const std::vector<int>& key : pick(std::move(made))) {
    const int f = cells.find_facet(key);
    if (f < 0) throw InternalError("a pick of a piece's boundary names a facet the mesh does not hold");
    facets.push_back(f);
  }
  return facets;
}

template <class Vec, class MeshType>
void pieces_in_turn(std::unique_ptr<const CellTopology> cells, const std::vector<Vec>& vertices,
                    const std::vector<int>& regions, const std::vector<int>& facets, HeldPoints held,
                    const PiecesInTurn<MeshType>& turn, const MakePieceLists<MeshType>& make_lists) {
  // found once for all the pieces
  WholeRule rule = whole_rule(*cells, regions, facets);
  const std::optional<std::vector<int>> picked = picked_facets(*cells, vertices, rule, turn.pick, make_lists);
  if (picked) hold_facets(rule, *cells, *picked);
  std::vector<int> order;
  if (std::any_of(turn.whose.begin(), turn.whose.end(), [](const PieceOwner& w) { return !w.owned && !w.flags; }))
    order = order_of(vertices);
  std::vector<char> kept;
  for (std::size_t k = 0; k < turn.whose.size(); ++k) {
    PieceLists<MeshType> lists;
    lists.cuts = chosen(*cells, vertices, rule, turn.whose[k], order, held, lists.piece, kept);
    lists.piece.picked = picked.has_value();
    const bool last = k + 1 == turn.whose.size();
    if (last) cells.reset();  // the topology freed before the last piece's lists are made
    make_lists(lists, kept, last);
    turn.deliver(k, std::move(lists));
  }
}

/// make_plane_pieces and make_solid_pieces: topology() the cells of `cells`; the pieces `turn`
/// asks for, all in region 0.
template <class Vec, class Cell, class MeshType, class Topology>
void make_list_pieces(const std::vector<Vec>& vertices, const std::vector<Cell>& cells, const Topology& topology,
                      HeldPoints held, const PiecesInTurn<MeshType>& turn) {
  const std::vector<int> regions(cells.size(), 0);
  const MakePieceLists<MeshType> make_lists = [&](PieceLists<MeshType>& lists, const std::vector<char>&, bool) {
    lists.vertices = vertices;
    lists.cells.reserve(lists.piece.cells.size());
    for (int c : lists.piece.cells) lists.cells.push_back(cells[static_cast<std::size_t>(c)]);
  };
  pieces_in_turn(std::make_unique<const CellTopology>(topology()), vertices, regions, {}, held, turn, make_lists);
}

/// The one piece of `who` of the cells `cells` (make_list_pieces).
template <class Vec, class Cell, class MeshType, class Topology>
void make_list_piece(const std::vector<Vec>& vertices, const std::vector<Cell>& cells, const Topology& topology,
                     HeldPoints held, const PieceOwner& who, MeshPieceRead<MeshType>& out) {
  PieceLists<MeshType> lists;
  make_list_pieces(vertices, cells, topology, held, piece_of(who, lists));
  out = make_piece(std::move(lists));
}

}  // namespace

void make_pieces(std::unique_ptr<const CellTopology> cells, const std::vector<Vec2>& vertices,
                 const std::vector<int>& regions, const std::vector<int>& facets, HeldPoints held,
                 const PiecesInTurn<Mesh>& turn, const MakePieceLists<Mesh>& make_lists) {
  pieces_in_turn(std::move(cells), vertices, regions, facets, held, turn, make_lists);
}
void make_pieces(std::unique_ptr<const CellTopology> cells, const std::vector<Vec3>& vertices,
                 const std::vector<int>& regions, const std::vector<int>& facets, HeldPoints held,
                 const PiecesInTurn<Mesh3D>& turn, const MakePieceLists<Mesh3D>& make_lists) {
  pieces_in_turn(std::move(cells), vertices, regions, facets, held, turn, make_lists);
}

void make_plane_pieces(const PlaneCells& cells, HeldPoints held, const PiecesInTurn<Mesh>& turn) {
  make_list_pieces(
      cells.vertices, cells.elements,
      [&] { return plane_topology(static_cast<int>(cells.vertices.size()), cells.elements); }, held, turn);
}
MeshLists<Mesh> plane_lists(std::shared_ptr<const PlaneCells> cells, std::function<void(MeshPieceRead<Mesh>&)> finish) {
  return {static_cast<int>(cells->vertices.size()),
          [cells, finish](const std::vector<char>& owned, HeldPoints held) {
            MeshPieceRead<Mesh> out;
            make_plane_piece(*cells, owned, held, out);
            if (finish) finish(out);
            return out;
          },
          [cells](int size, const std::function<std::vector<char>(int)>& owned, HeldPoints held,
                  const PieceDelivery<Mesh>& deliver) {
            make_plane_pieces(*cells, held, pieces_around<Mesh>(size, owned, deliver));
          },
          [cells] { (void)Mesh(cells->vertices, cells->elements); }};
}
void make_plane_piece(const PlaneCells& cells, const PieceOwner& who, HeldPoints held, MeshPieceRead<Mesh>& out) {
  make_list_piece(
      cells.vertices, cells.elements,
      [&] { return plane_topology(static_cast<int>(cells.vertices.size()), cells.elements); }, held, who, out);
}
void make_plane_piece(const PlaneCells& cells, HeldPoints held, int rank, int size, MeshPieceRead<Mesh>& out) {
  make_plane_piece(cells, PieceOwner{rank, size}, held, out);
}
void make_plane_piece(const PlaneCells& cells, const std::vector<char>& owned, HeldPoints held, MeshPieceRead<Mesh>& out) {
  make_plane_piece(cells, PieceOwner{.owned = &owned}, held, out);
}

void make_solid_pieces(const SolidCells& cells, HeldPoints held, const PiecesInTurn<Mesh3D>& turn) {
  make_list_pieces(
      cells.vertices, cells.cells, [&] { return solid_topology(static_cast<int>(cells.vertices.size()), cells.cells); },
      held, turn);
}
void make_solid_piece(const SolidCells& cells, HeldPoints held, int rank, int size, MeshPieceRead<Mesh3D>& out) {
  make_list_piece(
      cells.vertices, cells.cells, [&] { return solid_topology(static_cast<int>(cells.vertices.size()), cells.cells); },
      held, PieceOwner{rank, size}, out);
}
void make_solid_piece(const SolidCells& cells, const std::vector<char>& owned, HeldPoints held,
                      MeshPieceRead<Mesh3D>& out) {
  make_list_piece(
      cells.vertices, cells.cells, [&] { return solid_topology(static_cast<int>(cells.vertices.size()), cells.cells); },
      held, PieceOwner{.owned = &owned}, out);
}

}  // namespace detail

namespace {

template <class MeshType>
MeshType cut(const MeshType& mesh, std::span<const int> cells, std::vector<int>* facets) {
  for (std::size_t k = 0; k < cells.size(); ++k)
    if (cells[k] < 0 || cells[k] >= mesh.num_cells() || (k > 0 && cells[k] <= cells[k - 1]))
      throw InputError("the cells of a piece of a mesh of " + std::to_string(mesh.num_cells()) +
                       " cells are not increasing numbers of its cells (at " + std::to_string(k) + ": " +
                       std::to_string(cells[k]) + ")");
  std::vector<decltype(detail::cell_of(mesh, 0))> kept;
  std::vector<int> regions;
  kept.reserve(cells.size());
  regions.reserve(cells.size());
  for (int c : cells) {
    kept.push_back(detail::cell_of(mesh, c));
    regions.push_back(mesh.region(c));
  }
  MeshType piece = detail::make_mesh_of(mesh.vertices(), std::move(kept), std::move(regions), vertex_bodies(mesh));
  if (detail::facet_groups(mesh).empty() && facets == nullptr) return piece;
  // cell c's local facet l is the piece's cell's local facet l (its vertex lists are given in
  // that order)
  std::vector<int> facet_of(static_cast<std::size_t>(mesh.num_facets()), -1);
  for (std::size_t k = 0; k < cells.size(); ++k) {
    const auto whole = cell_facets(mesh, cells[k]);
    const auto mine = cell_facets(piece, static_cast<int>(k));
    for (std::size_t l = 0; l < whole.size(); ++l) facet_of[static_cast<std::size_t>(whole[l])] = mine[l];
  }
  for (const auto& [name, facets] : detail::facet_groups(mesh)) {
    std::vector<int> held;
    for (int f : facets)
      if (const int g = facet_of[static_cast<std::size_t>(f)]; g >= 0) held.push_back(g);
    detail::set_facet_group(piece, name, std::move(held));
  }
  if (facets != nullptr) *facets = std::move(facet_of);
  return piece;
}

}  // namespace

std::vector<int> piece_cells_around(const Mesh& mesh, const std::vector<char>& owned, std::span<const int> facets) {
  return cells_around(mesh, owned, PieceJoiner<Mesh>(mesh, cells_of_facets(mesh, facets)));
}
std::vector<int> piece_cells_around(const Mesh3D& mesh, const std::vector<char>& owned, std::span<const int> facets) {
  return cells_around(mesh, owned, PieceJoiner<Mesh3D>(mesh, cells_of_facets(mesh, facets)));
}

Mesh cut_mesh_piece(const Mesh& mesh, std::span<const int> cells, std::vector<int>* facets) {
  return cut(mesh, cells, facets);
}
Mesh3D cut_mesh_piece(const Mesh3D& mesh, std::span<const int> cells, std::vector<int>* facets) {
  return cut(mesh, cells, facets);
}

namespace {

/// The facets of `mesh` by their vertices, increasing, each to its number.
template <class MeshType>
std::map<std::vector<int>, int> facets_by_vertices(const MeshType& mesh) {
  std::map<std::vector<int>, int> out;
  for (int f = 0; f < mesh.num_facets(); ++f) out.emplace(sorted_vertices(mesh, f), f);
  return out;
}

void set_group(Mesh& mesh, const std::string& name, std::vector<int> edges) {
  std::sort(edges.begin(), edges.end());
  edges.erase(std::unique(edges.begin(), edges.end()), edges.end());
  mesh.set_edge_group(name, std::move(edges));
}
void set_group(Mesh3D& mesh, const std::string& name, std::vector<int> faces) { mesh.set_face_group(name, std::move(faces)); }

template <class MeshType>
MeshPieceRead<MeshType> make_any_piece(PieceLists<MeshType> lists) {
  MeshPieceRead<MeshType> out = std::move(lists.piece);
  out.mesh = MeshType(std::move(lists.vertices), std::move(lists.cells), std::move(lists.regions));
  if (!lists.groups.empty()) {
    const std::map<std::vector<int>, int> facet_of = facets_by_vertices(out.mesh);
    for (const auto& [name, keys] : lists.groups) {
      std::vector<int> facets;
      facets.reserve(keys.size());
      for (const std::vector<int>& key : keys) {
        const auto it = facet_of.find(key);
        if (it == facet_of.end()) throw InternalError("the facet group " + name + " of a piece names a facet it does not hold");
        facets.push_back(it->second);
      }
      set_group(out.mesh, name, std::move(facets));
    }
  }
  cut_facets_of(out, lists.cuts);
  return out;
}

void write_cells(ByteWriter& out, const std::vector<std::vector<int>>& elements) {
  std::vector<int> start{0}, loops;
  for (const auto& e : elements) {
    loops.insert(loops.end(), e.begin(), e.end());
    start.push_back(static_cast<int>(loops.size()));
  }
  out.array(start);
  out.array(loops);
}
void write_cells(ByteWriter& out, const std::vector<CellFaces>& cells) {
  std::vector<int> faces{0}, start{0}, loops;
  for (const CellFaces& c : cells) {
    for (const auto& loop : c) {
      loops.insert(loops.end(), loop.begin(), loop.end());
      start.push_back(static_cast<int>(loops.size()));
    }
    faces.push_back(static_cast<int>(start.size()) - 1);
  }
  out.array(faces);
  out.array(start);
  out.array(loops);
}
/// What write_cells wrote: each list of `start`'s ranges of `items`.
template <class Item>
std::vector<std::vector<Item>> ranges_of(const std::vector<int>& start, std::vector<Item>& items) {
  std::vector<std::vector<Item>> out;
  out.reserve(start.empty() ? 0 : start.size() - 1);
  for (std::size_t k = 0; k + 1 < start.size(); ++k) {
    const auto a = static_cast<std::size_t>(start[k]), b = static_cast<std::size_t>(start[k + 1]);
    if (a > b || b > items.size()) throw InternalError("a piece's bytes hold cells out of range");
    out.emplace_back(std::make_move_iterator(items.begin() + static_cast<std::ptrdiff_t>(a)),
                     std::make_move_iterator(items.begin() + static_cast<std::ptrdiff_t>(b)));
  }
  return out;
}
std::vector<std::vector<int>> read_loops(ByteReader& in) {
  const std::vector<int> start = in.array<int>();
  std::vector<int> loops = in.array<int>();
  return ranges_of(start, loops);
}
void read_cells(ByteReader& in, std::vector<std::vector<int>>& elements) { elements = read_loops(in); }
void read_cells(ByteReader& in, std::vector<CellFaces>& cells) {
  const std::vector<int> faces = in.array<int>();
  std::vector<std::vector<int>> loops = read_loops(in);
  cells = ranges_of(faces, loops);
}

template <class MeshType>
FacetKeys keys_of(const MeshType& mesh, std::span<const int> facets) {
  FacetKeys keys;
  keys.reserve(facets.size());
  for (int f : facets) keys.push_back(sorted_vertices(mesh, f));
  return keys;
}

template <class MeshType>
void write_any_shared(const PieceLists<MeshType>& lists, std::vector<char>& bytes) {
  ByteWriter out(bytes);
  out.array(lists.piece.order);
  out.points(lists.vertices);
}

template <class MeshType>
void write_any_piece(const PieceLists<MeshType>& lists, std::vector<char>& bytes, bool shared) {
  ByteWriter out(bytes);
  const MeshPieceRead<MeshType>& p = lists.piece;
  out.value(shared ? 1 : 0);
  for (const auto* a : {&p.cells, &lists.regions}) out.array(*a);
  for (const int v : {p.whole_cells, p.first, p.end, p.largest_cell, p.picked ? 1 : 0}) out.value(v);
  out.value(p.cell_vertices);
  out.value(p.cell_vertices_squared);
  if (shared) write_any_shared(lists, bytes);
  write_cells(out, lists.cells);
  out.value(static_cast<std::uint64_t>(lists.groups.size()));
  for (const auto& [name, keys] : lists.groups) {
    out.text(name);
    write_cells(out, keys);
  }
  write_cells(out, lists.cuts);
}

}  // namespace

FacetKeys facet_keys(const Mesh& mesh, std::span<const int> facets) { return keys_of(mesh, facets); }
FacetKeys facet_keys(const Mesh3D& mesh, std::span<const int> facets) { return keys_of(mesh, facets); }

MeshPieceRead<Mesh> make_piece(PieceLists<Mesh> lists) { return make_any_piece(std::move(lists)); }
MeshPieceRead<Mesh3D> make_piece(PieceLists<Mesh3D> lists) { return make_any_piece(std::move(lists)); }

void write_piece(const PieceLists<Mesh>& lists, std::vector<char>& out, bool shared) { write_any_piece(lists, out, shared); }
void write_piece(const PieceLists<Mesh3D>& lists, std::vector<char>& out, bool shared) { write_any_piece(lists, out, shared); }
void write_shared(const PieceLists<Mesh>& lists, std::vector<char>& out) { write_any_shared(lists, out); }
void write_shared(const PieceLists<Mesh3D>& lists, std::vector<char>& out) { write_any_shared(lists, out); }

namespace {

template <class MeshType>
void read_any_shared(ByteReader& in, PieceLists<MeshType>& lists) {
  lists.piece.order = in.array<int>();
  lists.vertices = in.points<typename PieceLists<MeshType>::Point>();
}

template <class MeshType>
void read_shared_alone(std::span<const char> bytes, PieceLists<MeshType>& lists) {
  ByteReader in(bytes);
  read_any_shared(in, lists);
  if (!in.done()) throw InternalError("the bytes of a piece's vertices hold more than them");
}

}  // namespace

void read_shared(std::span<const char> bytes, PieceLists<Mesh>& lists) { read_shared_alone(bytes, lists); }
void read_shared(std::span<const char> bytes, PieceLists<Mesh3D>& lists) { read_shared_alone(bytes, lists); }

template <class MeshType>
PieceLists<MeshType> read_piece(std::span<const char> bytes) {
  ByteReader in(bytes);
  PieceLists<MeshType> lists;
  MeshPieceRead<MeshType>& p = lists.piece;
  const bool shared = in.value<int>() != 0;
  for (auto* a : {&p.cells, &lists.regions}) *a = in.array<int>();
  for (int* v : {&p.whole_cells, &p.first, &p.end, &p.largest_cell}) *v = in.value<int>();
  p.picked = in.value<int>() != 0;
  p.cell_vertices = in.value<double>();
  p.cell_vertices_squared = in.value<double>();
  if (shared) read_any_shared(in, lists);
  read_cells(in, lists.cells);
  for (auto n = in.value<std::uint64_t>(); n > 0; --n) {
    std::string name = in.text();
    lists.groups.emplace_back(std::move(name), read_loops(in));
  }
  lists.cuts = read_loops(in);
  if (!in.done()) throw InternalError("a piece's bytes hold more than a piece");
  return lists;
}

template PieceLists<Mesh> read_piece<Mesh>(std::span<const char>);
template PieceLists<Mesh3D> read_piece<Mesh3D>(std::span<const char>);

}  // namespace hemivem
