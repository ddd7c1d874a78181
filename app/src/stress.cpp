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

/// The first cell of the largest von Mises stress among the cells of `mesh` that `owned` flags
/// (all when null), numbered by `cells` (their own numbers when null); `finite` false, and none,
/// when one of them has a von Mises stress that is not finite.
template <class MeshType, int dim>
std::optional<StressPeak> peak_of(const MeshType& mesh, const std::vector<BasicCellStress<dim>>& stresses,
                                  const std::vector<char>* owned, const std::vector<int>* cells, bool& finite) {
  if (stresses.size() != static_cast<std::size_t>(mesh.num_cells()))
    throw InputError(std::to_string(stresses.size()) + " cell stresses for a mesh of " + std::to_string(mesh.num_cells()) +
                     " cells");
  finite = true;
  std::optional<StressPeak> peak;
  int at = -1;
  for (std::size_t c = 0; c < stresses.size(); ++c) {
    if (owned && !(*owned)[c]) continue;
    const double vm = stresses[c].von_mises();
    if (!std::isfinite(vm)) {
      finite = false;
      return std::nullopt;
    }
    if (peak && !(vm > peak->von_mises)) continue;
    if (!peak) peak.emplace();
    at = static_cast<int>(c);
    peak->cell = cells ? (*cells)[c] : at;
    peak->von_mises = vm;
  }
  if (peak) {
    const auto x = mesh.centroid(at);
    peak->centroid.assign(x.data(), x.data() + dim);
  }
  return peak;
}

template <class MeshType, int dim>
std::optional<StressPeak> peak_of_pieces(const MeshType& mesh, const std::vector<BasicCellStress<dim>>& stresses,
                                         const std::vector<char>& owned, const std::vector<int>& cells,
                                         const RowDistribution& rows) {
  if (owned.size() != stresses.size() || cells.size() != stresses.size())
    throw InternalError(std::to_string(owned.size()) + " flags and " + std::to_string(cells.size()) +
                        " numbers for a piece of " + std::to_string(stresses.size()) + " cells");
  // each process's peak among its cells as [not finite, has one, von Mises, cell, centroid]
  bool finite = true;
  const std::optional<StressPeak> mine = peak_of(mesh, stresses, &owned, &cells, finite);
  constexpr Eigen::Index width = 4 + dim;
  Eigen::VectorXd sent = Eigen::VectorXd::Zero(width);
  sent(0) = finite ? 0.0 : 1.0;
  if (mine) {
    sent(1) = 1.0;
    sent(2) = mine->von_mises;
    sent(3) = mine->cell;
    for (int i = 0; i < dim; ++i) sent(4 + i) = mine->centroid[static_cast<std::size_t>(i)];
  }
  const Eigen::VectorXd all = rows.all_gather(sent);
  if (all.size() != width * rows.size()) throw InternalError("the processes' stress peaks differ in length");
  std::optional<StressPeak> peak;
  for (Eigen::Index at = 0; at < all.size(); at += width) {
    if (all(at) != 0.0) return std::nullopt;
    if (all(at + 1) == 0.0) continue;
    const double vm = all(at + 2);
    const int cell = static_cast<int>(all(at + 3));
    // the first cell, in the whole mesh's order, of the largest
    if (peak && (vm < peak->von_mises || (vm == peak->von_mises && cell > peak->cell))) continue;
    if (!peak) peak.emplace();
    peak->cell = cell;
    peak->von_mises = vm;
    peak->centroid.assign(all.data() + at + 4, all.data() + at + width);
  }
  return peak;
}

}  // namespace

std::optional<StressPeak> stress_peak(const Mesh& mesh, const std::vector<CellStress>& stresses) {
  bool finite = true;
  return peak_of(mesh, stresses, nullptr, nullptr, finite);
}

std::optional<StressPeak> stress_peak(const Mesh3D& mesh, const std::vector<BasicCellStress<3>>& stresses) {
  bool finite = true;
  return peak_of(mesh, stresses, nullptr, nullptr, finite);
}

std::optional<StressPeak> stress_peak_of_pieces(const Mesh& mesh, const std::vector<CellStress>& stresses,
                                                const std::vector<char>& owned, const std::vector<int>& cells,
                                                const RowDistribution& rows) {
  return peak_of_pieces(mesh, stresses, owned, cells, rows);
}

std::optional<StressPeak> stress_peak_of_pieces(const Mesh3D& mesh, const std::vector<BasicCellStress<3>>& stresses,
                                                const std::vector<char>& owned, const std::vector<int>& cells,
                                                const RowDistribution& rows) {
  return peak_of_pieces(mesh, stresses, owned, cells, rows);
}

}  // namespace hemivem::app
