// Two deformable bodies stacked along the last axis and joined at their contact
// (docs/two-bodies.md), as a scene's text: the tests of the full-space route in one process,
// across processes and from the command share it.
#pragma once

#include <string>

namespace hemivem::test {

/// What differs between the stacked bodies of the tests.
struct StackedBodies {
  int dim = 3;
  std::string n;             ///< each body's cells, e.g. "[4, 4, 3]" (matched along the interface)
  std::string top;           ///< the upper body's top displacement, e.g. "[0.004, 0.002, -0.01]"
  std::string supports;      ///< the lower body's further supports, inline tables each after ", "
  std::string contact;       ///< the interface's further keys (lines), e.g. a friction law
};

/// "upper" on [0, 1]^(dim-1) x [0.5, 1] (E 10, nu 0.3) with its top moved by `top`, "lower" on
/// [0, 1]^(dim-1) x [0, 0.5] (E 4, nu 0.1) clamped at its bottom, in squares or cubes; the
/// upper's bottom against the lower's top, one-sided, of the zero law. The upper's vertices come
/// first, its contact layer at their start.
inline std::string stacked_bodies(const StackedBodies& b) {
  const bool plane = b.dim == 2;
  const std::string generator = plane ? "squares" : "cubes";
  const auto body = [&](const std::string& name, const std::string& domain, const std::string& material,
                        const std::string& dirichlet) {
    return "[[body]]\nname = \"" + name + "\"\nmesh = {generator = \"" + generator + "\", n = " + b.n +
           ", domain = " + domain + "}\nmaterial = " + material + "\ndirichlet = [" + dirichlet + "]\n";
  };
  return "schema_version = 1\n" +
         body("upper", plane ? "[0.0, 1.0, 0.5, 1.0]" : "[0.0, 1.0, 0.0, 1.0, 0.5, 1.0]", "{E = 10.0, nu = 0.3}",
              "{side = \"top\", value = " + b.top + "}") +
         body("lower", plane ? "[0.0, 1.0, 0.0, 0.5]" : "[0.0, 1.0, 0.0, 1.0, 0.0, 0.5]", "{E = 4.0, nu = 0.1}",
              std::string("{side = \"bottom\", value = ") + (plane ? "[0.0, 0.0]" : "[0.0, 0.0, 0.0]") + "}" +
                  b.supports) +
         "[[contact]]\nname = \"interface\"\nside = \"upper.bottom\"\nagainst = \"lower.top\"\nlaw = \"zero\"\n"
         "constraint = \"one-sided\"\n" +
         b.contact;
}

}  // namespace hemivem::test
