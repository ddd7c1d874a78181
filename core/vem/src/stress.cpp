#include <hemivem/vem/stress.hpp>

#include <cmath>

#include <hemivem/error.hpp>
#include <hemivem/vem/element.hpp>

namespace hemivem {

double ElementStress::von_mises() const {
  return std::sqrt(0.5 * ((xx - yy) * (xx - yy) + (yy - zz) * (yy - zz) + (zz - xx) * (zz - xx)) + 3.0 * xy * xy);
}

std::vector<ElementStress> element_stresses(const Mesh& mesh, const MaterialTable& materials, const Eigen::VectorXd& u) {
  if (u.size() != 2 * mesh.num_vertices())
    throw InputError("displacement vector has " + std::to_string(u.size()) + " entries, expected " +
                     std::to_string(2 * mesh.num_vertices()));
  std::vector<ElementStress> out(static_cast<std::size_t>(mesh.num_elements()));
  std::vector<Vec2> poly;
  Eigen::VectorXd local;
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const auto verts = mesh.element(e);
    poly.resize(verts.size());
    local.resize(2 * static_cast<Eigen::Index>(verts.size()));
    for (std::size_t i = 0; i < verts.size(); ++i) {
      poly[i] = mesh.vertex(verts[i]);
      local.segment<2>(2 * static_cast<Eigen::Index>(i)) = u.segment<2>(2 * static_cast<Eigen::Index>(verts[i]));
    }
    // the stress of Pi u_h needs its strain only: the symmetric part of its gradient
    const Eigen::Vector3d eps = projected_strain(poly, local);
    const Lame l = materials.lame(mesh.region(e));  // plane stress: lambda is already lambda*
    const double tr = eps(0) + eps(1);
    ElementStress& s = out[static_cast<std::size_t>(e)];
    s.xx = l.lambda * tr + 2.0 * l.mu * eps(0);
    s.yy = l.lambda * tr + 2.0 * l.mu * eps(1);
    s.xy = l.mu * eps(2);
    s.zz = materials.model() == PlaneModel::strain ? l.lambda * tr : 0.0;
  }
  return out;
}

}  // namespace hemivem
