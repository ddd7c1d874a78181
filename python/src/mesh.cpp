// hemivem.Mesh: generators, readers, NumPy arrays of a mesh and a mesh from arrays.
#include "bindings.hpp"

#include <pybind11/stl.h>

#include <algorithm>
#include <pybind11/stl/filesystem.h>

#include <cmath>
#include <filesystem>
#include <optional>
#include <sstream>

#include <hemivem/error.hpp>
#include <hemivem/mesh/generators3d.hpp>
#include <hemivem/mesh/gmsh.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/mesh/poly2d.hpp>

namespace hemivem::python {

namespace {

PyMesh own(Mesh mesh) { return PyMesh{std::make_shared<const Mesh>(std::move(mesh))}; }

/// The vertices of a mesh built from arrays: an (n, 2) array of finite numbers.
std::vector<Vec2> vertices_from(const py::handle& values) {
  const auto a = py::array_t<double, py::array::c_style | py::array::forcecast>::ensure(values);
  if (!a || a.ndim() != 2 || a.shape(1) != 2)
    throw InputError("expected an (n, 2) array of coordinates", "vertices");
  std::vector<Vec2> v(static_cast<std::size_t>(a.shape(0)));
  for (py::ssize_t i = 0; i < a.shape(0); ++i) {
    v[static_cast<std::size_t>(i)] = Vec2(a.at(i, 0), a.at(i, 1));
    for (int k = 0; k < 2; ++k)
      if (!std::isfinite(a.at(i, k)))
        throw InputError("vertices[" + std::to_string(i) + ", " + std::to_string(k) + "] = " +
                             std::to_string(a.at(i, k)) + " is not finite",
                         "vertices");
  }
  return v;
}

std::vector<int> ints_from(const py::handle& values, const std::string& what) {
  const py::array a = py::array::ensure(values);
  if (!a || a.ndim() != 1) throw InputError("expected a 1-D array of integers", what);
  if (a.size() > 0 && !py::isinstance<py::array_t<std::int64_t>>(a) && !py::isinstance<py::array_t<std::int32_t>>(a) &&
      !(a.dtype().kind() == 'i' || a.dtype().kind() == 'u'))
    throw InputError("expected integers, got dtype " + py::str(a.dtype()).cast<std::string>(), what);
  const auto b = py::array_t<std::int64_t, py::array::c_style | py::array::forcecast>::ensure(a);
  std::vector<int> out(static_cast<std::size_t>(b.shape(0)));
  for (py::ssize_t i = 0; i < b.shape(0); ++i) {
    const std::int64_t x = b.at(i);
    if (x < std::numeric_limits<int>::min() || x > std::numeric_limits<int>::max())
      throw InputError(what + "[" + std::to_string(i) + "] = " + std::to_string(x) + " is out of range", what);
    out[static_cast<std::size_t>(i)] = static_cast<int>(x);
  }
  return out;
}

/// Elements from CSR offsets and indices (offsets[0] = 0, non-decreasing, last = len(indices)).
std::vector<std::vector<int>> elements_from(const std::vector<int>& offsets, const std::vector<int>& indices) {
  if (offsets.empty() || offsets.front() != 0)
    throw InputError("offsets must start with 0 (one more entry than elements)", "offsets");
  std::vector<std::vector<int>> elements;
  for (std::size_t e = 0; e + 1 < offsets.size(); ++e) {
    if (offsets[e + 1] < offsets[e])
      throw InputError("offsets must not decrease, but offsets[" + std::to_string(e + 1) + "] = " +
                           std::to_string(offsets[e + 1]) + " < offsets[" + std::to_string(e) + "] = " +
                           std::to_string(offsets[e]),
                       "offsets");
    if (offsets[e + 1] > static_cast<int>(indices.size()))
      throw InputError("offsets[" + std::to_string(e + 1) + "] = " + std::to_string(offsets[e + 1]) +
                           " is beyond the " + std::to_string(indices.size()) + " indices",
                       "offsets");
    elements.emplace_back(indices.begin() + offsets[e], indices.begin() + offsets[e + 1]);
  }
  if (offsets.back() != static_cast<int>(indices.size()))
    throw InputError("the last offset is " + std::to_string(offsets.back()) + ", but there are " +
                         std::to_string(indices.size()) + " indices",
                     "offsets");
  return elements;
}

Rectangle rectangle_from(const std::optional<std::array<double, 4>>& d) {
  if (!d) return Rectangle{};
  return Rectangle{(*d)[0], (*d)[1], (*d)[2], (*d)[3]};
}

const Mesh& get(const PyMesh& m) { return *m.mesh; }

/// A mesh from arrays; a MeshError names the offending element in its where.
PyMesh mesh_from_arrays(py::handle vertices, py::handle offsets, py::handle indices, const py::object& regions) {
  std::vector<int> r;
  if (!regions.is_none()) r = ints_from(regions, "regions");
  auto v = vertices_from(vertices);
  auto elements = elements_from(ints_from(offsets, "offsets"), ints_from(indices, "indices"));
  try {
    return own(Mesh(std::move(v), std::move(elements), std::move(r)));
  } catch (const MeshError& e) {
    if (!e.where().empty()) throw;
    throw MeshError(e.detail(), e.element(), e.element() >= 0 ? "element " + std::to_string(e.element()) : "Mesh");
  }
}

/// Refuses to write a mesh's regions or edge groups where the .poly2d format has no place for them.
void require_nothing_dropped(const Mesh& mesh, bool drop) {
  if (drop) return;
  const bool regions = std::any_of(mesh.regions().begin(), mesh.regions().end(), [](int r) { return r != 0; });
  std::string groups;
  for (const auto& [name, edges] : mesh.edge_groups()) groups += (groups.empty() ? "" : ", ") + name;
  if (!regions && groups.empty()) return;
  throw InputError(std::string("the .poly2d format holds no ") + (regions ? "region ids" : "") +
                       (regions && !groups.empty() ? " and no " : "") +
                       (groups.empty() ? "" : "edge groups (this mesh has: " + groups + ")") +
                       "; pass drop=True to write the mesh without them",
                   "write_poly2d");
}

using MeshClass = py::class_<PyMesh>;

/// Mesh.from_arrays (and the constructor), Mesh.generate, Mesh.read and write_poly2d.
void def_mesh_sources(MeshClass& c) {
  c.def(py::init([](py::handle vertices, py::handle offsets, py::handle indices, py::object regions) {
          return mesh_from_arrays(vertices, offsets, indices, regions);
        }),
        py::arg("vertices"), py::arg("offsets"), py::arg("indices"), py::arg("regions") = py::none(),
        "The same as Mesh.from_arrays.")
      .def_static(
          "from_arrays",
          [](py::handle vertices, py::handle offsets, py::handle indices, py::object regions) {
            return mesh_from_arrays(vertices, offsets, indices, regions);
          },
          py::arg("vertices"), py::arg("offsets"), py::arg("indices"), py::arg("regions") = py::none(),
          "A mesh from arrays: vertices (n, 2), elements as CSR offsets and indices (0-based,\n"
          "counter-clockwise), optional region id per element. Checked as every mesh is:\n"
          "InputError for a non-finite coordinate or inconsistent offsets, MeshError naming the\n"
          "first defective element.")
      .def_static(
          "generate",
          [](const std::string& generator, int n, std::optional<int> ny, std::optional<std::array<double, 4>> domain,
             std::optional<std::vector<std::array<double, 2>>> polygon, std::int64_t seed) {
            if (seed < 0) throw InputError("the seed must be >= 0, got " + std::to_string(seed), "seed");
            if (polygon) {
              if (ny || domain) throw InputError("give either a polygon or a rectangle (domain, ny), not both", "polygon");
              PolygonDomain p;
              for (const auto& c : *polygon) p.corners.emplace_back(c[0], c[1]);
              return own(make_mesh(generator, n, p, static_cast<std::uint64_t>(seed)));
            }
            const GridSize cells = ny ? GridSize(n, *ny) : GridSize(n);
            return own(make_mesh(generator, cells, rectangle_from(domain), static_cast<std::uint64_t>(seed)));
          },
          py::arg("generator"), py::arg("n"), py::kw_only(), py::arg("ny") = py::none(), py::arg("domain") = py::none(),
          py::arg("polygon") = py::none(), py::arg("seed") = 1,
          "A generated mesh: generator is one of mesh_generators() (squares, triangles, voronoi,\n"
          "nonconvex, distorted); n cells per side (ny: cells along y); domain = (x0, x1, y0, y1)\n"
          "(default the unit square) or, for triangles and voronoi, polygon = [[x, y], ...].\n"
          "Deterministic for a given seed.")
      .def_static(
          "read",
          [](const std::filesystem::path& path) {
            const std::string ext = path.extension().string();
            if (ext == ".msh") return own(read_gmsh(path));
            if (ext == ".poly2d") return own(read_poly2d(path).mesh);
            throw InputError("unknown mesh file type '" + ext + "'; expected .poly2d or .msh", path.string());
          },
          py::arg("path"),
          "Reads a .poly2d or Gmsh 4.1 .msh file; InputError (MeshError) naming file:line.")
      .def(
          "write_poly2d",
          [](const PyMesh& self, const std::filesystem::path& path, const std::vector<std::string>& comments, bool drop) {
            require_nothing_dropped(get(self), drop);
            write_poly2d(path, get(self), comments);
          },
          py::arg("path"), py::arg("comments") = std::vector<std::string>{}, py::kw_only(), py::arg("drop") = false,
          "Writes the mesh as .poly2d (17 significant digits: an exact round trip of the vertices and\n"
          "elements). The format holds no region ids and no edge groups: a mesh with either is refused\n"
          "(InputError) unless drop=True, which writes it without them.");
}

/// Sizes, vertices and elements (CSR offsets and indices, lists).
void def_mesh_elements(MeshClass& c) {
  c.def_property_readonly("num_vertices", [](const PyMesh& s) { return get(s).num_vertices(); })
      .def_property_readonly("num_elements", [](const PyMesh& s) { return get(s).num_elements(); })
      .def_property_readonly("num_edges", [](const PyMesh& s) { return get(s).num_edges(); })
      .def_property_readonly(
          "vertices",
          [](py::object self) {
            const Mesh& mesh = get(self.cast<const PyMesh&>());
            return view(mesh.vertices().empty() ? nullptr : mesh.vertices().front().data(), mesh.num_vertices(), 2, self);
          },
          "(num_vertices, 2) float64, C order, read-only view of the mesh's coordinates.")
      .def_property_readonly(
          "offsets",
          [](const PyMesh& s) {
            const Mesh& mesh = get(s);
            py::array_t<std::int32_t> a(mesh.num_elements() + 1);
            auto* p = a.mutable_data();
            p[0] = 0;
            for (int e = 0; e < mesh.num_elements(); ++e) p[e + 1] = p[e] + mesh.element_size(e);
            return a;
          },
          "CSR offsets of the elements (int32, num_elements + 1): element e is\n"
          "indices[offsets[e]:offsets[e + 1]].")
      .def_property_readonly(
          "indices",
          [](const PyMesh& s) {
            const Mesh& mesh = get(s);
            std::vector<std::int32_t> v;
            for (int e = 0; e < mesh.num_elements(); ++e)
              for (int i : mesh.element(e)) v.push_back(i);
            return copy(v);
          },
          "CSR vertex indices of the elements (int32), counter-clockwise per element.")
      .def_property_readonly(
          "elements", [](const PyMesh& s) { return get(s).elements(); },
          "The elements as a list of lists of vertex indices.")
      .def(
          "element", [](const PyMesh& s, int e) {
            const Mesh& mesh = get(s);
            if (e < 0 || e >= mesh.num_elements())
              throw py::index_error("element " + std::to_string(e) + " out of range [0, " +
                                    std::to_string(mesh.num_elements()) + ")");
            const auto span = mesh.element(e);
            return copy(std::vector<std::int32_t>(span.begin(), span.end()));
          },
          py::arg("e"), "The vertex indices of element e (int32).");
}

/// Edges, the elements beside them, and the boundary.
void def_mesh_edges(MeshClass& c) {
  c.def_property_readonly(
       "edges",
       [](const PyMesh& s) {
         const Mesh& mesh = get(s);
         py::array_t<std::int32_t> a({mesh.num_edges(), 2});
         auto r = a.mutable_unchecked<2>();
         for (int i = 0; i < mesh.num_edges(); ++i) r(i, 0) = mesh.edge(i).v0, r(i, 1) = mesh.edge(i).v1;
         return a;
       },
       "(num_edges, 2) int32: the end points v0, v1 of each edge (v0 -> v1 counter-clockwise in\n"
       "the element on its left).")
      .def_property_readonly(
          "edge_elements",
          [](const PyMesh& s) {
            const Mesh& mesh = get(s);
            py::array_t<std::int32_t> a({mesh.num_edges(), 2});
            auto r = a.mutable_unchecked<2>();
            for (int i = 0; i < mesh.num_edges(); ++i) r(i, 0) = mesh.edge(i).left, r(i, 1) = mesh.edge(i).right;
            return a;
          },
          "(num_edges, 2) int32: the element left and right of each edge (-1 on the boundary).")
      .def_property_readonly(
          "boundary_edges",
          [](const PyMesh& s) {
            const auto& b = get(s).boundary_edges();
            return copy(std::vector<std::int32_t>(b.begin(), b.end()));
          },
          "Ids of the edges of exactly one element (int32, increasing).")
      .def_property_readonly(
          "boundary_vertices",
          [](const PyMesh& s) {
            const auto b = get(s).boundary_vertices();
            return copy(std::vector<std::int32_t>(b.begin(), b.end()));
          },
          "End points of the boundary edges (int32, sorted).");
}

/// Element geometry, regions, edge groups, h, the bounding box, len and repr.
void def_mesh_geometry(MeshClass& c) {
  c.def_property_readonly(
       "areas",
       [](const PyMesh& s) {
         const Mesh& mesh = get(s);
         py::array_t<double> a(mesh.num_elements());
         for (int e = 0; e < mesh.num_elements(); ++e) a.mutable_data()[e] = mesh.area(e);
         return a;
       },
       "Element areas (float64).")
      .def_property_readonly(
          "centroids",
          [](const PyMesh& s) {
            const Mesh& mesh = get(s);
            py::array_t<double> a({mesh.num_elements(), 2});
            auto r = a.mutable_unchecked<2>();
            for (int e = 0; e < mesh.num_elements(); ++e) r(e, 0) = mesh.centroid(e).x(), r(e, 1) = mesh.centroid(e).y();
            return a;
          },
          "(num_elements, 2) element centroids.")
      .def_property_readonly(
          "diameters",
          [](const PyMesh& s) {
            const Mesh& mesh = get(s);
            py::array_t<double> a(mesh.num_elements());
            for (int e = 0; e < mesh.num_elements(); ++e) a.mutable_data()[e] = mesh.diameter(e);
            return a;
          },
          "Element diameters (largest distance between two of its vertices).")
      .def_property_readonly(
          "regions",
          [](const PyMesh& s) {
            const auto& r = get(s).regions();
            return copy(std::vector<std::int32_t>(r.begin(), r.end()));
          },
          "Material region id of each element (int32).")
      .def_property_readonly(
          "edge_groups",
          [](const PyMesh& s) {
            py::dict d;
            for (const auto& [name, edges] : get(s).edge_groups())
              d[py::str(name)] = copy(std::vector<std::int32_t>(edges.begin(), edges.end()));
            return d;
          },
          "Named edge sets (Gmsh physical groups, polygon edges 'edge<k>'): name -> edge ids.")
      .def_property_readonly("h", [](const PyMesh& s) { return get(s).h(); }, "The largest element diameter.")
      .def_property_readonly(
          "bounding_box",
          [](const PyMesh& s) {
            const Rectangle r = get(s).bounding_box();
            return py::make_tuple(r.x0, r.x1, r.y0, r.y1);
          },
          "(x0, x1, y0, y1).")
      .def("__len__", [](const PyMesh& s) { return get(s).num_elements(); })
      .def("__repr__", [](const PyMesh& s) {
        const Mesh& mesh = get(s);
        std::ostringstream o;
        o << "Mesh(" << mesh.num_vertices() << " vertices, " << mesh.num_elements() << " elements, " << mesh.num_edges()
          << " edges, h=" << mesh.h() << ")";
        return o.str();
      });
}

using Mesh3DClass = py::class_<PyMesh3D>;

const Mesh3D& get3(const PyMesh3D& s) { return *s.mesh; }

/// An int32 array of ids.
py::array_t<std::int32_t> int32s(const std::vector<int>& v) { return copy(std::vector<std::int32_t>(v.begin(), v.end())); }

/// An (n, 3) float64 array whose row i is at(i).
template <class At>
py::array_t<double> rows3(int n, const At& at) {
  py::array_t<double> a({static_cast<py::ssize_t>(n), py::ssize_t(3)});
  auto r = a.mutable_unchecked<2>();
  for (int i = 0; i < n; ++i) {
    const Vec3 v = at(i);
    r(i, 0) = v.x(), r(i, 1) = v.y(), r(i, 2) = v.z();
  }
  return a;
}

/// Mesh3D.generate.
void def_mesh3d_sources(Mesh3DClass& c) {
  c.def_static(
      "generate",
      [](const std::string& kind, std::array<int, 3> n, std::array<double, 6> box, std::uint64_t seed) {
        Mesh3D mesh;
        {
          py::gil_scoped_release release;
          mesh = make_mesh3d(kind, GridSize3(n[0], n[1], n[2]), Box{box[0], box[1], box[2], box[3], box[4], box[5]}, seed);
        }
        return PyMesh3D{std::make_shared<const Mesh3D>(std::move(mesh))};
      },
      py::arg("kind"), py::arg("n"), py::arg("box") = std::array<double, 6>{0.0, 1.0, 0.0, 1.0, 0.0, 1.0},
      py::arg("seed") = 1,
      "A generated mesh of the box [x0, x1, y0, y1, z0, z1] with n = [nx, ny, nz] cells along each side "
      "(InputError for an unknown kind or a bad size).");
}

/// Sizes, vertices, faces, cells and the boundary.
void def_mesh3d_topology(Mesh3DClass& c) {
  c.def_property_readonly("num_vertices", [](const PyMesh3D& s) { return get3(s).num_vertices(); })
      .def_property_readonly("num_cells", [](const PyMesh3D& s) { return get3(s).num_cells(); })
      .def_property_readonly("num_faces", [](const PyMesh3D& s) { return get3(s).num_faces(); })
      .def_property_readonly(
          "vertices",
          [](py::object self) {
            const Mesh3D& mesh = get3(self.cast<const PyMesh3D&>());
            return view(mesh.vertices().empty() ? nullptr : mesh.vertices().front().data(), mesh.num_vertices(), 3, self);
          },
          "(num_vertices, 3) float64, C order, read-only view of the mesh's coordinates.")
      .def_property_readonly(
          "faces",
          [](const PyMesh3D& s) {
            py::list out;
            for (const MeshFace& f : get3(s).faces()) out.append(py::cast(f.vertices));
            return out;
          },
          "The faces as a list of vertex loops, each counter-clockwise seen from outside its cell\n"
          "face_cells[f, 0] (the face's normal points from that cell to face_cells[f, 1]).")
      .def_property_readonly(
          "face_cells",
          [](const PyMesh3D& s) {
            const Mesh3D& mesh = get3(s);
            py::array_t<std::int32_t> a({static_cast<py::ssize_t>(mesh.num_faces()), py::ssize_t(2)});
            auto r = a.mutable_unchecked<2>();
            for (int f = 0; f < mesh.num_faces(); ++f) r(f, 0) = mesh.face(f).inner, r(f, 1) = mesh.face(f).outer;
            return a;
          },
          "(num_faces, 2) int32: the cell inside and outside each face (-1 outside a boundary face).")
      .def_property_readonly(
          "cells",
          [](const PyMesh3D& s) {
            const Mesh3D& mesh = get3(s);
            py::list out;
            for (int c = 0; c < mesh.num_cells(); ++c) out.append(py::cast(mesh.cell_faces(c)));
            return out;
          },
          "The cells as a list of lists of face ids.")
      .def_property_readonly(
          "cell_vertices",
          [](const PyMesh3D& s) {
            const Mesh3D& mesh = get3(s);
            py::list out;
            for (int c = 0; c < mesh.num_cells(); ++c) out.append(py::cast(mesh.cell_vertices(c)));
            return out;
          },
          "The sorted vertex ids of each cell (a list of lists).")
      .def_property_readonly(
          "boundary_faces", [](const PyMesh3D& s) { return int32s(get3(s).boundary_faces()); },
          "Ids of the faces of exactly one cell (int32, increasing).")
      .def_property_readonly(
          "boundary_vertices", [](const PyMesh3D& s) { return int32s(get3(s).boundary_vertices()); },
          "The vertices of the boundary faces (int32, sorted).");
}

/// Cell and face geometry.
void def_mesh3d_geometry(Mesh3DClass& c) {
  c.def_property_readonly(
       "volumes",
       [](const PyMesh3D& s) {
         const Mesh3D& mesh = get3(s);
         py::array_t<double> a(mesh.num_cells());
         for (int c = 0; c < mesh.num_cells(); ++c) a.mutable_data()[c] = mesh.volume(c);
         return a;
       },
       "Cell volumes (float64).")
      .def_property_readonly(
          "centroids",
          [](const PyMesh3D& s) {
            const Mesh3D& mesh = get3(s);
            return rows3(mesh.num_cells(), [&](int c) { return mesh.centroid(c); });
          },
          "(num_cells, 3) cell centroids.")
      .def_property_readonly(
          "diameters",
          [](const PyMesh3D& s) {
            const Mesh3D& mesh = get3(s);
            py::array_t<double> a(mesh.num_cells());
            for (int c = 0; c < mesh.num_cells(); ++c) a.mutable_data()[c] = mesh.diameter(c);
            return a;
          },
          "Cell diameters (largest distance between two of its vertices).")
      .def_property_readonly(
          "face_areas",
          [](const PyMesh3D& s) {
            const Mesh3D& mesh = get3(s);
            py::array_t<double> a(mesh.num_faces());
            for (int f = 0; f < mesh.num_faces(); ++f) a.mutable_data()[f] = mesh.face_area(f);
            return a;
          },
          "Face areas (float64).")
      .def_property_readonly(
          "face_normals",
          [](const PyMesh3D& s) {
            const Mesh3D& mesh = get3(s);
            return rows3(mesh.num_faces(), [&](int f) { return mesh.face_normal(f); });
          },
          "(num_faces, 3) unit normals, pointing out of face_cells[f, 0] (outward on the boundary).");
}

/// Regions, face groups, h, the bounding box, len and repr.
void def_mesh3d_parts(Mesh3DClass& c) {
  c.def_property_readonly(
       "regions", [](const PyMesh3D& s) { return int32s(get3(s).regions()); },
       "Material region id of each cell (int32).")
      .def_property_readonly(
          "face_groups",
          [](const PyMesh3D& s) {
            py::dict d;
            for (const auto& [name, faces] : get3(s).face_groups()) d[py::str(name)] = int32s(faces);
            return d;
          },
          "Named face sets (a Gmsh file's physical surfaces): name -> face ids.")
      .def_property_readonly("h", [](const PyMesh3D& s) { return get3(s).h(); }, "The largest cell diameter.")
      .def_property_readonly(
          "bounding_box",
          [](const PyMesh3D& s) {
            const Box b = get3(s).bounding_box();
            return py::make_tuple(b.x0, b.x1, b.y0, b.y1, b.z0, b.z1);
          },
          "(x0, x1, y0, y1, z0, z1).")
      .def("__len__", [](const PyMesh3D& s) { return get3(s).num_cells(); })
      .def("__repr__", [](const PyMesh3D& s) {
        const Mesh3D& mesh = get3(s);
        std::ostringstream o;
        o << "Mesh3D(" << mesh.num_vertices() << " vertices, " << mesh.num_cells() << " cells, " << mesh.num_faces()
          << " faces, h=" << mesh.h() << ")";
        return o.str();
      });
}

/// hemivem.Mesh3D: the polyhedral mesh of a three-dimensional solve (Result.mesh), read-only.
void register_mesh3d(py::module_& m) {
  Mesh3DClass c(m, "Mesh3D", R"doc(
The polyhedral mesh of a three-dimensional solve (Result.mesh of a scene whose dimension is
3; docs/three-dimensions.md): vertices, cells bounded by planar polygonal faces, face groups
and region ids. Read-only; it shares the Result's memory.

    r = hemivem.solve("scenes/example-4.1-3d.toml")
    m = r.mesh                  # Mesh3D(405 vertices, 256 cells, 896 faces, h=0.216506)
    m.vertices                  # (num_vertices, 3) float64, C order, read-only view
    m.faces[f]                  # the vertex loop of face f, counter-clockwise seen from outside face_cells[f, 0]
    m.cells[c]                  # the face ids of cell c

Mesh3D.generate(kind, n, box) makes one (a generator of three-dimensional scenes: cubes,
tetrahedra, voronoi), to solve a scene on with hemivem.solve(scene, mesh=m).
)doc");
  def_mesh3d_sources(c);
  def_mesh3d_topology(c);
  def_mesh3d_geometry(c);
  def_mesh3d_parts(c);
}

}  // namespace

void register_mesh(py::module_& m) {
  MeshClass c(m, "Mesh", R"doc(
A valid polygonal mesh: vertices, counter-clockwise elements of any number of vertices,
edges, boundary edges, element geometry and region ids. Immutable.

    mesh = hemivem.Mesh.generate("voronoi", 16, seed=3)
    mesh = hemivem.Mesh.read("scenes/meshes/half-disk.msh")
    mesh = hemivem.Mesh.from_arrays(vertices, offsets, indices)

Arrays: vertices (n, 2) float64 (a read-only view, no copy); elements as CSR (offsets of
length num_elements + 1 and indices, int32); edges (m, 2) int32 (v0, v1); edge_elements
(m, 2) int32 (left, right; -1 on the boundary); boundary_edges (edge ids) int32.
)doc");
  def_mesh_sources(c);
  def_mesh_elements(c);
  def_mesh_edges(c);
  def_mesh_geometry(c);
  register_mesh3d(m);
  m.def("mesh_generators", &mesh_generator_names, "The generator names of Mesh.generate.");
}

}  // namespace hemivem::python
