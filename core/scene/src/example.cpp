#include <hemivem/scene/example.hpp>
#include <hemivem/scene/scene.hpp>

namespace hemivem {

ContactProblem example_4_1(const Mesh& mesh) { return make_contact_problem(default_scene(), mesh); }

}  // namespace hemivem
