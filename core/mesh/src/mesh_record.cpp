#include <hemivem/mesh/mesh_record.hpp>

#include <algorithm>
#include <utility>

namespace hemivem {

namespace {

template <class Loops>
void append_loop(const Loops& loop, std::vector<int>& start, std::vector<int>& loops) {
  loops.insert(loops.end(), loop.begin(), loop.end());
  start.push_back(static_cast<int>(loops.size()));
}

std::vector<int> loop_at(const std::vector<int>& start, const std::vector<int>& loops, std::size_t k) {
  return {loops.begin() + start[k], loops.begin() + start[k + 1]};
}

}  // namespace

template <int dim>
MeshRecord<dim>::MeshRecord(const MeshOf<dim>& mesh)
    : vertices_(mesh.vertices().begin(), mesh.vertices().end()), loop_start_{0}, regions_(mesh.regions()) {
  if constexpr (dim == 2) {
    for (int e = 0; e < mesh.num_elements(); ++e) append_loop(mesh.element(e), loop_start_, loops_);
    groups_ = mesh.edge_groups();
  } else {
    for (const MeshFace& f : mesh.faces()) append_loop(f.vertices, loop_start_, loops_);
    cell_start_.push_back(0);
    for (int c = 0; c < mesh.num_cells(); ++c) append_loop(mesh.cell_faces(c), cell_start_, cell_faces_);
    groups_ = mesh.face_groups();
  }
}

template <int dim>
MeshOf<dim> MeshRecord<dim>::make() const {
  const auto cells = (dim == 2 ? loop_start_.size() : cell_start_.size()) - 1;
  if constexpr (dim == 2) {
    std::vector<std::vector<int>> elements(cells);
    for (std::size_t e = 0; e < cells; ++e) elements[e] = loop_at(loop_start_, loops_, e);
    Mesh mesh(vertices_, std::move(elements), regions_);
    for (const auto& [name, edges] : groups_) mesh.set_edge_group(name, edges);
    return mesh;
  } else {
    // each face's loop as its first cell (which stores it) gives it, reversed for the other
    std::vector<char> given(loop_start_.size() - 1, 0);
    std::vector<CellFaces> faces(cells);
    for (std::size_t c = 0; c < cells; ++c)
      for (int k = cell_start_[c]; k < cell_start_[c + 1]; ++k) {
        const auto f = static_cast<std::size_t>(cell_faces_[static_cast<std::size_t>(k)]);
        std::vector<int> loop = loop_at(loop_start_, loops_, f);
        if (given[f]) std::reverse(loop.begin(), loop.end());
        given[f] = 1;
        faces[c].push_back(std::move(loop));
      }
    Mesh3D mesh(vertices_, std::move(faces), regions_);
    for (const auto& [name, group] : groups_) mesh.set_face_group(name, group);
    return mesh;
  }
}

template class MeshRecord<2>;
template class MeshRecord<3>;

}  // namespace hemivem
