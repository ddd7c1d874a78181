// The three-dimensional Hertz problem on graded meshes (docs/three-dimensions.md): a plain
// program printing a Markdown table of the contact radius, the peak pressure and the force
// against Hertz's formulas as the mesh near the contact is refined. Usage: hertz3d [levels [L
// [profile.csv]]] (L: the block's size, 1 by default: 20 contact radii; profile.csv: r, p and
// Hertz's p of every contact node of the finest level).
#include "hertz3d.hpp"

#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>

using namespace hemivem;

int main(int argc, char** argv) {
  const int levels = argc > 1 ? std::atoi(argv[1]) : 4;
  hertz3d::Setup s;
  if (argc > 2) s.size = std::atof(argv[2]);
  std::printf("Hertz: a = %.5g, p0 = %.5g, P = %.5g (E = %g, nu = %g, R = %g, d = %g, block %g)\n\n", s.a(), s.p0(),
              s.force(), s.young, s.poisson, s.radius, s.indentation, s.size);
  std::printf("| h/a | cells | dofs | nodes in the disk (whole disk) | a_h/a - 1 | p0_h/p0 - 1 | P_h/P - 1 | certificate | seconds (assembly, condensation, minimize) |\n");
  std::printf("|---|---|---|---|---|---|---|---|---|\n");
  const double ratios[] = {1.0 / 4, 1.0 / 6, 1.0 / 8, 1.0 / 12, 1.0 / 16};
  for (int l = 0; l < levels && l < 5; ++l) {
    s.h_over_a = ratios[l];
    const auto t0 = std::chrono::steady_clock::now();
    const Mesh3D m = hertz3d::mesh(s);
    const ContactProblem3D p = hertz3d::problem(s, m);
    FactorizationOptions o;
    o.engine = "cholmod";
    const ContactSolution3D sol = solve_contact(p, make_factorization(o), *make_minimizer("ssn"), MinimizerOptions{});
    const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const hertz3d::Measured r = hertz3d::measure(s, sol);
    std::printf("| 1/%.0f | %d | %d | %d (%d) | %+.2e | %+.2e | %+.2e | %s | %.1f (%.1f, %.1f, %.2f) |\n", 1.0 / s.h_over_a, m.num_cells(),
                sol.unknowns, r.nodes_in_disk, r.full_disk, r.a / s.a() - 1.0, r.p0 / s.p0() - 1.0, r.force / s.force() - 1.0,
                sol.converged() ? "converged" : "FAILED", seconds, sol.timings.at("assembly"),
                sol.timings.at("condensation"), sol.timings.at("minimize"));
    std::fflush(stdout);
    if (argc > 3 && l + 1 == std::min(levels, 5)) {
      std::ofstream csv(argv[3]);
      csv << "r,p,p_hertz\n";
      for (const ContactNode3D& n : sol.contact) {
        const double r = n.x.head<2>().norm();
        const double q = r < s.a() ? s.p0() * std::sqrt(1.0 - r * r / (s.a() * s.a())) : 0.0;
        if (r < 2.0 * s.a()) csv << r << "," << n.pressure() << "," << q << "\n";
      }
    }
  }
  return 0;
}
