// host-app: a scene file solved, and its results written, by a program of one's own.
//
//   host-app SCENE.toml OUT_DIR
//
// solves the scene (plane or solid; one static solve, a loading path or an adaptive sequence)
// with the engines it names and writes into OUT_DIR what `hemivem solve`
// writes (result.json, contact.csv, displacement.csv, ...). Exit status: 0 converged,
// 3 not converged (the results are written and say so), 2 bad input or a failed engine.
#include <hemivem/app/run.hpp>

#include <exception>
#include <iostream>

int main(int argc, char** argv) {
  if (argc != 3) return std::cerr << "usage: host-app SCENE.toml OUT_DIR\n", 2;
  try {
    const hemivem::Scene scene = hemivem::parse_scene(argv[1]);
    const hemivem::app::SceneRun run = hemivem::app::run_scene(scene);
    run.write(argv[2]);
    std::cout << run.brief() << "\n";
    return run.converged() ? 0 : 3;
  } catch (const std::exception& e) {
    return std::cerr << "host-app: " << e.what() << "\n", 2;
  }
}
