// Example 4.1 on N x N squares for the benchmarks: assembled, with its contact boundary,
// built once per N and kept for the rest of the run.
#pragma once

#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/problem.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/scene/example.hpp>

#include <map>
#include <memory>

namespace hemivem::bench {

struct Example41 {
  Mesh mesh;
  ContactProblem problem;
  LinearSystem system;
  ContactBoundary boundary;
};

inline const Example41& example_4_1_on_squares(int n) {
  static std::map<int, std::unique_ptr<Example41>> cache;
  auto& s = cache[n];
  if (!s) {
    s = std::make_unique<Example41>();
    s->mesh = make_squares(n);
    s->problem = example_4_1(s->mesh);
    s->system = assemble(s->problem.elasticity);
    s->boundary = make_contact_boundary(s->mesh, s->problem.parts[0].facets, s->system.dofs, s->problem.parts[0].gap);
  }
  return *s;
}

}  // namespace hemivem::bench
