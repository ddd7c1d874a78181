// libFuzzer target: any bytes as a Gmsh .msh file. A defect must be an InputError (or a
// MeshError); every other exception, a crash, a hang or undefined behaviour is a finding.
#include <hemivem/error.hpp>
#include <hemivem/mesh/gmsh.hpp>

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const hemivem::Mesh m = hemivem::read_gmsh(in, "fuzz.msh");
    (void)m.num_elements();
  } catch (const hemivem::InputError&) {
  }
  return 0;
}
