#include "path_outputs.hpp"

#include <hemivem/app/format.hpp>
#include <hemivem/app/path.hpp>
#include <hemivem/app/text_writer.hpp>

#include "figure_style.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <regex>
#include <sstream>

namespace hemivem::app {

namespace fs = std::filesystem;
using detail::num;

template <int dim>
void write_path_contact_csv(std::ostream& stream, const BasicPathSolution<dim>& path) {
  TextWriter os(stream);
  const bool tangential = !path.steps.empty() && path.steps.front().slip.size() > 0;
  const bool parts = path.last.contact_parts.size() > 1;  // several contact parts: each node's
  os << "step,t,vertex," << (dim == 2 ? "x,y" : "x,y,z") << ",u_nu,law_force,reaction,pressure,state"
     << (tangential ? ",u_tau,slip,friction_force,friction_bound,friction_state" : "") << (parts ? ",part" : "") << "\n";
  for (const auto& s : path.steps)
    for (std::size_t i = 0; i < s.contact.size(); ++i) {
      const auto& n = s.contact[i];
      os << s.index << ',' << s.t << ',' << n.vertex;
      for (int c = 0; c < dim; ++c) os << ',' << n.x(c);
      os << ',' << n.u_nu << ','
         << n.law_force << ',' << n.reaction << ',' << n.pressure() << ',' << to_string(n.state);
      if (tangential && n.friction_state != FrictionState::none) {
        const auto k = static_cast<Eigen::Index>(i);
        os << ',' << n.u_tau << ',' << s.slip(k) << ',' << n.friction_force << ',' << s.friction_bound(k) << ','
           << to_string(n.friction_state);
      } else if (tangential) {
        os << ",,,,,";  // a frictionless part beside one with friction
      }
      if (parts) os << ',' << contact_part_name(path.last, n);
      os << '\n';
    }
}

template <class MeshType, int dim>
void write_path_displacement_csv(std::ostream& stream, const MeshType& mesh, const BasicPathSolution<dim>& path) {
  TextWriter os(stream);
  os << (dim == 2 ? "step,t,vertex,x,y,ux,uy\n" : "step,t,vertex,x,y,z,ux,uy,uz\n");
  for (const auto& s : path.steps) {
    if (s.u.size() == 0) continue;
    for (int v = 0; v < mesh.num_vertices(); ++v) {
      os << s.index << ',' << s.t << ',' << v;
      for (int c = 0; c < dim; ++c) os << ',' << mesh.vertex(v)(c);
      for (int c = 0; c < dim; ++c) os << ',' << s.u(dim * v + c);
      os << '\n';
    }
  }
}

std::string frame_file(int step) {
  char name[32];
  std::snprintf(name, sizeof name, "solution-%04d.vtu", step);
  return name;
}

template <int dim>
std::vector<std::string> frame_files(const BasicPathSolution<dim>& path) {
  std::vector<std::string> names;
  for (const auto& s : path.steps)
    if (s.u.size() > 0) names.push_back(frame_file(s.index));
  return names;
}

std::vector<std::string> files_matching(const fs::path& dir, const std::string& pattern) {
  std::vector<std::string> names;
  std::error_code ec;
  if (!fs::is_directory(dir, ec)) return names;
  const std::regex whole(pattern);
  for (const auto& entry : fs::directory_iterator(dir, ec)) {
    const std::string name = entry.path().filename().string();
    if (std::regex_match(name, whole)) names.push_back(name);
  }
  return names;
}

std::vector<std::string> frame_files_in(const fs::path& dir) { return files_matching(dir, R"(solution-[0-9]{4,}\.vtu)"); }

template <int dim>
void write_pvd(std::ostream& stream, const BasicPathSolution<dim>& path) {
  TextWriter os(stream);
  os << "<?xml version=\"1.0\"?>\n"
     << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
     << "  <Collection>\n";
  for (const auto& s : path.steps)
    if (s.u.size() > 0)
      os << "    <DataSet timestep=\"" << s.t << "\" group=\"\" part=\"0\" file=\"" << frame_file(s.index) << "\"/>\n";
  os << "  </Collection>\n</VTKFile>\n";
}

template <int dim>
nlohmann::json path_summary_json(const BasicPathSolution<dim>& path) {
  int converged = 0;
  for (const auto& s : path.steps) converged += s.converged() ? 1 : 0;
  return {{"steps", path.steps.size()},
          {"converged_steps", converged},
          {"jumps", path.jumps()},
          {"t", path.steps.empty() ? nlohmann::json() : nlohmann::json(path.steps.back().t)},
          {"proportional", path.proportional},
          {"condensed_loads", path.condensed_loads},
          {"file", "path.json"}};
}

template <int dim>
Figure path_figure(const BasicPathSolution<dim>& path, const RunInfo& info) {
  Figure f;
  f.png = "path.png";
  f.width = 1400;
  f.height = 600;
  const bool friction = !path.steps.empty() && path.steps.front().slip.size() > 0;
  // per step: t, mean u_nu, normal resultant, friction resultant, zone length, stick length, jump
  std::vector<std::array<double, 7>> rows;
  for (const auto& s : path.steps) {
    double w = 0.0, un = 0.0, normal = 0.0, tangential = 0.0, stick = 0.0;
    for (const auto& n : s.contact) {
      w += n.weight;
      un += n.weight * n.u_nu;
      normal += n.force();
      tangential += n.friction_force;
      if (n.friction_state == FrictionState::stick && n.force() > 0.0) stick += n.weight;
    }
    rows.push_back({s.t, w > 0.0 ? un / w : 0.0, normal, tangential, s.zone.length, stick, s.jump ? 1.0 : 0.0});
  }
  // the range of the columns `columns` over the steps, for tick labels that differ at any scale
  auto format = [&rows](const std::string& axis, const std::vector<int>& columns) {
    double lo = 0.0, hi = 0.0;
    bool first = true;
    for (const auto& r : rows)
      for (int c : columns)
        if (std::isfinite(r[static_cast<std::size_t>(c)])) {
          const double v = r[static_cast<std::size_t>(c)];
          lo = first ? v : std::min(lo, v), hi = first ? v : std::max(hi, v);
          first = false;
        }
    return axis_format(axis, lo, hi);
  };
  f.data.push_back({"path.dat", [rows](std::ostream& os) {
                      for (const auto& r : rows) {
                        for (std::size_t c = 0; c + 1 < r.size(); ++c) os << num(r[c]) << ' ';
                        os << (r.back() > 0.0 ? 1 : 0) << '\n';
                      }
                    }});
  std::ostringstream s;
  s << "set multiplot layout 1,2 title " << detail::solve_title("loading path, " + std::to_string(path.steps.size()) + " steps", info)
    << " noenhanced\n"
    << "set grid\nset key top left\n"
    << format("x", {1}) << format("y", friction ? std::vector<int>{2, 3} : std::vector<int>{2})
    << "set xlabel 'mean normal displacement of the contact nodes'\nset ylabel 'resultant of the contact forces'\n"
    << "plot 'path.dat' using 2:3 with linespoints pt 7 ps 0.6 lc rgb '#3b528b' title 'normal (compressive)'"
    << (friction ? ", 'path.dat' using 2:4 with linespoints pt 7 ps 0.6 lc rgb '#5ec962' title 'friction'" : "")
    << ", 'path.dat' using 2:($7 > 0 ? $3 : 1/0) with points pt 6 ps 2 lc rgb '#d62728' title 'jump'\n"
    << format("x", {0}) << format("y", friction ? std::vector<int>{4, 5} : std::vector<int>{4})
    << "set xlabel 'load factor t'\nset ylabel '" << (dim == 2 ? "length" : "area") << " of boundary'\n"
    << "plot 'path.dat' using 1:5 with linespoints pt 7 ps 0.6 lc rgb '#3b528b' title 'contact zone'"
    << (friction ? ", 'path.dat' using 1:6 with linespoints pt 7 ps 0.6 lc rgb '#5ec962' title 'stick zone'" : "") << "\n"
    << "unset multiplot\n";
  f.script = s.str();
  return f;
}

template <class MeshType, int dim>
void write_path_files(OutputTransaction& tx, const fs::path& dir, const MeshType& mesh, const BasicPathSolution<dim>* path,
                      const std::function<bool(const std::string&)>& want,
                      const std::function<void(std::ostream&, const BasicContactSolution<dim>&)>& write_frame,
                      OutputReport& report) {
  if (!path) {
    for (const char* name : {"path.json", "path-contact.csv", "path-displacement.csv", "solution.pvd"})
      if (want(name)) report.skipped.push_back(std::string(name) + ": not a loading path");
    return;
  }
  auto write = [&](const std::string& name, const std::function<void(std::ostream&)>& body) {
    if (!want(name)) return;
    tx.write(name, body);
    report.written.push_back(dir / name);
  };
  write("path.json", [&](std::ostream& os) {
    write_path_json(os, *path);
    os << '\n';
  });
  write("path-contact.csv", [&](std::ostream& os) { write_path_contact_csv(os, *path); });
  write("path-displacement.csv", [&](std::ostream& os) { write_path_displacement_csv(os, mesh, *path); });
  if (!want("solution.pvd")) return;
  for (const auto& step : path->steps) {
    if (step.u.size() == 0) continue;
    BasicContactSolution<dim> frame;
    frame.u = step.u;
    frame.contact = step.contact;
    const std::string name = frame_file(step.index);
    tx.write(name, [&](std::ostream& os) { write_frame(os, frame); });
    report.written.push_back(dir / name);
  }
  write("solution.pvd", [&](std::ostream& os) { write_pvd(os, *path); });
}

template <int dim>
std::vector<std::string> listed_frames(const BasicPathSolution<dim>* path,
                                       const std::function<bool(const std::string&)>& want) {
  return path && want("solution.pvd") ? frame_files(*path) : std::vector<std::string>();
}

#define HEMIVEM_PATH_OUTPUTS(dim, MeshType)                                                                         \
  template void write_path_contact_csv(std::ostream&, const BasicPathSolution<dim>&);                              \
  template void write_path_displacement_csv(std::ostream&, const MeshType&, const BasicPathSolution<dim>&);        \
  template void write_pvd(std::ostream&, const BasicPathSolution<dim>&);                                           \
  template std::vector<std::string> frame_files(const BasicPathSolution<dim>&);                                    \
  template nlohmann::json path_summary_json(const BasicPathSolution<dim>&);                                        \
  template Figure path_figure(const BasicPathSolution<dim>&, const RunInfo&);                                      \
  template void write_path_files(OutputTransaction&, const fs::path&, const MeshType&, const BasicPathSolution<dim>*, \
                                 const std::function<bool(const std::string&)>&,                                   \
                                 const std::function<void(std::ostream&, const BasicContactSolution<dim>&)>&,      \
                                 OutputReport&);                                                                   \
  template std::vector<std::string> listed_frames(const BasicPathSolution<dim>*,                                   \
                                                  const std::function<bool(const std::string&)>&);

HEMIVEM_PATH_OUTPUTS(2, Mesh)
HEMIVEM_PATH_OUTPUTS(3, Mesh3D)

}  // namespace hemivem::app
