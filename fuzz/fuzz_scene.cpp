// libFuzzer target: any bytes as a scene (TOML). A scene that parses is also built
// (mesh, materials, boundary parts, loads, contact data) when that is cheap: a generated mesh
// of at most 8 x 8 cells (with mesh.n = [nx, ny], both at most 8); scenes naming a mesh file
// are only parsed (the fuzzer must not read arbitrary files: parsing looks at the headers of an
// existing regular .msh file alone, to tell a solid's mesh). A three-dimensional scene of at
// most 8 x 8 x 8 cells is built by build_problem<3>. A defect must be an InputError; every other exception, a crash, a hang or
// undefined behaviour is a finding.
#include <hemivem/error.hpp>
#include <hemivem/scene/scene.hpp>

#include <cstddef>
#include <cstdint>
#include <string_view>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string_view text(reinterpret_cast<const char*>(data), size);
  try {
    const hemivem::Scene scene = hemivem::parse_scene_string(text, "fuzz.toml");
    (void)hemivem::to_toml(scene);
    const bool small = scene.mesh.n <= 8 && scene.mesh.ny.value_or(scene.mesh.n) <= 8 &&
                       scene.mesh.nz.value_or(scene.mesh.n) <= 8;  // every side bounded
    if (scene.mesh.file.empty() && small) {
      if (scene.dimension() == 3) (void)hemivem::build_problem<3>(scene);
      else (void)hemivem::build_problem(scene);
    }
  } catch (const hemivem::InputError&) {
  }
  return 0;
}
