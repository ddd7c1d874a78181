// libFuzzer target: any bytes as a .poly2d file. A defect must be an InputError (or a
// MeshError); every other exception, a crash, a hang or undefined behaviour is a finding.
#include <hemivem/error.hpp>
#include <hemivem/mesh/poly2d.hpp>

#include <cstddef>
#include <cstdint>
#include <sstream>
#include <string>

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  std::istringstream in(std::string(reinterpret_cast<const char*>(data), size));
  try {
    const hemivem::Poly2dMesh m = hemivem::read_poly2d(in, "fuzz.poly2d");
    (void)m.mesh.num_elements();
  } catch (const hemivem::InputError&) {
  }
  return 0;
}
