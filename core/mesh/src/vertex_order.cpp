#include <hemivem/mesh/vertex_order.hpp>

#include "hilbert.hpp"

namespace hemivem {

namespace {

template <class MeshType>
std::vector<int> hilbert_order_of(const MeshType& mesh) {
  if (mesh.num_vertices() == 0) return {};
  const std::vector<std::size_t> perm = detail::hilbert_order(mesh.vertices(), mesh.bounding_box());
  return std::vector<int>(perm.begin(), perm.end());
}

}  // namespace

std::vector<int> hilbert_vertex_order(const Mesh& mesh) { return hilbert_order_of(mesh); }
std::vector<int> hilbert_vertex_order(const Mesh3D& mesh) { return hilbert_order_of(mesh); }

}  // namespace hemivem
