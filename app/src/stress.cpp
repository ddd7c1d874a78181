// The projected stresses of the cells of a solve and their peak (stress.hpp).
#include <hemivem/app/stress.hpp>

#include <cmath>
#include <string>

#include <hemivem/error.hpp>
#include <hemivem/vem/assembly3d.hpp>
#include <hemivem/vem/element3d.hpp>
#include <hemivem/vem/stress.hpp>

namespace hemivem::app {

template <int dim>
double BasicCellStress<dim>::von_mises() const {
  const double normal = 0.5 * ((xx - yy) * (xx - yy) + (yy - zz) * (yy - zz) + (zz - xx) * (zz - xx));
  if constexpr (dim == 2) return std::sqrt(normal + 3.0 * xy * xy);  // yz = xz = 0
  else return std::sqrt(normal + 3.0 * (yz * yz + xz * xz + xy * xy));
}
template struct BasicCellStress<2>;
template struct BasicCellStress<3>;

std::vector<CellStress> cell_stresses(const Mesh& mesh, const MaterialTable& materials, const Eigen::VectorXd& u) {
  if (u.size() != 2 * static_cast<Eigen::Index>(mesh.num_vertices()))
    throw InputError("a displacement of " + std::to_string(u.size()) + " values for a mesh of " +
                     std::to_string(mesh.num_vertices()) + " vertices (2 per vertex)");
  std::vector<CellStress> out;
  for (const ElementStress& s : element_stresses(mesh, materials, u)) out.push_back({s.xx, s.yy, s.zz, 0.0, 0.0, s.xy});
  return out;
}

std::vector<BasicCellStress<3>> cell_stresses(const Mesh3D& mesh, const MaterialTable& materials,
                                              const Eigen::VectorXd& u) {
  if (u.size() != 3 * static_cast<Eigen::Index>(mesh.num_vertices()))
    throw InputError("a displacement of " + std::to_string(u.size()) + " values for a mesh of " +
                     std::to_string(mesh.num_vertices()) + " vertices (3 per vertex)");
  const std::vector<LinearField3> projected = project_solution(mesh, u);
  std::vector<BasicCellStress<3>> out(static_cast<std::size_t>(mesh.num_cells()));
  for (int c = 0; c < mesh.num_cells(); ++c) {
    const Eigen::Matrix3d sigma = stress_3d(projected[static_cast<std::size_t>(c)].gradient, materials.lame(mesh.region(c)));
    BasicCellStress<3>& s = out[static_cast<std::size_t>(c)];
    s.xx = sigma(0, 0), s.yy = sigma(1, 1), s.zz = sigma(2, 2);
    s.yz = sigma(1, 2), s.xz = sigma(0, 2), s.xy = sigma(0, 1);
  }
  return out;
}

namespace {

template <class MeshType, int dim>
std::optional<StressPeak> peak_of(const MeshType& mesh, const std::vector<BasicCellStress<dim>>& stresses) {
  if (stresses.size() != static_cast<std::size_t>(mesh.num_cells()))
    throw InputError(std::to_string(stresses.size()) + " cell stresses for a mesh of " + std::to_string(mesh.num_cells()) +
                     " cells");
  std::optional<StressPeak> peak;
  for (std::size_t c = 0; c < stresses.size(); ++c) {
    const double vm = stresses[c].von_mises();
    if (!std::isfinite(vm)) return std::nullopt;
    if (peak && !(vm > peak->von_mises)) continue;
    if (!peak) peak.emplace();
    peak->cell = static_cast<int>(c);
    peak->von_mises = vm;
  }
  if (peak) {
    const auto x = mesh.centroid(peak->cell);
    peak->centroid.assign(x.data(), x.data() + dim);
  }
  return peak;
}

}  // namespace

std::optional<StressPeak> stress_peak(const Mesh& mesh, const std::vector<CellStress>& stresses) {
  return peak_of(mesh, stresses);
}

std::optional<StressPeak> stress_peak(const Mesh3D& mesh, const std::vector<BasicCellStress<3>>& stresses) {
  return peak_of(mesh, stresses);
}

}  // namespace hemivem::app
