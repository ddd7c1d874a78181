#include <hemivem/vem/stress.hpp>

#include <cmath>

#include <hemivem/vem/element.hpp>

#include "cell_values.hpp"

namespace hemivem {

double ElementStress::von_mises() const {
  return std::sqrt(0.5 * ((xx - yy) * (xx - yy) + (yy - zz) * (yy - zz) + (zz - xx) * (zz - xx)) + 3.0 * xy * xy);
}

std::vector<ElementStress> element_stresses(const Mesh& mesh, const MaterialTable& materials, const Eigen::VectorXd& u) {
  std::vector<ElementStress> out(static_cast<std::size_t>(mesh.num_elements()));
  detail::for_each_cell_values(mesh, u, [&](int e, const std::vector<Vec2>& polygon, const Eigen::VectorXd& local) {
    // the stress of Pi u_h needs its strain only: the symmetric part of its gradient
    const Eigen::Vector3d eps = projected_strain(polygon, local);
    const Lame l = materials.lame(mesh.region(e));  // plane stress: lambda is already lambda*
    const double tr = eps(0) + eps(1);
    ElementStress& s = out[static_cast<std::size_t>(e)];
    s.xx = l.lambda * tr + 2.0 * l.mu * eps(0);
    s.yy = l.lambda * tr + 2.0 * l.mu * eps(1);
    s.xy = l.mu * eps(2);
    s.zz = materials.model() == PlaneModel::strain ? l.lambda * tr : 0.0;
  });
  return out;
}

}  // namespace hemivem
