// The files a three-dimensional solve leaves in its output folder (docs/reference/outputs.md,
// "Three-dimensional solves"): result.json (its 3D layout), contact.csv, displacement.csv,
// history.csv, solution.vtu (polyhedra), contact-surface.vtu (the contact faces), scene.toml and
// the gnuplot pictures deformed.png and pressure.png.
#pragma once

#include <filesystem>
#include <iosfwd>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include <hemivem/app/figures.hpp>
#include <hemivem/app/outputs.hpp>
#include <hemivem/contact/contact3d.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/vem/material.hpp>

namespace hemivem::app {

/// The result.json document of a 3D solve ("schema": "hemivem-result/13", "dimension": 3): the
/// keys of result_json that apply, points and vectors with three components (contact[].x and
/// contact[].normal [x, y, z]), contact_zone with its area, error_estimate; adapt, path and
/// friction null.
nlohmann::json result_json(const Mesh3D& mesh, const ContactSolution3D& solution, const RunInfo& info);

/// The projected stress of each cell: the stress of the P1 projection Pi u_h (constant on the
/// cell), sigma = lambda tr(eps) I + 2 mu eps with MaterialTable::lame(region), eps the
/// symmetric part of the projection's gradient.
struct CellStress3D {
  double xx = 0.0, yy = 0.0, zz = 0.0, yz = 0.0, xz = 0.0, xy = 0.0;
  /// sqrt(((xx - yy)^2 + (yy - zz)^2 + (zz - xx)^2) / 2 + 3 (yz^2 + xz^2 + xy^2)).
  double von_mises() const;
};
std::vector<CellStress3D> cell_stresses_3d(const Mesh3D& mesh, const MaterialTable& materials, const Eigen::VectorXd& u);

/// solution.vtu of a 3D solve: the cells as VTK_POLYHEDRON (type 42, with the arrays `faces`
/// and `faceoffsets`), the point data displacement (3 components) and, with contact, u_nu,
/// pressure and gap (0 off the contact nodes), the cell data stress (6 components in ParaView's
/// symmetric-tensor order XX, YY, ZZ, XY, YZ, XZ), von_mises, region and, with `indicators`
/// (one per cell), error_indicator. Arrays as write_vtu's.
void write_vtu(std::ostream& stream, const Mesh3D& mesh, const MaterialTable& materials,
                  const ContactSolution3D& solution, const std::vector<double>* indicators = nullptr);

/// contact-surface.vtu: the contact faces `faces` as VTK_POLYGON cells on their own points,
/// with the point data vertex (the id in the mesh), displacement, u_nu, pressure, gap and
/// contact_node (1 at the contact nodes; the other points, prescribed ones, carry 0 values).
void write_contact_surface_vtu(std::ostream& stream, const Mesh3D& mesh, const std::vector<int>& faces,
                               const ContactSolution3D& solution);

/// deformed.png of a 3D solve: the boundary faces of the deformed body in perspective, filled
/// with the colour of |u| (viridis), the displacement magnified so that its largest value is a
/// tenth of the body's size (the title says by how much), with the contact nodes marked.
Figure deformed_figure_3d(const Mesh3D& mesh, const ContactSolution3D& solution, const RunInfo& info);

/// pressure.png: the contact pressure over the contact faces `faces`, a colour map seen along
/// the axis nearest to the contact nodes' mean normal (over x and y for a contact on a bottom
/// or top face), each face filled from its nodes' pressures (0 at a node that is not a contact
/// node); the solution must have contact nodes.
Figure pressure_figure(const Mesh3D& mesh, const std::vector<int>& faces, const ContactSolution3D& solution,
                       const RunInfo& info);

/// Writes the `wanted` files (names from all_outputs_3d()) into `dir` as one transaction, as
/// write_outputs does: every file is written beside `dir` and the set replaces the previous one
/// at once (an earlier run's file of a name of all_outputs() or all_outputs_3d() that this run
/// did not write goes); the pictures are skipped with their reason when gnuplot is missing or
/// fails. Throws InputError for an unknown name (before writing anything), a solution whose size
/// does not match the mesh, when another process is writing `dir`, and for any I/O failure
/// (`dir` then keeps its previous set); never prints.
OutputReport write_outputs(const std::filesystem::path& dir, const Mesh3D& mesh, const MaterialTable& materials,
                              const std::vector<int>& contact_faces, const ContactSolution3D& solution,
                              const RunInfo& info, const std::vector<std::string>& wanted = all_outputs_3d());

}  // namespace hemivem::app
