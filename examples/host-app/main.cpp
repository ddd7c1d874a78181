// host-app: a scene file solved, and its results written, by a program of one's own.
//
//   host-app SCENE.toml OUT_DIR
//
// solves the scene with the engines it names and writes into OUT_DIR what `hemivem solve`
// writes (result.json, contact.csv, displacement.csv, ...). Exit status: 0 converged,
// 3 not converged (the results are written and say so), 2 bad input or a failed engine.
#include <hemivem/app/report.hpp>
#include <hemivem/app/solve.hpp>

#include <exception>
#include <iostream>

int main(int argc, char** argv) {
  if (argc != 3) return std::cerr << "usage: host-app SCENE.toml OUT_DIR\n", 2;
  try {
    const hemivem::Scene scene = hemivem::parse_scene(argv[1]);
    const hemivem::app::SceneSolve solved = hemivem::app::solve_scene(scene);
    hemivem::app::write_results(argv[2], scene, solved);
    std::cout << hemivem::app::brief_report(solved) << "\n";
    return solved.solution.converged() ? 0 : 3;
  } catch (const std::exception& e) {
    return std::cerr << "host-app: " << e.what() << "\n", 2;
  }
}
