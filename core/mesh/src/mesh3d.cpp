#include <hemivem/mesh/mesh3d.hpp>

#include "box_sides.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <sstream>
#include <unordered_map>

namespace hemivem {

double scale_free_norm(const Vec3& v) {
  const double squared = v.squaredNorm();
  if (squared >= std::numeric_limits<double>::min() / std::numeric_limits<double>::epsilon() &&
      squared <= std::numeric_limits<double>::max())
    return std::sqrt(squared);
  const double largest = v.cwiseAbs().maxCoeff();
  if (!(largest > 0.0) || !std::isfinite(largest)) return v.norm();  // 0, Inf or NaN
  const int e = std::ilogb(largest);
  return std::ldexp((v * std::ldexp(1.0, -e)).norm(), e);
}

Vec3 polygon_area_vector(std::span<const Vec3> z) {
  Vec3 a = Vec3::Zero();
  const std::size_t n = z.size();
  if (n == 0) return a;
  // relative to the first vertex: the same vector, with less cancellation far from the origin
  for (std::size_t i = 1; i + 1 < n; ++i) a += (z[i] - z[0]).cross(z[i + 1] - z[0]);
  return 0.5 * a;
}

Vec3 polygon_centroid(std::span<const Vec3> z) {
  Vec3 mean = Vec3::Zero();
  for (const Vec3& p : z) mean += p;
  mean /= static_cast<double>(z.size());
  const Vec3 normal = polygon_area_vector(z);
  const double length = scale_free_norm(normal);
  if (!(length > 0.0)) return mean;
  // the signed areas along the area vector divided by its length, or along the unit normal where
  // their product with the area vector (a fourth power of lengths) would leave the range of doubles
  const bool in_range = length == std::sqrt(normal.squaredNorm());
  const Vec3 unit = normal / length;
  Vec3 c = Vec3::Zero();
  double total = 0.0;
  for (std::size_t i = 0; i < z.size(); ++i) {
    const Vec3& a = z[i];
    const Vec3& b = z[i + 1 < z.size() ? i + 1 : 0];
    const Vec3 twice = (a - mean).cross(b - mean);
    const double w = in_range ? 0.5 * twice.dot(normal) / length : 0.5 * twice.dot(unit);  // signed area
    c += w * (mean + a + b) / 3.0;
    total += w;
  }
  return total != 0.0 ? Vec3(c / total) : mean;
}

namespace {

std::string point_text(const Vec3& p) {
  std::ostringstream s;
  s.precision(17);
  s << "(" << p.x() << ", " << p.y() << ", " << p.z() << ")";
  return s.str();
}

// the positions of a loop's vertices, into `out` (which keeps its capacity)
void positions(const std::vector<Vec3>& vertices, const std::vector<int>& loop, std::vector<Vec3>& out) {
  out.clear();
  for (int v : loop) out.push_back(vertices[static_cast<std::size_t>(v)]);
}

// The positions of a face's loop in the order that depends on its vertices alone, not on the
// vertex it starts at nor on the side it is given from: from its smallest vertex towards the
// smaller of that vertex's two neighbours. Returns -1 where that order runs against the loop's,
// 1 where it runs along it. A face's geometry is computed from this order, so that it is the
// same to the bit whichever of its cells the mesh stored it from (a piece of a mesh holds some
// faces from the other side than the whole: mesh_piece.hpp).
int canonical_positions(const std::vector<Vec3>& vertices, const std::vector<int>& loop, std::vector<Vec3>& out) {
  out.clear();
  const std::size_t n = loop.size();
  if (n == 0) return 1;
  const std::size_t m = static_cast<std::size_t>(std::min_element(loop.begin(), loop.end()) - loop.begin());
  const bool along = loop[(m + 1) % n] < loop[(m + n - 1) % n];
  for (std::size_t i = 0; i < n; ++i)
    out.push_back(vertices[static_cast<std::size_t>(loop[along ? (m + i) % n : (m + n - i) % n])]);
  return along ? 1 : -1;
}

std::uint64_t edge_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// What cell_defect computes in, reused from cell to cell.
struct DefectScratch {
  std::vector<Vec3> z, relative;
  std::vector<int> sorted;
  std::vector<Vec3> area, centroid;  // of each face
  std::vector<std::uint64_t> directed;
};

// The message of a cell whose faces do not use every directed edge once and its reverse once.
std::string orientation_defect(const CellFaces& cell) {
  std::unordered_map<std::uint64_t, int> directed;
  for (const auto& loop : cell)
    for (std::size_t i = 0; i < loop.size(); ++i) ++directed[edge_key(loop[i], loop[(i + 1) % loop.size()])];
  for (const auto& [key, count] : directed) {
    const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
    const auto reverse = directed.find(edge_key(b, a));
    if (count != 1 || reverse == directed.end() || reverse->second != 1)
      return "is not closed or its faces are not consistently oriented: the edge " + std::to_string(a) + " -> " +
             std::to_string(b) + " is used " + std::to_string(count) + " time(s) and its reverse " +
             std::to_string(reverse == directed.end() ? 0 : reverse->second) +
             " time(s); each edge must be used once in each direction";
  }
  return {};
}

// the defects of one cell on its own (indices, faces, planarity, closedness, volume)
std::string cell_defect(const std::vector<Vec3>& vertices, const CellFaces& cell, DefectScratch& s) {
  const int nv = static_cast<int>(vertices.size());
  if (cell.size() < 4) return "has " + std::to_string(cell.size()) + " faces; a cell needs at least 4";
  s.area.resize(cell.size());
  s.centroid.resize(cell.size());
  for (std::size_t f = 0; f < cell.size(); ++f) {
    const auto& loop = cell[f];
    const auto which = [&] { return "face " + std::to_string(f); };
    if (loop.size() < 3) return which() + " has " + std::to_string(loop.size()) + " vertices; a face needs at least 3";
    for (int v : loop)
      if (v < 0 || v >= nv)
        return which() + " has vertex index " + std::to_string(v) + " out of range [0, " + std::to_string(nv) + ")";
    s.sorted.assign(loop.begin(), loop.end());
    std::sort(s.sorted.begin(), s.sorted.end());
    if (std::adjacent_find(s.sorted.begin(), s.sorted.end()) != s.sorted.end())
      return which() + " repeats vertex " + std::to_string(*std::adjacent_find(s.sorted.begin(), s.sorted.end()));
    positions(vertices, loop, s.z);
    const auto& z = s.z;
    // the largest distance (the square root of the largest squared distance: the same number)
    double diameter2 = 0.0;
    for (const Vec3& p : z)
      for (const Vec3& q : z) diameter2 = std::max(diameter2, (p - q).squaredNorm());
    const double diameter = std::sqrt(diameter2);
    const Vec3 area = polygon_area_vector(z);
    const double a = scale_free_norm(area);
    if (!(a > 1e-14 * diameter * diameter)) return which() + " has zero area";
    const Vec3 n = area / a;
    // the distances off the plane in coordinates relative to the face's first vertex, so that
    // their round-off is relative to the face's size, not to its distance from the origin
    s.relative.clear();
    for (const Vec3& p : z) s.relative.push_back(p - z[0]);
    const Vec3 c = polygon_centroid(s.relative);
    s.area[f] = area;
    s.centroid[f] = z[0] + c;
    for (std::size_t i = 0; i < z.size(); ++i) {
      const double off = std::abs(n.dot(s.relative[i] - c));
      if (off > face_planarity_tolerance * diameter) {
        std::ostringstream o;
        o.precision(3);
        o << which() << " is not planar: vertex " << loop[i] << " lies " << off << " off its plane (" << off / diameter
          << " of its diameter; at most " << face_planarity_tolerance << ")";
        return o.str();
      }
    }
  }
  // closed and consistently oriented: every directed edge once, and its reverse once
  s.directed.clear();
  for (const auto& loop : cell)
    for (std::size_t i = 0; i < loop.size(); ++i)
      s.directed.push_back(edge_key(loop[i], loop[i + 1 < loop.size() ? i + 1 : 0]));
  std::sort(s.directed.begin(), s.directed.end());
  bool closed = std::adjacent_find(s.directed.begin(), s.directed.end()) == s.directed.end();
  for (std::size_t k = 0; closed && k < s.directed.size(); ++k) {
    const std::uint64_t key = s.directed[k];
    closed = std::binary_search(s.directed.begin(), s.directed.end(), edge_key(static_cast<int>(key & 0xffffffffu),
                                                                                 static_cast<int>(key >> 32)));
  }
  if (!closed) return orientation_defect(cell);  // the message names the edge as it always has
  const Vec3& x0 = vertices[static_cast<std::size_t>(cell[0][0])];
  double volume = 0.0, size2 = 0.0;
  for (std::size_t f = 0; f < cell.size(); ++f) {
    volume += s.area[f].dot(s.centroid[f] - x0) / 3.0;
    for (int v : cell[f]) size2 = std::max(size2, (vertices[static_cast<std::size_t>(v)] - x0).squaredNorm());
  }
  const double size = std::sqrt(size2);
  if (volume == 0.0 || std::abs(volume) <= 1e-14 * size * size * size) return "has zero volume";
  if (volume < 0.0) return "has negative volume: its faces are oriented inward (they must be counter-clockwise seen from outside)";
  return {};
}

// true when b is a reversed rotation of a
bool reversed(const std::vector<int>& a, const std::vector<int>& b) {
  if (a.size() != b.size()) return false;
  const std::size_t n = a.size();
  const auto at = std::find(b.begin(), b.end(), a[0]);
  if (at == b.end()) return false;
  const std::size_t s = static_cast<std::size_t>(at - b.begin());
  for (std::size_t i = 0; i < n; ++i)
    if (a[i] != b[(s + n - i) % n]) return false;
  return true;
}

// The faces of all cells grouped by their vertex sets. The faces are numbered in cell order,
// then local order (face k is local face local[k] of cell cell[k]); order[group_start[g] ..
// group_start[g + 1]) are the faces of group g, increasing, and the groups come in the
// lexicographic order of their sorted vertex lists (the order of a std::map keyed by them).
// The vertex ids must be in [0, num_vertices).
struct FaceGroups {
  std::vector<int> cell, local;
  std::vector<int> group_of;  // by face
  std::vector<int> order, group_start;
};

FaceGroups group_faces(std::size_t num_vertices, const std::vector<CellFaces>& cells) {
  FaceGroups g;
  std::vector<std::size_t> key_start{0};
  std::vector<int> keys;
  for (std::size_t c = 0; c < cells.size(); ++c)
    for (std::size_t f = 0; f < cells[c].size(); ++f) {
      g.cell.push_back(static_cast<int>(c));
      g.local.push_back(static_cast<int>(f));
      keys.insert(keys.end(), cells[c][f].begin(), cells[c][f].end());
      std::sort(keys.begin() + static_cast<std::ptrdiff_t>(key_start.back()), keys.end());
      key_start.push_back(keys.size());
    }
  const std::size_t nf = g.cell.size();
  const auto key_less = [&](int x, int y) {
    const auto* xb = keys.data() + key_start[static_cast<std::size_t>(x)];
    const auto* xe = keys.data() + key_start[static_cast<std::size_t>(x) + 1];
    const auto* yb = keys.data() + key_start[static_cast<std::size_t>(y)];
    const auto* ye = keys.data() + key_start[static_cast<std::size_t>(y) + 1];
    return std::lexicographical_compare(xb, xe, yb, ye);
  };
  // by smallest vertex (a counting sort, stable), then by the whole key and the face number
  std::vector<std::size_t> bucket(num_vertices + 1, 0);
  for (std::size_t k = 0; k < nf; ++k) ++bucket[static_cast<std::size_t>(keys[key_start[k]]) + 1];
  for (std::size_t v = 0; v < num_vertices; ++v) bucket[v + 1] += bucket[v];
  g.order.resize(nf);
  {
    std::vector<std::size_t> next(bucket.begin(), bucket.end() - 1);
    for (std::size_t k = 0; k < nf; ++k) g.order[next[static_cast<std::size_t>(keys[key_start[k]])]++] = static_cast<int>(k);
  }
  for (std::size_t v = 0; v < num_vertices; ++v) {
    const auto first = g.order.begin() + static_cast<std::ptrdiff_t>(bucket[v]);
    const auto last = g.order.begin() + static_cast<std::ptrdiff_t>(bucket[v + 1]);
    if (last - first > 1)
      std::sort(first, last, [&](int x, int y) { return key_less(x, y) || (!key_less(y, x) && x < y); });
  }
  g.group_of.assign(nf, -1);
  for (std::size_t k = 0; k < nf; ++k) {
    if (k == 0 || key_less(g.order[k - 1], g.order[k])) g.group_start.push_back(static_cast<int>(k));
    g.group_of[static_cast<std::size_t>(g.order[k])] = static_cast<int>(g.group_start.size()) - 1;
  }
  g.group_start.push_back(static_cast<int>(nf));
  return g;
}

// find_mesh3d_defects; with `groups`, the faces' groups when every cell is good (they are
// left empty otherwise)
std::vector<Mesh3DDefect> mesh3d_defects(const std::vector<Vec3>& vertices, const std::vector<CellFaces>& cells,
                                         std::size_t max_defects, FaceGroups* groups) {
  std::vector<Mesh3DDefect> out;
  if (vertices.empty()) out.push_back({-1, "the mesh has no vertices"});
  if (cells.empty()) out.push_back({-1, "the mesh has no cells"});
  for (std::size_t i = 0; i < vertices.size() && out.size() < max_defects; ++i)
    if (!vertices[i].allFinite() || vertices[i].cwiseAbs().maxCoeff() > 1e100)
      out.push_back({-1, "vertex " + std::to_string(i) + " " + point_text(vertices[i]) +
                             " is not finite or exceeds 1e100 in magnitude"});
  if (!out.empty()) return out;
  DefectScratch scratch;
  for (std::size_t c = 0; c < cells.size() && out.size() < max_defects; ++c) {
    const std::string d = cell_defect(vertices, cells[c], scratch);
    if (!d.empty()) out.push_back({static_cast<int>(c), "cell " + std::to_string(c) + " " + d});
  }
  if (!out.empty()) return out;
  // conformity: a face in at most two cells, with opposite orientations
  FaceGroups local_groups;
  FaceGroups& g = groups != nullptr ? *groups : local_groups;
  g = group_faces(vertices.size(), cells);
  std::vector<std::uint64_t> boundary_edges;  // undirected edges of the boundary faces, once per face
  for (std::size_t group = 0; group + 1 < g.group_start.size(); ++group) {
    if (out.size() >= max_defects) break;
    const int* uses = g.order.data() + g.group_start[group];
    const auto count = static_cast<std::size_t>(g.group_start[group + 1] - g.group_start[group]);
    const int c0 = g.cell[static_cast<std::size_t>(uses[0])], f0 = g.local[static_cast<std::size_t>(uses[0])];
    if (count > 2) {
      const int c1 = g.cell[static_cast<std::size_t>(uses[1])], c2 = g.cell[static_cast<std::size_t>(uses[2])];
      out.push_back({c2, "cell " + std::to_string(c2) + " shares a face with cells " + std::to_string(c0) + " and " +
                             std::to_string(c1) + "; a face belongs to at most two cells"});
      continue;
    }
    const auto& loop = cells[static_cast<std::size_t>(c0)][static_cast<std::size_t>(f0)];
    if (count == 2) {
      const int c1 = g.cell[static_cast<std::size_t>(uses[1])], f1 = g.local[static_cast<std::size_t>(uses[1])];
      if (c1 == c0) {
        out.push_back({c0, "cell " + std::to_string(c0) + " has the same face twice"});
      } else if (!reversed(loop, cells[static_cast<std::size_t>(c1)][static_cast<std::size_t>(f1)])) {
        out.push_back({c1, "cell " + std::to_string(c1) + " and cell " + std::to_string(c0) +
                               " share a face with the same orientation (or a different vertex order); a shared "
                               "face runs in opposite directions in its two cells"});
      }
      continue;
    }
    for (std::size_t i = 0; i < loop.size(); ++i) {
      const int a = loop[i], b = loop[i + 1 < loop.size() ? i + 1 : 0];
      boundary_edges.push_back(edge_key(std::min(a, b), std::max(a, b)));
    }
  }
  if (!out.empty()) return out;
  // no hanging vertex: the boundary is a closed surface whose every edge is in two faces
  std::sort(boundary_edges.begin(), boundary_edges.end());
  for (std::size_t k = 0; k < boundary_edges.size();) {
    std::size_t e = k + 1;
    while (e < boundary_edges.size() && boundary_edges[e] == boundary_edges[k]) ++e;
    const std::size_t count = e - k;
    const std::uint64_t key = boundary_edges[k];
    k = e;
    if (count == 2) continue;
    const int a = static_cast<int>(key >> 32), b = static_cast<int>(key & 0xffffffffu);
    out.push_back({-1, "the boundary edge " + std::to_string(a) + " - " + std::to_string(b) + " at " +
                           point_text(vertices[static_cast<std::size_t>(a)]) + " - " +
                           point_text(vertices[static_cast<std::size_t>(b)]) + " is in " + std::to_string(count) +
                           " boundary face(s), not 2: a hanging vertex or a non-matching face"});
    if (out.size() >= max_defects) break;
  }
  return out;
}

}  // namespace

std::vector<Mesh3DDefect> find_mesh3d_defects(const std::vector<Vec3>& vertices, const std::vector<CellFaces>& cells,
                                              std::size_t max_defects) {
  return mesh3d_defects(vertices, cells, max_defects, nullptr);
}

Mesh3D::Mesh3D(std::vector<Vec3> vertices, std::vector<CellFaces> cells, std::vector<int> regions)
    : vertices_(std::move(vertices)) {
  FaceGroups groups;
  const auto defects = mesh3d_defects(vertices_, cells, 1, &groups);
  if (!defects.empty()) throw MeshError(defects.front().message, defects.front().cell);
  // faces numbered in the order they first appear (cell order, then local order)
  std::vector<int> face_of_group(groups.group_start.size() - 1, -1);
  cell_faces_.resize(cells.size());
  cell_vertices_.resize(cells.size());
  std::size_t k = 0;  // the face's number in groups
  for (std::size_t c = 0; c < cells.size(); ++c) {
    cell_faces_[c].reserve(cells[c].size());
    for (const auto& loop : cells[c]) {
      int& id = face_of_group[static_cast<std::size_t>(groups.group_of[k++])];
      if (id < 0) {
        id = static_cast<int>(faces_.size());
        faces_.push_back(MeshFace{loop, static_cast<int>(c), -1});
      } else {
        faces_[static_cast<std::size_t>(id)].outer = static_cast<int>(c);
      }
      cell_faces_[c].push_back(id);
      for (int v : loop) cell_vertices_[c].push_back(v);
    }
    auto& cv = cell_vertices_[c];
    std::sort(cv.begin(), cv.end());
    cv.erase(std::unique(cv.begin(), cv.end()), cv.end());
  }
  for (std::size_t f = 0; f < faces_.size(); ++f)
    if (faces_[f].on_boundary()) boundary_faces_.push_back(static_cast<int>(f));
  face_area_.resize(faces_.size());
  face_centroid_.resize(faces_.size());
  face_normal_.resize(faces_.size());
  std::vector<Vec3> z;
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    const int sign = canonical_positions(vertices_, faces_[f].vertices, z);
    const Vec3 a = polygon_area_vector(z);
    face_area_[f] = scale_free_norm(a);
    face_normal_[f] = static_cast<double>(sign) * a / face_area_[f];
    // the centroid relative to the first vertex: its round-off relative to the face's size, not
    // to its distance from the origin (a face on a plane of constant x has its centroid on it)
    const Vec3 first = z.front();
    for (Vec3& p : z) p -= first;
    face_centroid_[f] = first + polygon_centroid(z);
  }
  volume_.resize(cells.size());
  centroid_.resize(cells.size());
  diameter_.resize(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) {
    // the volume and centroid from a fan of tetrahedra (x0, face triangle fan from the face centroid)
    const Vec3 x0 = vertices_[static_cast<std::size_t>(cell_vertices_[c][0])];
    double volume = 0.0;
    Vec3 moment = Vec3::Zero();
    for (const int f : cell_faces_[c]) {
      // the loop in the order its vertices fix (canonical_positions), the sign of the cell's
      // orientation applied to each tetrahedron, and the face's centroid: what any mesh holding
      // the cell computes of it, whichever of its cells stored the face and from which vertex
      const MeshFace& face = faces_[static_cast<std::size_t>(f)];
      const double sign = canonical_positions(vertices_, face.vertices, z) * (face.inner == static_cast<int>(c) ? 1.0 : -1.0);
      const Vec3 fc = face_centroid_[static_cast<std::size_t>(f)];
      for (std::size_t i = 0; i < z.size(); ++i) {
        const Vec3& a = z[i];
        const Vec3& b = z[i + 1 < z.size() ? i + 1 : 0];
        const double v = sign * (a - x0).cross(b - x0).dot(fc - x0) / 6.0;
        volume += v;
        moment += v * ((a - x0) + (b - x0) + (fc - x0)) / 4.0;  // about x0: no fourth power of coordinates
      }
    }
    volume_[c] = volume;
    centroid_[c] = x0 + moment / volume;
    // the largest distance between two vertices (the square root of the largest squared one)
    double d2 = 0.0;
    for (int p : cell_vertices_[c])
      for (int q : cell_vertices_[c])
        d2 = std::max(d2, (vertices_[static_cast<std::size_t>(p)] - vertices_[static_cast<std::size_t>(q)]).squaredNorm());
    const double d = std::sqrt(d2);
    diameter_[c] = d;
    h_ = std::max(h_, d);
  }
  set_regions(std::move(regions));
}

