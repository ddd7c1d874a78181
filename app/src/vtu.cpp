// solution.vtu and contact-surface.vtu (vtu.hpp): the file, its points, point data and cell data
// are written once for plane and solid bodies; the cells are each dimension's own (polygons and
// contact lines, or polyhedra). The arrays are made once over the whole mesh and written for a
// selection of its points and cells: the whole, one body of several (solution.body-NAME.vtu) or
// one process's share (solution.piece-K.vtu of solution.pvtu).
#include <hemivem/app/vtu.hpp>

#include <hemivem/app/outputs.hpp>

#include "vtk_data_array.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <functional>
#include <map>
#include <numeric>
#include <memory>
#include <ostream>
#include <string>
#include <type_traits>
#include <variant>
#include <vector>

#include <hemivem/error.hpp>

namespace hemivem::app {

std::uint8_t friction_state_code(FrictionState state) { return static_cast<std::uint8_t>(state); }

namespace {

using detail::data_array;

int num_cells(const Mesh& mesh) { return mesh.num_elements(); }
int num_cells(const Mesh3D& mesh) { return mesh.num_cells(); }

void file_head(std::ostream& os, std::size_t points, std::size_t cells) {
  os << "<?xml version=\"1.0\"?>\n"
     << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\""
     << (std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian")
     << "\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">\n"
     << "  <UnstructuredGrid>\n"
     << "    <Piece NumberOfPoints=\"" << points << "\" NumberOfCells=\"" << cells << "\">\n";
}

void file_tail(std::ostream& os) {
  os << "    </Piece>\n"
     << "  </UnstructuredGrid>\n"
     << "</VTKFile>\n";
}

/// The points `which` of `points`, three coordinates each (z = 0 in the plane).
template <class Point>
void write_points(std::ostream& os, const std::vector<Point>& points, const std::vector<int>& which) {
  std::vector<double> xyz(3 * which.size(), 0.0);
  for (std::size_t v = 0; v < which.size(); ++v)
    for (int c = 0; c < Point::RowsAtCompileTime; ++c)
      xyz[3 * v + static_cast<std::size_t>(c)] = points[static_cast<std::size_t>(which[v])](c);
  os << "      <Points>\n";
  data_array(os, "Points", 3, xyz);
  os << "      </Points>\n";
}
template <class Point>
void write_points(std::ostream& os, const std::vector<Point>& points) {
  std::vector<int> all(points.size());
  std::iota(all.begin(), all.end(), 0);
  write_points(os, points, all);
}

/// The cells of a mesh: VTK's connectivity, offsets and types, and for polyhedra their faces;
/// `contact_lines` cells at the end are a plane's contact boundary.
struct Cells {
  std::vector<std::int64_t> connectivity, offsets, faces, faceoffsets;
  std::vector<std::uint8_t> types;
  std::size_t contact_lines = 0;
  void close(std::uint8_t type) {
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
    types.push_back(type);
  }
};

/// What one file of solution.vtu writes of a mesh: its points (the mesh's vertices, in order)
/// and its cells (the mesh's), a plane's contact lines after them, and each vertex's point.
struct Selection {
  std::string name;                          ///< for messages: "'upper'", "the share of the vertices 0 to 99"
  std::vector<int> points, cells;
  std::vector<std::array<int, 2>> lines;     ///< a plane's contact lines (their ends are points)
  std::vector<std::int64_t> point;           ///< each vertex of the mesh: its point, or -1
  void number_points(std::size_t vertices) {
    point.assign(vertices, -1);
    for (std::size_t k = 0; k < points.size(); ++k) point[static_cast<std::size_t>(points[k])] = static_cast<std::int64_t>(k);
  }
};

/// Vertex v of the mesh as a point of `s`; an InternalError when a cell of `s` reaches outside
/// its points.
std::int64_t point_of(const Selection& s, int v, int cell) {
  const std::int64_t p = s.point[static_cast<std::size_t>(v)];
  if (p < 0)
    throw InternalError("cell " + std::to_string(cell) + " of " + s.name + " has the vertex " + std::to_string(v) +
                        ", not one of its vertices");
  return p;
}

/// The vertices of a cell of either mesh.
auto vertices_of(const Mesh& mesh, int e) { return mesh.element(e); }
std::vector<int> vertices_of(const Mesh3D& mesh, int c) { return mesh.cell_vertices(c); }

/// The points and cells of `body` (a consecutive range of each of the mesh's): a plane's
/// contact lines whose two ends are its points follow its polygons.
template <class MeshType, int dim>
Selection body_selection(const MeshType& mesh, const BasicContactSolution<dim>& sol, const BodyRange& body) {
  Selection s;
  s.name = "'" + body.name + "'";
  for (int v = body.first_vertex; v < body.first_vertex + body.vertices; ++v) s.points.push_back(v);
  for (int c = body.first_cell; c < body.first_cell + body.cells; ++c) s.cells.push_back(c);
  if constexpr (dim == 2)
    for (const auto& l : contact_lines(mesh, sol))
      if (body.has_vertex(l[0]) && body.has_vertex(l[1])) s.lines.push_back(l);
  s.number_points(static_cast<std::size_t>(mesh.num_vertices()));
  return s;
}

/// The share of the vertices `share`: the cells whose smallest vertex is one of them and a
/// plane's contact lines whose smaller end is, with every point they reach (in the mesh's
/// order). The shares of a split of the vertices hold each cell and line once. With `body`, of
/// those only the body's: the cells whose smallest vertex is the body's, and the contact lines
/// whose two ends are.
template <class MeshType, int dim>
Selection share_selection(const MeshType& mesh, const BasicContactSolution<dim>& sol, const VertexShare& share,
                          const BodyRange* body) {
  Selection s;
  s.name = "the share of " + share.text() + (body ? " in '" + body->name + "'" : "");
  const auto nv = static_cast<std::size_t>(mesh.num_vertices());
  std::vector<char> used(nv, 0);
  std::vector<char> mask = share.mask(mesh.num_vertices());
  if (body)
    for (std::size_t v = 0; v < nv; ++v) mask[v] = mask[v] && body->has_vertex(static_cast<int>(v));
  const auto owned = [&mask](int v) { return mask[static_cast<std::size_t>(v)] != 0; };
  for (int c = 0; c < num_cells(mesh); ++c) {
    const auto& vs = vertices_of(mesh, c);
    if (vs.empty() || !owned(*std::min_element(vs.begin(), vs.end()))) continue;
    s.cells.push_back(c);
    for (int v : vs) used[static_cast<std::size_t>(v)] = 1;
  }
  if constexpr (dim == 2)
    for (const auto& l : contact_lines(mesh, sol))
      if (owned(std::min(l[0], l[1])) && (!body || (body->has_vertex(l[0]) && body->has_vertex(l[1])))) {
        s.lines.push_back(l);
        used[static_cast<std::size_t>(l[0])] = used[static_cast<std::size_t>(l[1])] = 1;
      }
  for (std::size_t v = 0; v < nv; ++v)
    if (used[v]) s.points.push_back(static_cast<int>(v));
  s.number_points(nv);
  return s;
}

/// A plane's polygons of `s`, then its contact lines.
Cells cells_of(const Mesh& mesh, const Selection& s) {
  Cells cells;
  for (int e : s.cells) {
    for (int v : mesh.element(e)) cells.connectivity.push_back(point_of(s, v, e));
    cells.close(7);  // VTK_POLYGON
  }
  for (const auto& l : s.lines) {
    cells.connectivity.insert(cells.connectivity.end(), {point_of(s, l[0], -1), point_of(s, l[1], -1)});
    cells.close(3);  // VTK_LINE: Gamma_3
    ++cells.contact_lines;
  }
  return cells;
}

/// A solid's cells of `s` as VTK_POLYHEDRON: the cell's points, and its faces as [number of
/// faces, then per face its number of points and their ids], each face counter-clockwise seen
/// from outside.
Cells cells_of(const Mesh3D& mesh, const Selection& s) {
  Cells cells;
  for (int c : s.cells) {
    for (int v : mesh.cell_vertices(c)) cells.connectivity.push_back(point_of(s, v, c));
    cells.close(42);
    const CellFaces loops = mesh.cell(c);
    cells.faces.push_back(static_cast<std::int64_t>(loops.size()));
    for (const auto& loop : loops) {
      cells.faces.push_back(static_cast<std::int64_t>(loop.size()));
      for (int v : loop) cells.faces.push_back(point_of(s, v, c));
    }
    cells.faceoffsets.push_back(static_cast<std::int64_t>(cells.faces.size()));
  }
  return cells;
}

void write_cells(std::ostream& os, const Cells& cells, bool polyhedra) {
  os << "      <Cells>\n";
  data_array(os, "connectivity", 1, cells.connectivity);
  data_array(os, "offsets", 1, cells.offsets);
  data_array(os, "types", 1, cells.types);
  if (polyhedra) {
    data_array(os, "faces", 1, cells.faces);
    data_array(os, "faceoffsets", 1, cells.faceoffsets);
  }
  os << "      </Cells>\n";
}

/// The contact values of each vertex (0 off the contact nodes): u_nu, pressure, gap, flag.
struct ContactFields {
  std::vector<double> u_nu, pressure, gap;
  std::vector<std::uint8_t> node;
  template <int dim>
  ContactFields(std::size_t vertices, const BasicContactSolution<dim>& sol)
      : u_nu(vertices, 0.0), pressure(vertices, 0.0), gap(vertices, 0.0), node(vertices, 0) {
    for (const auto& n : sol.contact) {
      const auto v = static_cast<std::size_t>(n.vertex);
      u_nu[v] = n.u_nu;
      pressure[v] = std::isfinite(n.pressure()) ? n.pressure() : 0.0;
      gap[v] = std::isfinite(n.gap) ? n.gap : 0.0;  // a ray that misses the obstacle: +inf, written as 0
      node[v] = 1;
    }
  }
};

/// One array of point or cell data over the whole mesh, `width` values per point or cell;
/// a cell array's value on a plane's contact lines, which follow the cells.
struct Field {
  const char* name;
  int width;
  std::variant<std::vector<double>, std::vector<std::int64_t>, std::vector<std::int32_t>, std::vector<std::uint8_t>> values;
  double on_lines = 0.0;
};

/// The arrays of solution.vtu over the whole mesh, in the order written.
struct Fields {
  std::vector<Field> point, cell;
};

/// With friction: u_tau, the friction traction (a plane's along tau, a solid's as vectors of
/// three components) and the state code, 0 off the contact nodes.
template <int dim>
void add_friction_point_data(Fields& f, std::size_t nv, const BasicContactSolution<dim>& sol) {
  constexpr std::size_t width = dim == 2 ? 1 : 3;
  std::vector<double> u_tau(width * nv, 0.0), traction(width * nv, 0.0);
  std::vector<std::uint8_t> state(nv, 0);
  for (const auto& n : sol.contact) {
    const auto v = static_cast<std::size_t>(n.vertex);
    if constexpr (dim == 2) {
      u_tau[v] = n.u_tau;
      traction[v] = n.friction_force / n.weight;
    } else {
      for (std::size_t c = 0; c < 3; ++c) {
        u_tau[3 * v + c] = n.u_tangential(static_cast<Eigen::Index>(c));
        traction[3 * v + c] = n.friction_vector(static_cast<Eigen::Index>(c)) / n.weight;
      }
    }
    state[v] = friction_state_code(n.friction_state);
  }
  f.point.push_back({"u_tau", static_cast<int>(width), std::move(u_tau)});
  f.point.push_back({"friction_traction", static_cast<int>(width), std::move(traction)});
  f.point.push_back({"friction_state", 1, std::move(state)});
}

/// The displacement (three components) and the contact nodes' values; a plane's with several
/// contact parts also each node's part (-1 off the contact), with friction the friction's.
template <int dim>
void add_point_data(Fields& f, std::size_t nv, const BasicContactSolution<dim>& sol) {
  std::vector<double> displacement(3 * nv, 0.0);
  for (std::size_t v = 0; v < nv; ++v)
    for (std::size_t c = 0; c < dim; ++c) displacement[3 * v + c] = sol.u(static_cast<Eigen::Index>(dim * v + c));
  f.point.push_back({"displacement", 3, std::move(displacement)});
  if (sol.contact.empty()) return;
  ContactFields c(nv, sol);
  f.point.push_back({"u_nu", 1, std::move(c.u_nu)});
  f.point.push_back({"pressure", 1, std::move(c.pressure)});
  f.point.push_back({"gap", 1, std::move(c.gap)});
  if (dim == 2 && sol.contact_parts.size() > 1) {
    std::vector<std::int32_t> part(nv, -1);
    for (const auto& n : sol.contact) part[static_cast<std::size_t>(n.vertex)] = n.part;
    f.point.push_back({"contact_part", 1, std::move(part)});
  }
  if (has_tangential(sol)) add_friction_point_data(f, nv, sol);
}

/// Stresses, von Mises, regions per cell; a plane's contact lines after them carry zeros,
/// region -1 and contact = 1 (the cell data "contact", written when there is contact).
template <class MeshType, int dim>
void add_cell_data(Fields& f, const MeshType& mesh, const MaterialTable& materials, const BasicContactSolution<dim>& sol,
                   const std::vector<double>* indicators) {
  const std::vector<BasicCellStress<dim>> stress = cell_stresses(mesh, materials, sol.u);
  const auto nc = static_cast<std::size_t>(num_cells(mesh));
  // ParaView's symmetric-tensor order: XX, YY, ZZ, XY, YZ, XZ
  std::vector<double> tensor(6 * nc, 0.0), von_mises(nc, 0.0);
  std::vector<std::int32_t> region(nc, -1);
  for (std::size_t c = 0; c < nc; ++c) {
    const BasicCellStress<dim>& s = stress[c];
    for (std::size_t k = 0; const double value : {s.xx, s.yy, s.zz, s.xy, s.yz, s.xz}) tensor[6 * c + k++] = value;
    von_mises[c] = s.von_mises();
    region[c] = mesh.region(static_cast<int>(c));
  }
  f.cell.push_back({"stress", 6, std::move(tensor)});
  f.cell.push_back({"von_mises", 1, std::move(von_mises)});
  f.cell.push_back({"region", 1, std::move(region), -1.0});
  if (dim == 2 && !sol.contact.empty()) f.cell.push_back({"contact", 1, std::vector<std::uint8_t>(nc, 0), 1.0});
  if (indicators && indicators->size() == nc) f.cell.push_back({"error_indicator", 1, *indicators});
}

/// A field's values of the points or cells `which`, then `lines` times its value on the
/// contact lines.
void write_field(std::ostream& os, const Field& f, const std::vector<int>& which, std::size_t lines = 0) {
  std::visit(
      [&](const auto& all) {
        using T = typename std::decay_t<decltype(all)>::value_type;
        const auto w = static_cast<std::size_t>(f.width);
        std::vector<T> part;
        part.reserve(w * (which.size() + lines));
        for (const int k : which)
          for (std::size_t c = 0; c < w; ++c) part.push_back(all[w * static_cast<std::size_t>(k) + c]);
        part.resize(w * (which.size() + lines), static_cast<T>(f.on_lines));
        data_array(os, f.name, f.width, part);
      },
      f.values);
}

/// The VTK type of a field's values.
const char* vtk_type_of(const Field& f) {
  return std::visit([](const auto& all) { return detail::vtk_type<typename std::decay_t<decltype(all)>::value_type>(); },
                    f.values);
}

/// One file of solution.vtu: the points and cells `s` selects, and the arrays `fields`
/// restricted to them.
template <class MeshType>
void write_selection(std::ostream& os, const MeshType& mesh, const Fields& fields, const Selection& s) {
  constexpr bool solid = std::is_same_v<MeshType, Mesh3D>;
  const Cells cells = cells_of(mesh, s);
  file_head(os, s.points.size(), cells.types.size());
  write_points(os, mesh.vertices(), s.points);
  write_cells(os, cells, solid);
  os << "      <PointData Vectors=\"displacement\">\n";
  for (const Field& f : fields.point) write_field(os, f, s.points);
  os << "      </PointData>\n";
  os << "      <CellData Tensors=\"stress\" Scalars=\"von_mises\">\n";
  for (const Field& f : fields.cell) write_field(os, f, s.cells, cells.contact_lines);
  os << "      </CellData>\n";
  file_tail(os);
}

}  // namespace

/// The arrays, made once, and the writers of a body's file and of a share's.
struct SolutionVtu::Impl {
  Fields fields;
  BodyRange whole;
  std::function<void(std::ostream&, const Fields&, const BodyRange&)> body;
  std::function<void(std::ostream&, const Fields&, const VertexShare&, const BodyRange*)> share;
};

template <class MeshType, int dim>
std::unique_ptr<const SolutionVtu::Impl> SolutionVtu::make(const MeshType& mesh, const MaterialTable& materials,
                                                           const BasicContactSolution<dim>& sol,
                                                           const std::vector<double>* indicators) {
  auto impl = std::make_unique<Impl>();
  const auto nv = static_cast<std::size_t>(mesh.num_vertices());
  if (sol.u.size() != dim * static_cast<Eigen::Index>(nv))
    throw InputError("the solution has " + std::to_string(sol.u.size()) + " values for " + std::to_string(nv) +
                     " vertices (" + std::to_string(dim) + " per vertex)");
  add_point_data(impl->fields, nv, sol);
  add_cell_data(impl->fields, mesh, materials, sol, indicators);
  impl->whole = BodyRange{"the mesh", 0, mesh.num_vertices(), 0, num_cells(mesh), 0};
  impl->body = [&mesh, &sol](std::ostream& os, const Fields& f, const BodyRange& body) {
    write_selection(os, mesh, f, body_selection(mesh, sol, body));
  };
  impl->share = [&mesh, &sol](std::ostream& os, const Fields& f, const VertexShare& share, const BodyRange* body) {
    write_selection(os, mesh, f, share_selection(mesh, sol, share, body));
  };
  return impl;
}

SolutionVtu::SolutionVtu(const Mesh& mesh, const MaterialTable& materials, const ContactSolution& solution,
                         const std::vector<double>* indicators)
    : impl_(make(mesh, materials, solution, indicators)) {}

SolutionVtu::SolutionVtu(const Mesh3D& mesh, const MaterialTable& materials, const ContactSolution3D& solution,
                         const std::vector<double>* indicators)
    : impl_(make(mesh, materials, solution, indicators)) {}

SolutionVtu::~SolutionVtu() = default;

void SolutionVtu::write(std::ostream& os) const { impl_->body(os, impl_->fields, impl_->whole); }

void SolutionVtu::write(std::ostream& os, const BodyRange& body) const {
  const BodyRange& all = impl_->whole;
  if (body.first_vertex < 0 || body.vertices < 0 || body.first_vertex + body.vertices > all.vertices ||
      body.first_cell < 0 || body.cells < 0 || body.first_cell + body.cells > all.cells)
    throw InputError("body '" + body.name + "' (vertices " + std::to_string(body.first_vertex) + " + " +
                     std::to_string(body.vertices) + ", cells " + std::to_string(body.first_cell) + " + " +
                     std::to_string(body.cells) + ") is not a part of a mesh of " + std::to_string(all.vertices) +
                     " vertices and " + std::to_string(all.cells) + " cells");
  impl_->body(os, impl_->fields, body);
}

void SolutionVtu::write_share(std::ostream& os, const VertexShare& share, const BodyRange* body) const {
  impl_->share(os, impl_->fields, share, body);
}

void SolutionVtu::write_pieces(std::ostream& os, const std::vector<std::string>& files) const {
  const auto declare = [&os](const Field& f) {
    os << "      <PDataArray type=\"" << vtk_type_of(f) << "\" Name=\"" << f.name << "\"";
    if (f.width > 1) os << " NumberOfComponents=\"" << f.width << "\"";
    os << "/>\n";
  };
  os << "<?xml version=\"1.0\"?>\n"
     << "<VTKFile type=\"PUnstructuredGrid\" version=\"1.0\" byte_order=\""
     << (std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian") << "\" header_type=\"UInt64\">\n"
     << "  <PUnstructuredGrid GhostLevel=\"0\">\n"
     << "    <PPoints>\n      <PDataArray type=\"Float64\" Name=\"Points\" NumberOfComponents=\"3\"/>\n    </PPoints>\n"
     << "    <PPointData Vectors=\"displacement\">\n";
  for (const Field& f : impl_->fields.point) declare(f);
  os << "    </PPointData>\n    <PCellData Tensors=\"stress\" Scalars=\"von_mises\">\n";
  for (const Field& f : impl_->fields.cell) declare(f);
  os << "    </PCellData>\n";
  for (const auto& file : files) os << "    <Piece Source=\"" << file << "\"/>\n";
  os << "  </PUnstructuredGrid>\n</VTKFile>\n";
}

void write_vtu(std::ostream& os, const Mesh& mesh, const MaterialTable& materials, const ContactSolution& sol,
               const std::vector<double>* indicators) {
  SolutionVtu(mesh, materials, sol, indicators).write(os);
}

void write_vtu(std::ostream& os, const Mesh3D& mesh, const MaterialTable& materials, const ContactSolution3D& sol,
               const std::vector<double>* indicators) {
  SolutionVtu(mesh, materials, sol, indicators).write(os);
}

void write_contact_surface_vtu(std::ostream& os, const Mesh3D& mesh, const std::vector<int>& faces,
                               const ContactSolution3D& sol) {
  std::vector<std::vector<int>> loops;
  loops.reserve(faces.size());
  for (int f : faces) loops.push_back(mesh.face(f).vertices);
  write_contact_surface_vtu(os, mesh, loops, sol);
}

void write_contact_surface_vtu(std::ostream& os, const Mesh3D& mesh, const std::vector<std::vector<int>>& faces,
                               const ContactSolution3D& sol) {
  // the points of the contact faces, numbered in the order of their vertex ids
  std::map<int, std::int64_t> point;
  for (const auto& loop : faces)
    for (int v : loop) point.emplace(v, 0);
  std::int64_t next = 0;
  std::vector<Vec3> points;
  std::vector<std::int64_t> vertex;
  for (auto& [v, id] : point) {
    id = next++;
    points.push_back(mesh.vertex(v));
    vertex.push_back(v);
  }
  Cells cells;
  for (const auto& loop : faces) {
    for (int v : loop) cells.connectivity.push_back(point.at(v));
    cells.close(7);  // VTK_POLYGON
  }
  file_head(os, points.size(), faces.size());
  write_points(os, points);
  write_cells(os, cells, false);

  const ContactFields all(static_cast<std::size_t>(mesh.num_vertices()), sol);
  std::vector<double> displacement, u_nu, pressure, gap;
  std::vector<std::uint8_t> node;
  for (std::int64_t v : vertex) {
    const auto k = static_cast<std::size_t>(v);
    for (int c = 0; c < 3; ++c) displacement.push_back(sol.u(3 * static_cast<Eigen::Index>(v) + c));
    u_nu.push_back(all.u_nu[k]);
    pressure.push_back(all.pressure[k]);
    gap.push_back(all.gap[k]);
    node.push_back(all.node[k]);
  }
  os << "      <PointData Vectors=\"displacement\" Scalars=\"pressure\">\n";
  data_array(os, "vertex", 1, vertex);
  data_array(os, "displacement", 3, displacement);
  data_array(os, "u_nu", 1, u_nu);
  data_array(os, "pressure", 1, pressure);
  data_array(os, "gap", 1, gap);
  data_array(os, "contact_node", 1, node);
  if (has_tangential(sol)) {
    // the friction's point data, picked at the surface's points
    std::vector<double> u_tau, traction;
    std::vector<std::uint8_t> state;
    std::vector<const ContactNode3D*> of(static_cast<std::size_t>(mesh.num_vertices()), nullptr);
    for (const ContactNode3D& n : sol.contact) of[static_cast<std::size_t>(n.vertex)] = &n;
    for (std::int64_t v : vertex) {
      const ContactNode3D* n = of[static_cast<std::size_t>(v)];
      for (int c = 0; c < 3; ++c) {
        u_tau.push_back(n ? n->u_tangential(c) : 0.0);
        traction.push_back(n ? n->friction_vector(c) / n->weight : 0.0);
      }
      state.push_back(n ? friction_state_code(n->friction_state) : 0);
    }
    data_array(os, "u_tau", 3, u_tau);
    data_array(os, "friction_traction", 3, traction);
    data_array(os, "friction_state", 1, state);
  }
  os << "      </PointData>\n";
  file_tail(os);
}

}  // namespace hemivem::app
