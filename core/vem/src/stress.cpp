#include <hemivem/vem/stress.hpp>

#include <cmath>

#include <hemivem/vem/assembly.hpp>

namespace hemivem {

double ElementStress::von_mises() const {
  return std::sqrt(0.5 * ((xx - yy) * (xx - yy) + (yy - zz) * (yy - zz) + (zz - xx) * (zz - xx)) + 3.0 * xy * xy);
}

std::vector<ElementStress> element_stresses(const Mesh& mesh, const MaterialTable& materials, const Eigen::VectorXd& u) {
  const std::vector<LinearField> fields = project_solution(mesh, u);
  std::vector<ElementStress> out(fields.size());
  for (int e = 0; e < mesh.num_elements(); ++e) {
    const Eigen::Matrix2d& g = fields[static_cast<std::size_t>(e)].gradient;
    const Eigen::Matrix2d eps = 0.5 * (g + g.transpose());
    const Lame l = materials.lame(mesh.region(e));  // plane stress: lambda is already lambda*
    const double tr = eps.trace();
    ElementStress& s = out[static_cast<std::size_t>(e)];
    s.xx = l.lambda * tr + 2.0 * l.mu * eps(0, 0);
    s.yy = l.lambda * tr + 2.0 * l.mu * eps(1, 1);
    s.xy = 2.0 * l.mu * eps(0, 1);
    s.zz = materials.model() == PlaneModel::strain ? l.lambda * tr : 0.0;
  }
  return out;
}

}  // namespace hemivem
