// solution.vtu (and a solid's contact-surface.vtu): VTK's XML unstructured grid
// (docs/reference/outputs.md), every array in VTK's binary form: zlib-compressed in blocks of
// 32 KiB, base64-encoded inline, UInt64 headers. ParaView, VisIt and meshio read it. One writer
// serves plane and solid bodies; only the cells differ (polygons and the contact lines of a
// plane, VTK_POLYHEDRON cells of a solid). The same writer writes the whole mesh or one body of
// a mesh of several (solution.body-NAME.vtu).
#pragma once

#include <cstdint>
#include <iosfwd>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <hemivem/mesh/vertex_order.hpp>
#include <hemivem/app/stress.hpp>
#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/mesh/body_range.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>
#include <hemivem/vem/material.hpp>

namespace hemivem::app {

/// The VTU code of a friction state: 0 not a contact node, 1 stick, 2 slip, 3 slip-weakening,
/// 4 slip-kinetic.
std::uint8_t friction_state_code(FrictionState state);

/// The mesh's cells with the point data displacement (3 components) and, with contact, u_nu,
/// pressure and gap (0 off the contact nodes), and the cell data stress (6 components in
/// ParaView's symmetric-tensor order XX, YY, ZZ, XY, YZ, XZ), von_mises, region and, with
/// `indicators` (one per cell), the error indicators eta_E as "error_indicator".
/// A plane's cells are its polygons then Gamma_3's edges as line cells when there is contact
/// (flagged by the cell data "contact", carrying zeros elsewhere); with several contact parts
/// the point data contact_part, and with friction also u_tau, the friction traction and the
/// state code.
void write_vtu(std::ostream& stream, const Mesh& mesh, const MaterialTable& materials, const ContactSolution& solution,
               const std::vector<double>* indicators = nullptr);
/// A solid's cells are VTK_POLYHEDRON (type 42, with the arrays `faces` and `faceoffsets`).
void write_vtu(std::ostream& stream, const Mesh3D& mesh, const MaterialTable& materials,
               const ContactSolution3D& solution, const std::vector<double>* indicators = nullptr);

/// solution.vtu's arrays of a solution, made once (the stresses included), written for the
/// whole mesh (write_vtu) or for one body of a mesh of several (RunInfo::bodies). It refers to
/// the mesh and the solution, which must outlive it.
class SolutionVtu {
 public:
  SolutionVtu(const Mesh& mesh, const MaterialTable& materials, const ContactSolution& solution,
              const std::vector<double>* indicators = nullptr);
  SolutionVtu(const Mesh3D& mesh, const MaterialTable& materials, const ContactSolution3D& solution,
              const std::vector<double>* indicators = nullptr);
  ~SolutionVtu();
  SolutionVtu(const SolutionVtu&) = delete;
  SolutionVtu& operator=(const SolutionVtu&) = delete;

  /// Every point and cell: solution.vtu (write_vtu).
  void write(std::ostream& stream) const;
  /// The points and cells of `body` (a consecutive range of each of the mesh's), numbered from
  /// 0, with the arrays of solution.vtu restricted to them: a plane's contact lines whose two
  /// ends are the body's points follow its polygons. InputError when `body` is not a range of
  /// the mesh's; InternalError when one of its cells has a vertex outside its vertices.
  void write(std::ostream& stream, const BodyRange& body) const;
  /// One piece of solution.pvtu: the share `share` of a split of the mesh's vertices among
  /// processes. Its cells are those whose smallest vertex is one of them (and a plane's contact
  /// lines whose smaller end is), its points every vertex they reach, in the mesh's order, with
  /// the arrays of solution.vtu restricted to them: the pieces of a split hold each cell once.
  /// InputError when the share is not one of the mesh's (VertexShare::mask). With `body`, the
  /// share's piece of the body's file (write above): the share's cells whose smallest vertex is
  /// the body's, and a plane's contact lines whose two ends are; the pieces of a split hold each
  /// of the body's cells once.
  void write_share(std::ostream& stream, const VertexShare& share, const BodyRange* body = nullptr) const;
  /// solution.pvtu: VTK's parallel unstructured grid naming the pieces `files` (each written by
  /// write_share of a solution with the same arrays as this one), in their order.
  void write_pieces(std::ostream& stream, const std::vector<std::string>& files) const;

 private:
  struct Impl;
  template <class MeshType, int dim>
  static std::unique_ptr<const Impl> make(const MeshType& mesh, const MaterialTable& materials,
                                          const BasicContactSolution<dim>& solution, const std::vector<double>* indicators);
  std::unique_ptr<const Impl> impl_;
};

/// contact-surface.vtu: the contact faces `faces` of a solid as VTK_POLYGON cells on their own
/// points, with the point data vertex (the id in the mesh), displacement, u_nu, pressure, gap
/// and contact_node (1 at the contact nodes; the other points, prescribed ones, carry 0 values).
void write_contact_surface_vtu(std::ostream& stream, const Mesh3D& mesh, const std::vector<int>& faces,
                               const ContactSolution3D& solution);
/// The same of the contact faces given as vertex loops of `mesh` (each as a face's vertices,
/// counter-clockwise seen from outside its cell): those a run across processes gathered from
/// the processes' pieces (WholeOfPieces::contact_surface).
void write_contact_surface_vtu(std::ostream& stream, const Mesh3D& mesh, const std::vector<std::vector<int>>& loops,
                               const ContactSolution3D& sol);

}  // namespace hemivem::app
