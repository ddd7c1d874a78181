// The delamination benchmark loaded from zero along a path, checked against the global search
// (docs/nonconvex.md, "Loaded from zero"): one check for the layer on a rigid foundation and for
// the layer bonded to a second body.
#pragma once

#include <hemivem/app/run.hpp>
#include <hemivem/scene/scene.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <iostream>
#include <string>
#include <vector>

namespace hemivem::test {

/// The nodes debonded: separated by more than 2 mm.
inline int debonded(const std::vector<ContactNode>& contact) {
  return static_cast<int>(
      std::count_if(contact.begin(), contact.end(), [](const ContactNode& n) { return n.u_nu <= -2e-3; }));
}

/// The path of `scene_at(30)` loaded from 0 to 30 MPa in 300 steps: every step converges (and
/// passes `each_step`), the debonded nodes never become fewer and some debond, the path jumps
/// at least twice, and at 20, 26 and 30 MPa no step lies below the lowest critical point the
/// global search finds at its load (32 starts; the tie 1e-9 |energy|), and at 30 MPa, past the
/// end of the bonded branch, the path is that point (the same energy within the tie, the same
/// debonded nodes).
inline void expect_delamination_path_above_the_global_search(const std::function<Scene(double)>& scene_at,
                                                             const std::function<void(const PathStep&)>& each_step = {}) {
  Scene scene = scene_at(30.0);
  apply_override(scene, "solver.search=\"local\"");
  apply_override(scene, "path.steps=300");
  apply_override(scene, "path.frames=1");
  const app::SceneSolve solved = app::solve_scene_path(scene);
  ASSERT_TRUE(solved.path);
  const PathSolution& path = *solved.path;
  ASSERT_EQ(path.steps.size(), 300u);
  int before = 0, jumps = 0;
  for (const PathStep& s : path.steps) {
    SCOPED_TRACE("load " + std::to_string(30.0 * s.t) + " MPa");
    ASSERT_TRUE(s.converged()) << s.message;
    if (each_step) each_step(s);
    const int now = debonded(s.contact);
    EXPECT_GE(now, before);
    before = now;
    jumps += s.jump;
  }
  EXPECT_GT(before, 0) << "the path debonds before 30 MPa";
  EXPECT_GE(jumps, 2);  // the first drop of the law (0.5 mm), then debonding
  for (const int step : {200, 260, 300}) {  // 20, 26 and 30 MPa
    const PathStep& s = path.steps[static_cast<std::size_t>(step - 1)];
    const double mpa = 30.0 * s.t;
    SCOPED_TRACE("load " + std::to_string(mpa) + " MPa");
    Scene global = scene_at(mpa);
    apply_override(global, "solver.search=\"global\"");
    apply_override(global, "solver.max_starts=32");
    apply_override(global, "solver.search_engines=[\"bundle-dca\", \"ceres-active-set\"]");
    const app::SceneSolve g = app::solve_scene(global);
    ASSERT_TRUE(g.solution.converged()) << g.solution.message;
    const double tie = 1e-9 * std::abs(g.solution.energy);
    EXPECT_GE(s.energy, g.solution.energy - tie);
    if (step == 300) {
      EXPECT_LE(s.energy, g.solution.energy + tie);
      EXPECT_EQ(debonded(s.contact), debonded(g.solution.contact));
    }
    std::cout << mpa << " MPa: path " << s.energy << " J/m (" << debonded(s.contact) << " debonded), lowest found "
              << g.solution.energy << " J/m (" << debonded(g.solution.contact) << " debonded), path - lowest "
              << s.energy - g.solution.energy << " J/m\n";
  }
}

}  // namespace hemivem::test
