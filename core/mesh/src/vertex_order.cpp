#include <hemivem/mesh/vertex_order.hpp>

#include "hilbert.hpp"

#include <hemivem/error.hpp>

#include <string>

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

std::vector<char> VertexShare::mask(int num_vertices) const {
  const int size = order.empty() ? num_vertices : static_cast<int>(order.size());
  if (first < 0 || end < first || end > size || (!order.empty() && size != num_vertices))
    throw InputError(text() + " are not a share of a mesh of " + std::to_string(num_vertices) + " vertices" +
                     (order.empty() ? "" : " (an order of " + std::to_string(order.size()) + ")"));
  std::vector<char> out(static_cast<std::size_t>(num_vertices), 0);
  for (int k = first; k < end; ++k) {
    const int v = order.empty() ? k : order[static_cast<std::size_t>(k)];
    if (v < 0 || v >= num_vertices) throw InputError(text() + " name the vertex " + std::to_string(v) + ", not one of the mesh's");
    out[static_cast<std::size_t>(v)] = 1;
  }
  return out;
}

std::string VertexShare::text() const {
  return (order.empty() ? "the vertices " : "the vertices at ") + std::to_string(first) + " to " +
         std::to_string(end - 1) + (order.empty() ? "" : " of the shared order");
}

}  // namespace hemivem