CellFaces Mesh3D::cell(int c) const {
  CellFaces out;
  for (int f : cell_faces(c)) {
    const MeshFace& face = faces_[static_cast<std::size_t>(f)];
    std::vector<int> loop = face.vertices;
    if (face.inner != c) std::reverse(loop.begin(), loop.end());
    out.push_back(std::move(loop));
  }
  return out;
}

std::vector<std::vector<int>> Mesh3D::local_faces(int c) const {
  std::vector<std::vector<int>> faces;
  local_faces(c, faces);
  return faces;
}

void Mesh3D::local_faces(int c, std::vector<std::vector<int>>& faces) const {
  const auto& cv = cell_vertices(c);
  const auto& ids = cell_faces(c);
  faces.resize(ids.size());
  for (std::size_t k = 0; k < ids.size(); ++k) {
    const MeshFace& face = faces_[static_cast<std::size_t>(ids[k])];
    auto& loop = faces[k];
    loop.assign(face.vertices.begin(), face.vertices.end());
    if (face.inner != c) std::reverse(loop.begin(), loop.end());
    for (int& v : loop) v = static_cast<int>(std::lower_bound(cv.begin(), cv.end(), v) - cv.begin());
  }
}

std::vector<int> Mesh3D::boundary_vertices() const {
  std::vector<int> out;
  for (int f : boundary_faces_)
    for (int v : faces_[static_cast<std::size_t>(f)].vertices) out.push_back(v);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

double Mesh3D::total_volume() const {
  double v = 0.0;
  for (double x : volume_) v += x;
  return v;
}

Box Mesh3D::bounding_box() const {
  Vec3 lo = vertices_.front(), hi = lo;
  for (const Vec3& p : vertices_) {
    lo = lo.cwiseMin(p);
    hi = hi.cwiseMax(p);
  }
  return {lo.x(), hi.x(), lo.y(), hi.y(), lo.z(), hi.z()};
}

void Mesh3D::set_face_group(const std::string& name, std::vector<int> faces) {
  for (int id : faces)
    if (id < 0 || id >= num_faces())
      throw InputError("face id " + std::to_string(id) + " is out of range [0, " + std::to_string(num_faces()) + ")",
                       "face group '" + name + "'");
  std::sort(faces.begin(), faces.end());
  faces.erase(std::unique(faces.begin(), faces.end()), faces.end());
  face_groups_[name] = std::move(faces);
}

const std::vector<int>& Mesh3D::face_group(const std::string& name) const {
  const auto it = face_groups_.find(name);
  if (it == face_groups_.end()) {
    std::string known;
    for (const auto& [n, _] : face_groups_) known += (known.empty() ? "" : ", ") + n;
    throw InputError("the mesh has no face group '" + name + "'; its groups: " + (known.empty() ? "none" : known));
  }
  return it->second;
}

void Mesh3D::set_regions(std::vector<int> regions) {
  if (regions.empty()) regions.assign(static_cast<std::size_t>(num_cells()), 0);
  if (regions.size() != static_cast<std::size_t>(num_cells()))
    throw InputError("region list has " + std::to_string(regions.size()) + " entries for " +
                     std::to_string(num_cells()) + " cells");
  for (std::size_t c = 0; c < regions.size(); ++c)
    if (regions[c] < 0)
      throw MeshError("cell " + std::to_string(c) + " has negative region id " + std::to_string(regions[c]),
                      static_cast<int>(c));
  regions_ = std::move(regions);
}

std::vector<int> select_boundary_faces(const Mesh3D& mesh, const std::function<bool(const Vec3&)>& keep) {
  std::vector<int> out;
  for (int f : mesh.boundary_faces()) {
    const auto& loop = mesh.face(f).vertices;
    if (std::all_of(loop.begin(), loop.end(), [&](int v) { return keep(mesh.vertex(v)); })) out.push_back(f);
  }
  return out;
}

std::vector<int> select_boundary_faces(const Mesh3D& mesh, const std::string& group) {
  const auto& faces = mesh.face_group(group);
  for (int f : faces)
    if (!mesh.face(f).on_boundary())
      throw InputError("face group '" + group + "' holds face " + std::to_string(f) + ", which is not on the boundary");
  return faces;
}

std::vector<int> select_box_side(const Mesh3D& mesh, const Box& box, const std::string& side,
                                 double relative_tolerance) {
  const std::pair<int, bool> named = detail::box_side_axis(3, side);
  const int axis = named.first;  // a plain variable: a lambda below reads it
  const double at = named.second ? box.upper(axis) : box.lower(axis);
  const double tol = relative_tolerance * std::max({box.size(0), box.size(1), box.size(2)});
  return select_boundary_faces(mesh, [&](const Vec3& p) { return std::abs(p(axis) - at) <= tol; });
}

}  // namespace hemivem
