#include <hemivem/app/vtu.hpp>

#include <hemivem/app/outputs.hpp>

#include "vtk_data_array.hpp"

#include <array>
#include <bit>
#include <cmath>
#include <cstdint>
#include <ostream>
#include <string>
#include <string_view>
#include <vector>

#include <hemivem/error.hpp>
#include <hemivem/vem/stress.hpp>

namespace hemivem::app {

std::uint8_t friction_state_code(FrictionState state) { return static_cast<std::uint8_t>(state); }

namespace {

using detail::data_array;

void write_points(std::ostream& os, const Mesh& mesh) {
  const auto nv = static_cast<std::size_t>(mesh.num_vertices());
  std::vector<double> points(3 * nv, 0.0);
  for (std::size_t v = 0; v < nv; ++v) {
    const Vec2& p = mesh.vertex(static_cast<int>(v));
    points[3 * v] = p.x();
    points[3 * v + 1] = p.y();
  }
  os << "      <Points>\n";
  data_array(os, "Points", 3, points);
  os << "      </Points>\n";
}

/// The mesh's polygons, then the contact lines.
void write_cells(std::ostream& os, const Mesh& mesh, const std::vector<std::array<int, 2>>& lines) {
  const auto ne = static_cast<std::size_t>(mesh.num_elements());
  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::uint8_t> types;
  for (std::size_t e = 0; e < ne; ++e) {
    for (int v : mesh.element(static_cast<int>(e))) connectivity.push_back(v);
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
    types.push_back(7);  // VTK_POLYGON
  }
  for (const auto& l : lines) {
    connectivity.insert(connectivity.end(), {l[0], l[1]});
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
    types.push_back(3);  // VTK_LINE: Gamma_3
  }
  os << "      <Cells>\n";
  data_array(os, "connectivity", 1, connectivity);
  data_array(os, "offsets", 1, offsets);
  data_array(os, "types", 1, types);
  os << "      </Cells>\n";
}

/// The contact nodes' values, 0 at the other vertices; with friction also u_tau, the friction
/// traction and the state code.
void write_contact_point_data(std::ostream& os, const Mesh& mesh, const ContactSolution& sol) {
  const auto nv = static_cast<std::size_t>(mesh.num_vertices());
  std::vector<double> u_nu(nv, 0.0), pressure(nv, 0.0), gap(nv, 0.0);
  for (const auto& n : sol.contact) {
    const auto v = static_cast<std::size_t>(n.vertex);
    u_nu[v] = n.u_nu;
    pressure[v] = std::isfinite(n.pressure()) ? n.pressure() : 0.0;
    gap[v] = std::isfinite(n.gap) ? n.gap : 0.0;  // a ray that misses the obstacle: +inf, written as 0
  }
  data_array(os, "u_nu", 1, u_nu);
  data_array(os, "pressure", 1, pressure);
  data_array(os, "gap", 1, gap);
  if (sol.contact_parts.size() > 1) {  // several contact parts: each node's index, -1 off the contact
    std::vector<std::int32_t> part(nv, -1);
    for (const auto& n : sol.contact) part[static_cast<std::size_t>(n.vertex)] = n.part;
    data_array(os, "contact_part", 1, part);
  }
  if (!has_tangential(sol)) return;
  std::vector<double> u_tau(nv, 0.0), traction(nv, 0.0);
  std::vector<std::uint8_t> state(nv, 0);
  for (const auto& n : sol.contact) {
    const auto v = static_cast<std::size_t>(n.vertex);
    u_tau[v] = n.u_tau;
    traction[v] = n.friction_force / n.weight;
    state[v] = friction_state_code(n.friction_state);
  }
  data_array(os, "u_tau", 1, u_tau);
  data_array(os, "friction_traction", 1, traction);
  data_array(os, "friction_state", 1, state);
}

void write_point_data(std::ostream& os, const Mesh& mesh, const ContactSolution& sol) {
  const auto nv = static_cast<std::size_t>(mesh.num_vertices());
  std::vector<double> displacement(3 * nv, 0.0);
  for (std::size_t v = 0; v < nv; ++v) {
    displacement[3 * v] = sol.u(static_cast<Eigen::Index>(2 * v));
    displacement[3 * v + 1] = sol.u(static_cast<Eigen::Index>(2 * v + 1));
  }
  os << "      <PointData Vectors=\"displacement\">\n";
  data_array(os, "displacement", 3, displacement);
  if (!sol.contact.empty()) write_contact_point_data(os, mesh, sol);
  os << "      </PointData>\n";
}

/// Stresses, von Mises, regions per polygon; the `nl` contact lines carry zeros and contact = 1.
void write_cell_data(std::ostream& os, const Mesh& mesh, const MaterialTable& materials, const ContactSolution& sol,
                     std::size_t nl, const std::vector<double>* indicators) {
  const std::vector<ElementStress> stress = element_stresses(mesh, materials, sol.u);
  const auto ne = static_cast<std::size_t>(mesh.num_elements());
  // ParaView's symmetric-tensor order: XX, YY, ZZ, XY, YZ, XZ; line cells carry zeros
  std::vector<double> tensor(6 * (ne + nl), 0.0), von_mises(ne + nl, 0.0);
  std::vector<std::int32_t> region(ne + nl, -1);
  std::vector<std::uint8_t> on_contact(ne + nl, 0);
  for (std::size_t e = 0; e < ne; ++e) {
    const ElementStress& s = stress[e];
    tensor[6 * e] = s.xx;
    tensor[6 * e + 1] = s.yy;
    tensor[6 * e + 2] = s.zz;
    tensor[6 * e + 3] = s.xy;
    von_mises[e] = s.von_mises();
    region[e] = mesh.region(static_cast<int>(e));
  }
  for (std::size_t l = 0; l < nl; ++l) on_contact[ne + l] = 1;
  os << "      <CellData Tensors=\"stress\" Scalars=\"von_mises\">\n";
  data_array(os, "stress", 6, tensor);
  data_array(os, "von_mises", 1, von_mises);
  data_array(os, "region", 1, region);
  if (!sol.contact.empty()) data_array(os, "contact", 1, on_contact);
  if (indicators && indicators->size() == ne) {
    std::vector<double> eta(ne + nl, 0.0);
    std::copy(indicators->begin(), indicators->end(), eta.begin());
    data_array(os, "error_indicator", 1, eta);
  }
  os << "      </CellData>\n";
}

}  // namespace

void write_vtu(std::ostream& os, const Mesh& mesh, const MaterialTable& materials, const ContactSolution& sol,
               const std::vector<double>* indicators) {
  const std::vector<std::array<int, 2>> lines = contact_lines(mesh, sol);
  os << "<?xml version=\"1.0\"?>\n"
     << "<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" byte_order=\""
     << (std::endian::native == std::endian::little ? "LittleEndian" : "BigEndian")
     << "\" header_type=\"UInt64\" compressor=\"vtkZLibDataCompressor\">\n"
     << "  <UnstructuredGrid>\n"
     << "    <Piece NumberOfPoints=\"" << mesh.num_vertices() << "\" NumberOfCells=\""
     << static_cast<std::size_t>(mesh.num_elements()) + lines.size() << "\">\n";
  write_points(os, mesh);
  write_cells(os, mesh, lines);
  write_point_data(os, mesh, sol);
  write_cell_data(os, mesh, materials, sol, lines.size(), indicators);
  os << "    </Piece>\n"
     << "  </UnstructuredGrid>\n"
     << "</VTKFile>\n";
}

}  // namespace hemivem::app
