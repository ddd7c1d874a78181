#include <hemivem/mesh/mesh3d.hpp>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <sstream>
#include <unordered_map>

namespace hemivem {

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
  const double area2 = normal.squaredNorm();
  if (!(area2 > 0.0)) return mean;
  Vec3 c = Vec3::Zero();
  double total = 0.0;
  for (std::size_t i = 0; i < z.size(); ++i) {
    const Vec3& a = z[i];
    const Vec3& b = z[(i + 1) % z.size()];
    const double w = 0.5 * (a - mean).cross(b - mean).dot(normal) / std::sqrt(area2);  // signed area
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

std::vector<Vec3> positions(const std::vector<Vec3>& vertices, const std::vector<int>& loop) {
  std::vector<Vec3> out;
  out.reserve(loop.size());
  for (int v : loop) out.push_back(vertices[static_cast<std::size_t>(v)]);
  return out;
}

std::uint64_t edge_key(int a, int b) {
  return (static_cast<std::uint64_t>(static_cast<std::uint32_t>(a)) << 32) | static_cast<std::uint32_t>(b);
}

// the defects of one cell on its own (indices, faces, planarity, closedness, volume)
std::string cell_defect(const std::vector<Vec3>& vertices, const CellFaces& cell) {
  const int nv = static_cast<int>(vertices.size());
  if (cell.size() < 4) return "has " + std::to_string(cell.size()) + " faces; a cell needs at least 4";
  for (std::size_t f = 0; f < cell.size(); ++f) {
    const auto& loop = cell[f];
    const std::string which = "face " + std::to_string(f);
    if (loop.size() < 3) return which + " has " + std::to_string(loop.size()) + " vertices; a face needs at least 3";
    for (int v : loop)
      if (v < 0 || v >= nv)
        return which + " has vertex index " + std::to_string(v) + " out of range [0, " + std::to_string(nv) + ")";
    std::vector<int> sorted = loop;
    std::sort(sorted.begin(), sorted.end());
    if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
      return which + " repeats vertex " + std::to_string(*std::adjacent_find(sorted.begin(), sorted.end()));
    const auto z = positions(vertices, loop);
    double diameter = 0.0;
    for (const Vec3& p : z)
      for (const Vec3& q : z) diameter = std::max(diameter, (p - q).norm());
    const Vec3 area = polygon_area_vector(z);
    const double a = area.norm();
    if (!(a > 1e-14 * diameter * diameter)) return which + " has zero area";
    const Vec3 n = area / a;
    const Vec3 c = polygon_centroid(z);
    for (std::size_t i = 0; i < z.size(); ++i) {
      const double off = std::abs(n.dot(z[i] - c));
      if (off > face_planarity_tolerance * diameter) {
        std::ostringstream s;
        s.precision(3);
        s << which << " is not planar: vertex " << loop[i] << " lies " << off << " off its plane (" << off / diameter
          << " of its diameter; at most " << face_planarity_tolerance << ")";
        return s.str();
      }
    }
  }
  // closed and consistently oriented: every directed edge once, and its reverse once
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
  double volume = 0.0, size = 0.0;
  for (const auto& loop : cell) {
    const auto z = positions(vertices, loop);
    volume += polygon_area_vector(z).dot(polygon_centroid(z) - vertices[static_cast<std::size_t>(cell[0][0])]) / 3.0;
    for (const Vec3& p : z) size = std::max(size, (p - vertices[static_cast<std::size_t>(cell[0][0])]).norm());
  }
  if (volume == 0.0 || std::abs(volume) <= 1e-14 * size * size * size) return "has zero volume";
  if (volume < 0.0) return "has negative volume: its faces are oriented inward (they must be counter-clockwise seen from outside)";
  return {};
}

std::vector<int> sorted_key(const std::vector<int>& loop) {
  std::vector<int> k = loop;
  std::sort(k.begin(), k.end());
  return k;
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

}  // namespace

std::vector<Mesh3DDefect> find_mesh3d_defects(const std::vector<Vec3>& vertices, const std::vector<CellFaces>& cells,
                                              std::size_t max_defects) {
  std::vector<Mesh3DDefect> out;
  if (vertices.empty()) out.push_back({-1, "the mesh has no vertices"});
  if (cells.empty()) out.push_back({-1, "the mesh has no cells"});
  for (std::size_t i = 0; i < vertices.size() && out.size() < max_defects; ++i)
    if (!vertices[i].allFinite() || vertices[i].cwiseAbs().maxCoeff() > 1e100)
      out.push_back({-1, "vertex " + std::to_string(i) + " " + point_text(vertices[i]) +
                             " is not finite or exceeds 1e100 in magnitude"});
  if (!out.empty()) return out;
  std::vector<char> good(cells.size(), 0);
  for (std::size_t c = 0; c < cells.size() && out.size() < max_defects; ++c) {
    const std::string d = cell_defect(vertices, cells[c]);
    if (d.empty()) good[c] = 1;
    else out.push_back({static_cast<int>(c), "cell " + std::to_string(c) + " " + d});
  }
  if (!out.empty()) return out;
  // conformity: a face in at most two cells, with opposite orientations
  std::map<std::vector<int>, std::vector<std::pair<int, int>>> by_key;  // (cell, local face)
  for (std::size_t c = 0; c < cells.size(); ++c)
    for (std::size_t f = 0; f < cells[c].size(); ++f)
      by_key[sorted_key(cells[c][f])].emplace_back(static_cast<int>(c), static_cast<int>(f));
  std::map<std::uint64_t, int> boundary_edges;  // undirected edge -> number of boundary faces holding it
  for (const auto& [key, uses] : by_key) {
    if (out.size() >= max_defects) break;
    const auto& [c0, f0] = uses[0];
    if (uses.size() > 2) {
      out.push_back({uses[2].first, "cell " + std::to_string(uses[2].first) + " shares a face with cells " +
                                        std::to_string(c0) + " and " + std::to_string(uses[1].first) +
                                        "; a face belongs to at most two cells"});
      continue;
    }
    const auto& loop = cells[static_cast<std::size_t>(c0)][static_cast<std::size_t>(f0)];
    if (uses.size() == 2) {
      const auto& [c1, f1] = uses[1];
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
      const int a = loop[i], b = loop[(i + 1) % loop.size()];
      ++boundary_edges[edge_key(std::min(a, b), std::max(a, b))];
    }
  }
  if (!out.empty()) return out;
  // no hanging vertex: the boundary is a closed surface whose every edge is in two faces
  for (const auto& [key, count] : boundary_edges) {
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

Mesh3D::Mesh3D(std::vector<Vec3> vertices, std::vector<CellFaces> cells, std::vector<int> regions)
    : vertices_(std::move(vertices)) {
  const auto defects = find_mesh3d_defects(vertices_, cells, 1);
  if (!defects.empty()) throw MeshError(defects.front().message, defects.front().cell);
  std::map<std::vector<int>, int> face_of;
  cell_faces_.resize(cells.size());
  cell_vertices_.resize(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) {
    for (const auto& loop : cells[c]) {
      const auto [at, added] = face_of.emplace(sorted_key(loop), static_cast<int>(faces_.size()));
      if (added) faces_.push_back(MeshFace{loop, static_cast<int>(c), -1});
      else faces_[static_cast<std::size_t>(at->second)].outer = static_cast<int>(c);
      cell_faces_[c].push_back(at->second);
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
  for (std::size_t f = 0; f < faces_.size(); ++f) {
    const auto z = positions(vertices_, faces_[f].vertices);
    const Vec3 a = polygon_area_vector(z);
    face_area_[f] = a.norm();
    face_normal_[f] = a / face_area_[f];
    face_centroid_[f] = polygon_centroid(z);
  }
  volume_.resize(cells.size());
  centroid_.resize(cells.size());
  diameter_.resize(cells.size());
  for (std::size_t c = 0; c < cells.size(); ++c) {
    // the volume and centroid from a fan of tetrahedra (x0, face triangle fan from the face centroid)
    const Vec3 x0 = vertices_[static_cast<std::size_t>(cell_vertices_[c][0])];
    double volume = 0.0;
    Vec3 moment = Vec3::Zero();
    for (const auto& loop : cells[c]) {
      const auto z = positions(vertices_, loop);
      const Vec3 fc = polygon_centroid(z);
      for (std::size_t i = 0; i < z.size(); ++i) {
        const Vec3& a = z[i];
        const Vec3& b = z[(i + 1) % z.size()];
        const double v = (a - x0).cross(b - x0).dot(fc - x0) / 6.0;
        volume += v;
        moment += v * (x0 + a + b + fc) / 4.0;
      }
    }
    volume_[c] = volume;
    centroid_[c] = moment / volume;
    double d = 0.0;
    for (int p : cell_vertices_[c])
      for (int q : cell_vertices_[c]) d = std::max(d, (vertices_[static_cast<std::size_t>(p)] - vertices_[static_cast<std::size_t>(q)]).norm());
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
  static const std::map<std::string, std::pair<int, bool>> sides = {
      {"x0", {0, false}}, {"x1", {0, true}}, {"y0", {1, false}}, {"y1", {1, true}},
      {"z0", {2, false}}, {"z1", {2, true}}, {"bottom", {2, false}}, {"top", {2, true}}};
  const auto it = sides.find(side);
  if (it == sides.end())
    throw InputError("unknown side '" + side + "' of a box; expected x0, x1, y0, y1, z0, z1, bottom or top");
  const int axis = it->second.first;
  const double at = it->second.second ? box.upper(axis) : box.lower(axis);
  const double tol = relative_tolerance * std::max({box.size(0), box.size(1), box.size(2)});
  return select_boundary_faces(mesh, [&](const Vec3& p) { return std::abs(p(axis) - at) <= tol; });
}

}  // namespace hemivem
