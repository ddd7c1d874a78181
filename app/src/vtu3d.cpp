// solution.vtu and contact-surface.vtu of a three-dimensional solve (outputs3d.hpp): VTK's XML
// unstructured grids with the arrays of write_vtu (vtk_data_array.hpp).
#include <hemivem/app/outputs3d.hpp>

#include <bit>
#include <cmath>
#include <cstdint>
#include <map>
#include <ostream>
#include <vector>

#include "vtk_data_array.hpp"

namespace hemivem::app {

namespace {

using detail::data_array;

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

void points_of(std::ostream& os, const std::vector<Vec3>& points) {
  std::vector<double> xyz;
  xyz.reserve(3 * points.size());
  for (const Vec3& p : points) xyz.insert(xyz.end(), {p.x(), p.y(), p.z()});
  os << "      <Points>\n";
  data_array(os, "Points", 3, xyz);
  os << "      </Points>\n";
}

/// The contact values of each vertex (0 off the contact nodes): u_nu, pressure, gap, flag.
struct ContactFields {
  std::vector<double> u_nu, pressure, gap;
  std::vector<std::uint8_t> node;
  ContactFields(std::size_t vertices, const ContactSolution3D& sol)
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

}  // namespace

void write_vtu(std::ostream& os, const Mesh3D& mesh, const MaterialTable& materials, const ContactSolution3D& sol,
                  const std::vector<double>* indicators) {
  const auto nv = static_cast<std::size_t>(mesh.num_vertices());
  const auto nc = static_cast<std::size_t>(mesh.num_cells());
  file_head(os, nv, nc);
  points_of(os, mesh.vertices());

  // VTK_POLYHEDRON: the cell's points, and its faces as [number of faces, then per face its
  // number of points and their ids], each face counter-clockwise seen from outside
  std::vector<std::int64_t> connectivity, offsets, faces, faceoffsets;
  std::vector<std::uint8_t> types;
  for (int c = 0; c < mesh.num_cells(); ++c) {
    for (int v : mesh.cell_vertices(c)) connectivity.push_back(v);
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
    types.push_back(42);
    const CellFaces loops = mesh.cell(c);
    faces.push_back(static_cast<std::int64_t>(loops.size()));
    for (const auto& loop : loops) {
      faces.push_back(static_cast<std::int64_t>(loop.size()));
      for (int v : loop) faces.push_back(v);
    }
    faceoffsets.push_back(static_cast<std::int64_t>(faces.size()));
  }
  os << "      <Cells>\n";
  data_array(os, "connectivity", 1, connectivity);
  data_array(os, "offsets", 1, offsets);
  data_array(os, "types", 1, types);
  data_array(os, "faces", 1, faces);
  data_array(os, "faceoffsets", 1, faceoffsets);
  os << "      </Cells>\n";

  std::vector<double> displacement(3 * nv);
  for (std::size_t k = 0; k < 3 * nv; ++k) displacement[k] = sol.u(static_cast<Eigen::Index>(k));
  os << "      <PointData Vectors=\"displacement\">\n";
  data_array(os, "displacement", 3, displacement);
  if (!sol.contact.empty()) {
    const ContactFields f(nv, sol);
    data_array(os, "u_nu", 1, f.u_nu);
    data_array(os, "pressure", 1, f.pressure);
    data_array(os, "gap", 1, f.gap);
  }
  os << "      </PointData>\n";

  // ParaView's symmetric-tensor order: XX, YY, ZZ, XY, YZ, XZ
  const std::vector<CellStress3D> stress = cell_stresses_3d(mesh, materials, sol.u);
  std::vector<double> tensor(6 * nc), von_mises(nc);
  std::vector<std::int32_t> region(nc);
  for (std::size_t c = 0; c < nc; ++c) {
    const CellStress3D& s = stress[c];
    tensor[6 * c] = s.xx;
    tensor[6 * c + 1] = s.yy;
    tensor[6 * c + 2] = s.zz;
    tensor[6 * c + 3] = s.xy;
    tensor[6 * c + 4] = s.yz;
    tensor[6 * c + 5] = s.xz;
    von_mises[c] = s.von_mises();
    region[c] = mesh.region(static_cast<int>(c));
  }
  os << "      <CellData Tensors=\"stress\" Scalars=\"von_mises\">\n";
  data_array(os, "stress", 6, tensor);
  data_array(os, "von_mises", 1, von_mises);
  data_array(os, "region", 1, region);
  if (indicators != nullptr && indicators->size() == nc) data_array(os, "error_indicator", 1, *indicators);
  os << "      </CellData>\n";
  file_tail(os);
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
  file_head(os, points.size(), faces.size());
  points_of(os, points);

  std::vector<std::int64_t> connectivity, offsets;
  std::vector<std::uint8_t> types;
  for (int f : faces) {
    for (int v : mesh.face(f).vertices) connectivity.push_back(point.at(v));
    offsets.push_back(static_cast<std::int64_t>(connectivity.size()));
    types.push_back(7);  // VTK_POLYGON
  }
  os << "      <Cells>\n";
  data_array(os, "connectivity", 1, connectivity);
  data_array(os, "offsets", 1, offsets);
  data_array(os, "types", 1, types);
  os << "      </Cells>\n";

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
  os << "      </PointData>\n";
  file_tail(os);
}

}  // namespace hemivem::app
