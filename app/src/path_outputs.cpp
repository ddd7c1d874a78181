#include "path_outputs.hpp"

#include <hemivem/app/format.hpp>
#include <hemivem/error.hpp>
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

std::string frame_file(int step) {
  char name[32];
  std::snprintf(name, sizeof name, "solution-%04d.vtu", step);
  return name;
}

std::string frame_pvtu_file(int step) { return fs::path(frame_file(step)).replace_extension(".pvtu").string(); }

std::string frame_piece_file(int step, int piece) {
  return fs::path(frame_file(step)).replace_extension(".piece-" + std::to_string(piece) + ".vtu").string();
}

std::vector<std::string> frame_files_of(int step, int pieces) {
  if (pieces <= 0) return {frame_file(step)};
  std::vector<std::string> names;
  for (int k = 0; k < pieces; ++k) names.push_back(frame_piece_file(step, k));
  names.push_back(frame_pvtu_file(step));
  return names;
}

template <int dim>
BasicContactSolution<dim> frame_of(const BasicPathStep<dim>& step, const std::vector<std::string>& parts) {
  BasicContactSolution<dim> frame;
  frame.u = step.u;
  frame.contact = step.contact;
  frame.contact_parts = parts;
  return frame;
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

std::vector<std::string> frame_files_in(const fs::path& dir) {
  return files_matching(dir, R"(solution-[0-9]{4,}(\.vtu|\.pvtu|\.piece-[0-9]+\.vtu))");
}

template <int dim>
nlohmann::json path_summary_json(const BasicPathSolution<dim>& path) {
  return {{"steps", path.solved_steps},
          {"converged_steps", path.converged_steps},
          {"jumps", path.jumps()},
          {"t", path.steps.empty() ? nlohmann::json() : nlohmann::json(path.steps.back().t)},
          {"proportional", path.proportional},
          {"condensed_loads", path.condensed_loads},
          {"file", "path.json"}};
}

namespace {

// A value dumped with an indent of 2, its lines after the first indented by `indent` more.
std::string indented(const nlohmann::json& value, const std::string& indent) {
  std::string text = value.dump(2);
  for (std::size_t at = text.find('\n'); at != std::string::npos; at = text.find('\n', at + 1 + indent.size()))
    text.insert(at + 1, indent);
  return text;
}

}  // namespace

template <int dim>
PathFiles<dim>::PathFiles(OutputTransaction& tx, std::function<bool(const std::string&)> want, const MeshType& mesh,
                          std::vector<std::string> parts, WriteFrame write_frame, std::vector<BodyRange> bodies)
    : tx_(tx),
      want_(std::move(want)),
      mesh_(mesh),
      parts_(std::move(parts)),
      write_frame_(std::move(write_frame)),
      bodies_(std::move(bodies)) {
  stage([&] {
    if (want_("path.json")) {
      json_ = std::make_unique<FileInPieces>(tx_.staging() / "path.json");
      json_->write([](std::ostream& os) { os << "{\n  \"schema\": \"hemivem-path/1\",\n  \"steps\": ["; });
    }
    if (want_("path-contact.csv")) contact_ = std::make_unique<FileInPieces>(tx_.staging() / "path-contact.csv");
    if (want_("path-displacement.csv")) {
      displacement_ = std::make_unique<FileInPieces>(tx_.staging() / "path-displacement.csv");
      displacement_->write([this](std::ostream& os) {
        os << (dim == 2 ? "step,t,vertex,x,y,ux,uy" : "step,t,vertex,x,y,z,ux,uy,uz") << (bodies_.empty() ? "" : ",body")
           << '\n';
      });
    }
  });
}

template <int dim>
PathFiles<dim>::~PathFiles() = default;

template <int dim>
void PathFiles<dim>::stage(const std::function<void()>& writes) {
  tx_.stage([&](const fs::path&) { writes(); });
}

template <int dim>
void PathFiles<dim>::add(const BasicPathStep<dim>& s) {
  const bool first = steps_++ == 0;
  if (first) tangential_ = s.slip.size() > 0;
  const bool parts = parts_.size() > 1;  // several contact parts: each node's
  // two bodies: the other body's vertex across the contact (the same pairs at every step)
  const bool pairs = std::any_of(s.contact.begin(), s.contact.end(), [](const auto& n) { return n.partner >= 0; });
  stage([&] {
    if (json_)
      json_->write([&](std::ostream& os) { os << (first ? "\n    " : ",\n    ") << indented(path_step_json(s), "    "); });
    if (contact_)
      contact_->write([&](std::ostream& stream) {
        TextWriter os(stream);
        if (first)
          os << "step,t,vertex," << (dim == 2 ? "x,y" : "x,y,z") << ",u_nu,law_force,reaction,pressure,state"
             << (!tangential_ ? ""
                 : dim == 2  ? ",u_tau,slip,friction_force,friction_bound,friction_state"
                             : ",u_tau_x,u_tau_y,u_tau_z,slip,friction_force_x,friction_force_y,friction_force_z,"
                               "friction_bound,friction_state")
             << (parts ? ",part" : "") << (pairs ? ",partner" : "") << "\n";
        for (std::size_t i = 0; i < s.contact.size(); ++i) {
          const auto& n = s.contact[i];
          os << s.index << ',' << s.t << ',' << n.vertex;
          for (int c = 0; c < dim; ++c) os << ',' << n.x(c);
          os << ',' << n.u_nu << ',' << n.law_force << ',' << n.reaction << ',' << n.pressure() << ',' << to_string(n.state);
          if (tangential_ && n.friction_state != FrictionState::none) {
            const auto k = static_cast<Eigen::Index>(i);
            // a plane's along tau, a solid's as vectors (the slip of the step: its length)
            if constexpr (dim == 2) {
              os << ',' << n.u_tau << ',' << s.slip(k) << ',' << n.friction_force;
            } else {
              for (int c = 0; c < 3; ++c) os << ',' << n.u_tangential(c);
              os << ',' << s.slip(k);
              for (int c = 0; c < 3; ++c) os << ',' << n.friction_vector(c);
            }
            os << ',' << s.friction_bound(k) << ',' << to_string(n.friction_state);
          } else if (tangential_) {
            os << (dim == 2 ? ",,,,," : ",,,,,,,,,");  // a frictionless part beside one with friction
          }
          if (parts) os << ',' << contact_part_name(parts_, n);
          if (pairs) {
            os << ',';
            if (n.partner >= 0) os << n.partner;  // empty: a foundation's or an obstacle's node
          }
          os << '\n';
        }
      });
    if (s.u.size() > 0 && displacement_)
      displacement_->write([&](std::ostream& stream) {
        TextWriter os(stream);
        std::size_t b = 0;
        for (int v = 0; v < mesh_.num_vertices(); ++v) {
          os << s.index << ',' << s.t << ',' << v;
          for (int c = 0; c < dim; ++c) os << ',' << mesh_.vertex(v)(c);
          for (int c = 0; c < dim; ++c) os << ',' << s.u(dim * v + c);
          if (!bodies_.empty()) {
            while (b + 1 < bodies_.size() && !bodies_[b].has_vertex(v)) ++b;
            os << ',' << bodies_[b].name;
          }
          os << '\n';
        }
      });
  });
  if (s.u.size() > 0 && want_("solution.pvd")) {
    const std::vector<std::string> files = write_frame_(s.index, frame_of(s, parts_));
    if (files.empty()) throw InternalError("a frame of no file");
    frames_.emplace_back(s.t, files.back());
    frame_files_.insert(frame_files_.end(), files.begin(), files.end());
  }
  double w = 0.0, un = 0.0, normal = 0.0, tangential = 0.0, stick = 0.0;
  for (const auto& n : s.contact) {
    w += n.weight;
    un += n.weight * n.u_nu;
    normal += n.force();
    tangential += n.friction_force;
    if (n.friction_state == FrictionState::stick && n.force() > 0.0) stick += n.weight;
  }
  rows_.push_back({s.t, w > 0.0 ? un / w : 0.0, normal, tangential, s.zone.length, stick, s.jump ? 1.0 : 0.0});
}

template <int dim>
void PathFiles<dim>::finish(const BasicPathSolution<dim>& path, OutputReport& report) {
  const fs::path& dir = tx_.dir();
  stage([&] {
    if (json_) {
      nlohmann::json members = path_json_members(path);
      members.erase("schema");
      json_->write([&](std::ostream& os) {
        os << (steps_ > 0 ? "\n  ]" : "]");
        for (auto it = members.begin(); it != members.end(); ++it)
          os << ",\n  " << nlohmann::json(it.key()).dump() << ": " << indented(it.value(), "  ");
        os << "\n}\n";
      });
      json_->close();
      report.written.push_back(dir / "path.json");
    }
    if (contact_) {
      contact_->close();
      report.written.push_back(dir / "path-contact.csv");
    }
    if (displacement_) {
      displacement_->close();
      report.written.push_back(dir / "path-displacement.csv");
    }
  });
  if (!want_("solution.pvd")) return;
  for (const auto& file : frame_files_) report.written.push_back(dir / file);
  tx_.write("solution.pvd", [&](std::ostream& stream) {
    TextWriter os(stream);
    os << "<?xml version=\"1.0\"?>\n"
       << "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
       << "  <Collection>\n";
    for (const auto& [t, file] : frames_)
      os << "    <DataSet timestep=\"" << t << "\" group=\"\" part=\"0\" file=\"" << file << "\"/>\n";
    os << "  </Collection>\n</VTKFile>\n";
  });
  report.written.push_back(dir / "solution.pvd");
}

template <int dim>
std::vector<std::string> PathFiles<dim>::frames() const {
  return frame_files_;
}

template <int dim>
Figure PathFiles<dim>::figure(const RunInfo& info) const {
  Figure f;
  f.png = "path.png";
  f.width = 1400;
  f.height = 600;
  const bool friction = tangential_;
  // the range of the columns `columns` over the steps, for tick labels that differ at any scale
  auto format = [this](const std::string& axis, const std::vector<int>& columns) {
    double lo = 0.0, hi = 0.0;
    bool first = true;
    for (const auto& r : rows_)
      for (int c : columns)
        if (std::isfinite(r[static_cast<std::size_t>(c)])) {
          const double v = r[static_cast<std::size_t>(c)];
          lo = first ? v : std::min(lo, v), hi = first ? v : std::max(hi, v);
          first = false;
        }
    return axis_format(axis, lo, hi);
  };
  f.data.push_back({"path.dat", [this](std::ostream& os) {
                      for (const auto& r : rows_) {
                        for (std::size_t c = 0; c + 1 < r.size(); ++c) os << num(r[c]) << ' ';
                        os << (r.back() > 0.0 ? 1 : 0) << '\n';
                      }
                    }});
  std::ostringstream s;
  s << "set multiplot layout 1,2 title " << detail::solve_title("loading path, " + std::to_string(steps_) + " steps", info)
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
std::unique_ptr<PathFiles<dim>> write_path_files(OutputTransaction& tx, const MeshType& mesh, const BasicPathSolution<dim>* path,
                                                 const std::function<bool(const std::string&)>& want,
                                                 const typename PathFiles<dim>::WriteFrame& write_frame, OutputReport& report,
                                                 const std::vector<BodyRange>& bodies) {
  if (!path) {
    for (const char* name : {"path.json", "path-contact.csv", "path-displacement.csv", "solution.pvd"})
      if (want(name)) report.skipped.push_back(std::string(name) + ": not a loading path");
    return nullptr;
  }
  auto files = std::make_unique<PathFiles<dim>>(tx, want, mesh, path->last.contact_parts, write_frame, bodies);
  for (const auto& step : path->steps) files->add(step);
  files->finish(*path, report);
  return files;
}

#define HEMIVEM_PATH_OUTPUTS(dim, MeshType)                                                                       \
  template class PathFiles<dim>;                                                                                 \
  template std::vector<std::string> frame_files(const BasicPathSolution<dim>&);                                  \
  template BasicContactSolution<dim> frame_of(const BasicPathStep<dim>&, const std::vector<std::string>&);      \
  template nlohmann::json path_summary_json(const BasicPathSolution<dim>&);                                      \
  template std::unique_ptr<PathFiles<dim>> write_path_files(OutputTransaction&, const MeshType&,                 \
                                                            const BasicPathSolution<dim>*,                      \
                                                            const std::function<bool(const std::string&)>&,     \
                                                            const PathFiles<dim>::WriteFrame&, OutputReport&,   \
                                                            const std::vector<BodyRange>&);

HEMIVEM_PATH_OUTPUTS(2, Mesh)
HEMIVEM_PATH_OUTPUTS(3, Mesh3D)

}  // namespace hemivem::app
