// solution.vtu and contact-surface.vtu (vtu.hpp): the file, its points, point data and cell data
// are written once for plane and solid bodies; the cells are each dimension's own (polygons and
// contact lines, or polyhedra).
#include <hemivem/app/vtu.hpp>

#include <hemivem/app/outputs.hpp>

#include "vtk_data_array.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <map>
#include <ostream>
#include <string>
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

/// The points, three coordinates each (z = 0 in the plane).
template <class Point>
void write_points(std::ostream& os, const std::vector<Point>& points) {
  std::vector<double> xyz(3 * points.size(), 0.0);
  for (std::size_t v = 0; v < points.size(); ++v)
    for (int c = 0; c < Point::RowsAtCompileTime; ++c) xyz[3 * v + static_cast<std::size_t>(c)] = points[v](c);
  os << "      <Points>\n";
  data_array(os, "Points", 3, xyz);
  os << "      </Points>\n";
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

/// A plane's polygons, then the contact lines.
Cells cells_of(const Mesh& mesh, const ContactSolution& sol) {
  Cells cells;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    for (int v : mesh.element(e)) cells.connectivity.push_back(v);
    cells.close(7);  // VTK_POLYGON
  }
  for (const auto& l : contact_lines(mesh, sol)) {
    cells.connectivity.insert(cells.connectivity.end(), {l[0], l[1]});
    cells.close(3);  // VTK_LINE: Gamma_3
    ++cells.contact_lines;
  }
  return cells;
}

