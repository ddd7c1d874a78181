// The kernels of the load vector, one per dimension (assembly.cpp, assembly3d.cpp): the load of
// the body force on one cell and of a traction on one boundary facet. Each hands every term it
// adds to the load vector to `add(dof, value)`, in the order the load vector takes them, so that
// the whole load (assemble_load) and the load of some rows alone (assemble_rows) are summed alike,
// to the bit.
#pragma once

#include <hemivem/vem/assembly.hpp>
#include <hemivem/vem/assembly3d.hpp>

#include <functional>

namespace hemivem::detail {

/// Receives a term of the load vector: the value added to one dof (dim v + c).
using LoadTerms = std::function<void(int dof, double value)>;

/// The body force's load on cell c (3.13): per local basis function phi_k, the integral of
/// f0 . Pi^nabla_1 phi_k.
void cell_body_load(const Mesh& mesh, int c, const VectorField& body_force, const LoadTerms& add);
void cell_body_load(const Mesh3D& mesh, int c, const VectorField3& body_force, const LoadTerms& add);

/// The load of `load` (its traction less its pressure times the outward normal) on boundary
/// facet `id`. InputError for an id out of range, or for a facet that is not on the boundary
/// (in the plane: where the load has a pressure, which needs an outward normal).
void facet_traction_load(const Mesh& mesh, const TractionLoad& load, int id, const LoadTerms& add);
void facet_traction_load(const Mesh3D& mesh, const TractionLoad3D& load, int id, const LoadTerms& add);

}  // namespace hemivem::detail
