// solution.vtu: VTK's XML unstructured grid (docs/reference/outputs.md), every array in VTK's
// binary form: zlib-compressed in blocks of 32 KiB, base64-encoded inline, UInt64 headers.
// ParaView, VisIt and meshio read it.
#pragma once

#include <cstdint>
#include <iosfwd>
#include <string>
#include <vector>

#include <hemivem/contact/solver.hpp>
#include <hemivem/vem/material.hpp>
#include <hemivem/mesh/mesh.hpp>

namespace hemivem::app {

/// The VTU code of a friction state: 0 not a contact node, 1 stick, 2 slip, 3 slip-weakening,
/// 4 slip-kinetic.
std::uint8_t friction_state_code(FrictionState state);

/// The mesh's polygons (then Gamma_3's edges as line cells when there is contact) with the
/// displacement, the contact values at the contact nodes (with friction also u_tau, the
/// friction traction and the state code), the projected stresses, the
/// regions and the contact flag of each cell; with `indicators` (one per element) the error
/// indicators eta_E as the cell field "error_indicator" (0 on the contact lines).
void write_vtu(std::ostream& stream, const Mesh& mesh, const MaterialTable& materials, const ContactSolution& solution,
               const std::vector<double>* indicators = nullptr);

}  // namespace hemivem::app