/// A solid's cells as VTK_POLYHEDRON: the cell's points, and its faces as [number of faces,
/// then per face its number of points and their ids], each face counter-clockwise seen from
/// outside.
Cells cells_of(const Mesh3D& mesh, const ContactSolution3D&) {
  Cells cells;
  for (int c = 0; c < mesh.num_cells(); ++c) {
    for (int v : mesh.cell_vertices(c)) cells.connectivity.push_back(v);
    cells.close(42);
    const CellFaces loops = mesh.cell(c);
    cells.faces.push_back(static_cast<std::int64_t>(loops.size()));
    for (const auto& loop : loops) {
      cells.faces.push_back(static_cast<std::int64_t>(loop.size()));
      for (int v : loop) cells.faces.push_back(v);
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

/// With friction: u_tau, the friction traction (a plane's along tau, a solid's as vectors of
/// three components) and the state code, 0 off the contact nodes.
template <int dim>
void write_friction_point_data(std::ostream& os, std::size_t nv, const BasicContactSolution<dim>& sol) {
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
  data_array(os, "u_tau", static_cast<int>(width), u_tau);
  data_array(os, "friction_traction", static_cast<int>(width), traction);
  data_array(os, "friction_state", 1, state);
}

/// The displacement (three components) and the contact nodes' values; a plane's with several
/// contact parts also each node's part (-1 off the contact), with friction the friction's.
template <int dim>
void write_point_data(std::ostream& os, std::size_t nv, const BasicContactSolution<dim>& sol) {
  std::vector<double> displacement(3 * nv, 0.0);
  for (std::size_t v = 0; v < nv; ++v)
    for (std::size_t c = 0; c < dim; ++c) displacement[3 * v + c] = sol.u(static_cast<Eigen::Index>(dim * v + c));
  os << "      <PointData Vectors=\"displacement\">\n";
  data_array(os, "displacement", 3, displacement);
  if (!sol.contact.empty()) {
    const ContactFields f(nv, sol);
    data_array(os, "u_nu", 1, f.u_nu);
    data_array(os, "pressure", 1, f.pressure);
    data_array(os, "gap", 1, f.gap);
    if (dim == 2 && sol.contact_parts.size() > 1) {
      std::vector<std::int32_t> part(nv, -1);
      for (const auto& n : sol.contact) part[static_cast<std::size_t>(n.vertex)] = n.part;
      data_array(os, "contact_part", 1, part);
    }
    if (has_tangential(sol)) write_friction_point_data(os, nv, sol);
  }
  os << "      </PointData>\n";
}

/// Stresses, von Mises, regions per cell; the contact lines after them carry zeros and
/// contact = 1 (a plane's cell data "contact", written when there is contact).
template <class MeshType, int dim>
void write_cell_data(std::ostream& os, const MeshType& mesh, const MaterialTable& materials,
                     const BasicContactSolution<dim>& sol, std::size_t nl, const std::vector<double>* indicators) {
  const std::vector<BasicCellStress<dim>> stress = cell_stresses(mesh, materials, sol.u);
  const auto nc = static_cast<std::size_t>(num_cells(mesh));
  // ParaView's symmetric-tensor order: XX, YY, ZZ, XY, YZ, XZ
  std::vector<double> tensor(6 * (nc + nl), 0.0), von_mises(nc + nl, 0.0);
  std::vector<std::int32_t> region(nc + nl, -1);
  for (std::size_t c = 0; c < nc; ++c) {
    const BasicCellStress<dim>& s = stress[c];
    for (std::size_t k = 0; const double value : {s.xx, s.yy, s.zz, s.xy, s.yz, s.xz}) tensor[6 * c + k++] = value;
    von_mises[c] = s.von_mises();
    region[c] = mesh.region(static_cast<int>(c));
  }
  os << "      <CellData Tensors=\"stress\" Scalars=\"von_mises\">\n";
  data_array(os, "stress", 6, tensor);
  data_array(os, "von_mises", 1, von_mises);
  data_array(os, "region", 1, region);
  if (dim == 2 && !sol.contact.empty()) {
    std::vector<std::uint8_t> on_contact(nc + nl, 0);
    for (std::size_t l = 0; l < nl; ++l) on_contact[nc + l] = 1;
    data_array(os, "contact", 1, on_contact);
  }
  if (indicators && indicators->size() == nc) {
    std::vector<double> eta(nc + nl, 0.0);
    std::copy(indicators->begin(), indicators->end(), eta.begin());
    data_array(os, "error_indicator", 1, eta);
  }
  os << "      </CellData>\n";
}

template <class MeshType, int dim>
void write_solution_vtu(std::ostream& os, const MeshType& mesh, const MaterialTable& materials,
                        const BasicContactSolution<dim>& sol, const std::vector<double>* indicators) {
  const Cells cells = cells_of(mesh, sol);
  const auto nv = static_cast<std::size_t>(mesh.num_vertices());
  file_head(os, nv, cells.types.size());
  write_points(os, mesh.vertices());
  write_cells(os, cells, dim == 3);
  write_point_data(os, nv, sol);
  write_cell_data(os, mesh, materials, sol, cells.contact_lines, indicators);
  file_tail(os);
}

}  // namespace

void write_vtu(std::ostream& os, const Mesh& mesh, const MaterialTable& materials, const ContactSolution& sol,
               const std::vector<double>* indicators) {
  write_solution_vtu(os, mesh, materials, sol, indicators);
}

void write_vtu(std::ostream& os, const Mesh3D& mesh, const MaterialTable& materials, const ContactSolution3D& sol,
               const std::vector<double>* indicators) {
  write_solution_vtu(os, mesh, materials, sol, indicators);
}

void write_contact_surface_vtu(std::ostream& os, const Mesh3D& mesh, const std::vector<int>& faces,
                               const ContactSolution3D& sol) {
  // the points of the contact faces, numbered in the order of their vertex ids
  std::map<int, std::int64_t> point;
  for (int f : faces)
    for (int v : mesh.face(f).vertices) point.emplace(v, 0);
  std::int64_t next = 0;
  std::vector<Vec3> points;
  std::vector<std::int64_t> vertex;
  for (auto& [v, id] : point) {
    id = next++;
    points.push_back(mesh.vertex(v));
    vertex.push_back(v);
  }
  Cells cells;
  for (int f : faces) {
    for (int v : mesh.face(f).vertices) cells.connectivity.push_back(point.at(v));
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
