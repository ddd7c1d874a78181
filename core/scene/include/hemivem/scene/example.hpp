// The paper's Example 4.1 as a contact problem on a mesh of one's own.
#pragma once

#include <hemivem/contact/problem.hpp>
#include <hemivem/mesh/mesh.hpp>

namespace hemivem {

/// Example 4.1 of the paper on a mesh of the unit square, built from the default scene
/// (scenes/paper-example-4.1.toml, see scene/scene.hpp): Gamma_1 = {x = 0} u {x = 1} (clamped),
/// Gamma_2 = top with f2 = (0, -8), Gamma_3 = bottom; E = 65, nu = 0.29 (plane strain),
/// f0 = 0, g = 0.02, the law (4.7) with split (4.8), the box constraint (4.6). Sides of the
/// mesh's bounding box are found with a tolerance of 1e-8 (Sutton's meshes miss them by up
/// to 5e-10).
ContactProblem example_4_1(const Mesh& mesh);

}  // namespace hemivem
