// The pictures of a three-dimensional solve (outputs3d.hpp), drawn by gnuplot as the plane
// figures are (figures.hpp): polygons as pm3d patches, each quadrilateral one patch and any
// other polygon a fan of triangles from its centroid, coloured by a value at the vertices.
#include <hemivem/app/outputs3d.hpp>

#include <algorithm>
#include <cmath>
#include <iomanip>
#include <sstream>

#include <hemivem/app/text_writer.hpp>

#include "figure_style.hpp"

namespace hemivem::app {

using detail::kViridis;
using detail::num;
using detail::solve_title;

namespace {

/// The most boundary faces deformed.png draws (a 1000 x 800 picture): beyond, the faces are
/// finer than the picture's pixels and only cost time.
constexpr std::size_t kMaxDrawnFaces = 200000;

/// One polygon with a value at each corner, written as pm3d patches of "a b c value" rows: a
/// quadrilateral as one 2 x 2 patch, another polygon as triangles (centroid, z_i, z_{i+1}),
/// each a 2 x 2 patch with the centroid twice. Patches are separated by two blank lines.
void put_polygon(TextWriter& os, const std::vector<Vec3>& p, const std::vector<double>& value) {
  auto row = [&](const Vec3& x, double v) { os << x.x() << ' ' << x.y() << ' ' << x.z() << ' ' << v << '\n'; };
  if (p.size() == 4) {
    row(p[0], value[0]), row(p[1], value[1]);
    os << '\n';
    row(p[3], value[3]), row(p[2], value[2]);
    os << "\n\n";
    return;
  }
  Vec3 c = Vec3::Zero();
  double cv = 0.0;
  for (std::size_t i = 0; i < p.size(); ++i) c += p[i], cv += value[i];
  c /= static_cast<double>(p.size());
  cv /= static_cast<double>(p.size());
  for (std::size_t i = 0; i < p.size(); ++i) {
    const std::size_t j = (i + 1) % p.size();
    row(c, cv), row(p[i], value[i]);
    os << '\n';
    row(c, cv), row(p[j], value[j]);
    os << "\n\n";
  }
}

Vec3 displacement(const ContactSolution3D& sol, int v) { return sol.u.segment<3>(3 * static_cast<Eigen::Index>(v)); }

}  // namespace

Figure deformed_figure_3d(const Mesh3D& mesh, const ContactSolution3D& sol, const RunInfo& info) {
  const Box box = mesh.bounding_box();
  const double size = std::sqrt(box.size(0) * box.size(0) + box.size(1) * box.size(1) + box.size(2) * box.size(2));
  double umax = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v) umax = std::max(umax, displacement(sol, v).norm());
  // the largest displacement shows as 10% of the body's size (never shrunk)
  const double scale = umax > 0.0 && std::isfinite(umax) ? std::max(1.0, 0.1 * size / umax) : 1.0;
  const std::vector<int>& faces = mesh.boundary_faces();
  const bool all = faces.size() <= kMaxDrawnFaces;

  Figure f;
  f.png = "deformed.png";
  f.height = 800;
  f.data.push_back({"faces.dat", [&mesh, &sol, &faces, scale, all](std::ostream& stream) {
                      TextWriter os(stream);
                      os << "# x y z |u| (deformed boundary faces as pm3d patches)\n";
                      std::vector<Vec3> p;
                      std::vector<double> value;
                      for (std::size_t k = 0; k < faces.size(); ++k) {
                        if (!all && k % ((faces.size() + kMaxDrawnFaces - 1) / kMaxDrawnFaces) != 0) continue;
                        p.clear();
                        value.clear();
                        for (int v : mesh.face(faces[k]).vertices) {
                          const Vec3 u = displacement(sol, v);
                          p.push_back(mesh.vertex(v) + scale * u);
                          value.push_back(u.norm());
                        }
                        put_polygon(os, p, value);
                      }
                    }});
  std::ostringstream title;
  title << "deformed body (displacement x " << std::setprecision(3) << scale << "), coloured by |u|";
  if (!all) title << "; " << faces.size() << " boundary faces, one in " << (faces.size() + kMaxDrawnFaces - 1) / kMaxDrawnFaces << " drawn";
  std::ostringstream s;
  s << "set title " << solve_title(title.str(), info) << " noenhanced\n"
    << "set view 62, 32\nset view equal xyz\nset xyplane at " << num(box.z0 - 0.05 * size) << "\n"
    << "set xlabel 'x'\nset ylabel 'y'\nset zlabel 'z'\nset tics font ',9'\n"
    << "set pm3d depthorder border lc rgb '#303030' lw 0.4\nunset key\n"
    << kViridis << "set cblabel '|u| (scene units)'\n"
    << "splot 'faces.dat' using 1:2:3:4 with pm3d notitle";
  f.script = s.str();
  return f;
}

