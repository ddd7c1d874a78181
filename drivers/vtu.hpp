// solution.vtu: VTK's XML unstructured grid (drivers/OUTPUTS.md), every array in VTK's
// binary form: zlib-compressed in blocks of 32 KiB, base64-encoded inline, UInt64 headers.
// ParaView, VisIt and meshio read it.
#pragma once

#include <iosfwd>

#include <hemivem/contact_solver.hpp>
#include <hemivem/material.hpp>
#include <hemivem/mesh.hpp>

namespace hemivem::cli {

/// The mesh's polygons (then Gamma_3's edges as line cells when there is contact) with the
/// displacement, the contact values at the contact nodes, the projected stresses, the
/// regions and the contact flag of each cell.
void write_vtu(std::ostream& stream, const Mesh& mesh, const MaterialTable& materials, const ContactSolution& solution);

}  // namespace hemivem::cli