Figure pressure_figure(const Mesh3D& mesh, const std::vector<int>& faces, const ContactSolution3D& sol,
                       const RunInfo& info) {
  // the axis the contact faces are seen along: the largest component of their mean normal
  Vec3 mean = Vec3::Zero();
  for (const auto& n : sol.contact) mean += n.weight * n.normal;
  int along = 2;
  mean.cwiseAbs().maxCoeff(&along);
  const int a = along == 0 ? 1 : 0, b = along == 2 ? 1 : 2;
  const char* names = "xyz";
  std::vector<double> pressure(static_cast<std::size_t>(mesh.num_vertices()), 0.0);
  double lo = 0.0, hi = 0.0;
  for (const auto& n : sol.contact) {
    const double p = std::isfinite(n.pressure()) ? n.pressure() : 0.0;
    pressure[static_cast<std::size_t>(n.vertex)] = p;
    lo = std::min(lo, p), hi = std::max(hi, p);
  }
  double a_lo = 0.0, a_hi = 0.0, b_lo = 0.0, b_hi = 0.0;  // the extent of the map, for its height
  bool first = true;
  for (int face : faces)
    for (int v : mesh.face(face).vertices) {
      const Vec3& x = mesh.vertex(v);
      a_lo = first ? x(a) : std::min(a_lo, x(a)), a_hi = first ? x(a) : std::max(a_hi, x(a));
      b_lo = first ? x(b) : std::min(b_lo, x(b)), b_hi = first ? x(b) : std::max(b_hi, x(b));
      first = false;
    }
  Figure f;
  f.png = "pressure.png";
  // a flat contact surface gets a lower picture, so that the colour bar stays near it
  const double aspect = a_hi > a_lo ? (b_hi - b_lo) / (a_hi - a_lo) : 1.0;
  f.height = static_cast<int>(std::clamp(200.0 + 700.0 * aspect, 400.0, 900.0));
  f.data.push_back({"pressure.dat", [&mesh, &faces, pressure, a, b](std::ostream& stream) {
                      TextWriter os(stream);
                      os << "# a b 0 pressure (the contact faces seen along their normal, as pm3d patches)\n";
                      std::vector<Vec3> p;
                      std::vector<double> value;
                      for (int face : faces) {
                        p.clear();
                        value.clear();
                        for (int v : mesh.face(face).vertices) {
                          const Vec3& x = mesh.vertex(v);
                          p.emplace_back(x(a), x(b), 0.0);
                          value.push_back(pressure[static_cast<std::size_t>(v)]);
                        }
                        put_polygon(os, p, value);
                      }
                    }});
  std::ostringstream s;
  s << "set title "
    << solve_title("contact pressure over the contact faces, seen along " + std::string(1, names[along]), info)
    << " noenhanced\n"
    << "set view map\nset size ratio -1\nunset key\nset grid front\n"
    << "set xlabel '" << names[a] << " (scene units)'\nset ylabel '" << names[b] << " (scene units)'\n"
    << "set pm3d interpolate 4,4\n"
    << kViridis << "set cblabel 'contact pressure (force per unit area, scene units; compression > 0)'\n";
  if (hi > lo) s << "set cbrange [" << num(lo) << ":" << num(hi) << "]\n";
  s << "splot 'pressure.dat' using 1:2:3:4 with pm3d notitle";
  f.script = s.str();
  return f;
}

}  // namespace hemivem::app
