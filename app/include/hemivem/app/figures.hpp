// Figures drawn with gnuplot: the one helper every command draws with (solve's figures,
// study.png, bench.png), and the figures of a solve of a plane or a solid body.
//
// A Figure is a gnuplot script and the data files it reads. draw_figures runs gnuplot once
// for several figures in a private temporary folder (the scripts' working folder, so they
// name their data files plainly: plot 'u_nu.dat' ...), in each format asked (PNG, PDF, SVG),
// then moves each file made into the output folder atomically. A figure is never worth failing
// a run for: gnuplot missing or failing is reported per figure, not thrown. The helpers of the
// house style (tick labels, line widths) are here too.
#pragma once

#include <cstddef>
#include <filesystem>
#include <functional>
#include <iosfwd>
#include <string>
#include <utility>
#include <vector>

#include <hemivem/contact/contact3d.hpp>
#include <hemivem/contact/solver.hpp>
#include <hemivem/mesh/mesh.hpp>
#include <hemivem/mesh/mesh3d.hpp>

#include <hemivem/app/outputs.hpp>

namespace hemivem::app {

/// A data file of a figure: its name in the scripts' working folder and what it holds.
struct PlotData {
  std::string name;
  std::function<void(std::ostream&)> write;
};

/// One figure: `script` draws it (the terminal and `set output` are set before it runs, `unset
/// output` and `reset` after), reading `data`.
struct Figure {
  std::string png;  ///< the PNG's name in the output folder, e.g. "u_nu.png" (another format: its extension)
  int width = 1000, height = 700;
  std::string script;
  std::vector<PlotData> data;
};

/// The formats a figure can be drawn in: png (pngcairo, or gnuplot's gd-based png), pdf
/// (pdfcairo) and svg.
const std::vector<std::string>& figure_formats();
/// The files of `figure` in `formats`, in their order: its PNG name (Figure::png) with the
/// format's extension ("u_nu.png", "u_nu.pdf", "u_nu.svg").
std::vector<std::string> figure_files(const Figure& figure, const std::vector<std::string>& formats);
/// Whether `p` is a file of `format`: a PNG's signature, a PDF's "%PDF-", an <svg element in
/// the first 4096 bytes of an SVG.
bool is_figure_file(const std::filesystem::path& p, const std::string& format);

/// Draws `figures` into `dir` (which must exist) with one run of gnuplot, each in every one of
/// `formats` (figure_formats; InputError for another). For each figure, in order: empty when
/// its files were written (figure_files), else why not ("gnuplot not found on PATH", "gnuplot
/// failed (exit status 1): ...", "gnuplot made no PNG", "gnuplot made no PDF (it needs
/// gnuplot's pdfcairo terminal)"); a figure is written in every format or in none. Throws
/// InputError when a file cannot be written.
std::vector<std::string> draw_figures(const std::filesystem::path& dir, const std::vector<Figure>& figures,
                                      const std::vector<std::string>& formats = {"png"});

/// One warning per reason of the figures not drawn (`failed`: each figure's name and why),
/// naming the figures it kept from being drawn, in the order given: "figure not drawn:
/// u_nu.png, deformed.png: gnuplot failed (exit status 1): ...".
std::vector<std::string> figure_warnings(const std::vector<std::pair<std::string, std::string>>& failed);

/// A single-quoted gnuplot string ('' stands for a quote; control characters, a newline among
/// them, as spaces: gnuplot's single-quoted strings have no escapes).
std::string gnuplot_quote(const std::string& s);
/// Whether `p` starts with the PNG signature.
bool is_png(const std::filesystem::path& p);

/// A printf format of gnuplot for the tick labels of an axis from `lo` to `hi`: "%.Ng" with N
/// (3 ... 15) significant digits, enough that ticks a twentieth of the span apart print
/// differently ("%.3g" from -3.1e-8 to -2.9e-8: -3.1e-08, -3.05e-08, ...) and that numbers
/// below 1e7 print in full (12500, not 1.25e+04); "%g" for a range that is not finite.
std::string tick_format(double lo, double hi);
/// `set format AXIS "..."` (tick_format) as a line of a script; `axis` is x, y, x2, y2, z or cb.
std::string axis_format(const std::string& axis, double lo, double hi);
/// The step of the ticks of an axis from `lo` to `hi`: 1, 2 or 5 times a power of ten, the
/// smallest such that the axis has at most `intervals` (>= 1) intervals; 0 for an empty or
/// not finite range.
double tick_step(double lo, double hi, int intervals);
/// The width of the lines of a mesh of `elements` elements drawn in a picture about 1000 points
/// wide: 1 up to 100 elements, then falling as 1 / sqrt(elements) (the edges' spacing) down to
/// 0.05, so that a fine mesh shows its cells rather than a solid blob.
double mesh_line_width(long long elements);

/// u_nu.png: the normal displacement u_nu along the contact boundary against x (when Gamma_3
/// is one horizontal line) or its arc length, and the contact pressure on a second axis. The
/// axis follows u_nu: the law's breakpoints and the gap (when u_nu <= g is a constraint) widen
/// it only where they lie near u_nu's range; a gap farther away is clipped, and its key entry
/// says so. Breakpoints too close to be told apart share a label. The title names the scene
/// and the mesh (files without their folders). With friction (has_tangential) a second panel
/// below: u_tau with its stick and slip nodes marked, and the friction traction on a second
/// axis. The solution must have contact nodes.
Figure u_nu_figure(const Mesh& mesh, const ContactSolution& solution, const RunInfo& info);
/// The same where `mesh` is the first process's piece of the whole mesh (every vertex, some
/// cells), over the whole mesh's boundary edges gathered from the pieces (`whole`).
Figure u_nu_figure(const Mesh& mesh, const WholeOfPieces& whole, const ContactSolution& solution, const RunInfo& info);

/// deformed.png: the deformed mesh (its boundary alone above 100000 edges) coloured by |u|
/// (viridis) over the undeformed outline, in a frame that holds the body with a margin. With
/// a rigid obstacle (info.obstacle) the obstacle's own geometry clipped to the frame, and the
/// body at its true displacement; else the displacement is magnified so that its largest
/// value is a tenth of the domain's size, and when u_nu <= g is a constraint the foundation
/// where u_nu = g (x_i + g_i nu_i, moved by the same magnification, so that a node touching
/// it is drawn on it). With contact, the contact nodes.
Figure deformed_figure(const Mesh& mesh, const ContactSolution& solution, const RunInfo& info);
/// The same where `mesh` is the first process's piece, over the whole mesh's edges gathered from
/// the pieces (`whole`: its edge count, boundary edges and, where drawn, every edge).
Figure deformed_figure(const Mesh& mesh, const WholeOfPieces& whole, const ContactSolution& solution, const RunInfo& info);
/// Whether deformed.png of a plane draws each of a mesh's `edges` edges (up to 100000), else its
/// boundary alone.
bool draws_every_edge(std::size_t edges);
/// deformed.png of a solid: the boundary faces of the deformed body in perspective, filled with
/// the colour of |u| (viridis), the displacement magnified so that its largest value is a tenth
/// of the body's size (the title says by how much).
Figure deformed_figure(const Mesh3D& mesh, const ContactSolution3D& solution, const RunInfo& info);
/// The same over the boundary faces given as vertex loops of `mesh` (in the order of its
/// boundary faces: those gathered from the processes' pieces, WholeOfPieces::boundary).
Figure deformed_figure(const Mesh3D& mesh, std::vector<std::vector<int>> boundary, const ContactSolution3D& solution,
                       const RunInfo& info);

/// pressure.png of a solid: the contact pressure over the contact faces `faces`, a colour map
/// seen along the axis nearest to the contact nodes' mean normal (over x and y for a contact on
/// a bottom or top face), each face filled from its nodes' pressures (0 at a node that is not a
/// contact node); the solution must have contact nodes.
Figure pressure_figure(const Mesh3D& mesh, const std::vector<int>& faces, const ContactSolution3D& solution,
                       const RunInfo& info);
/// The same over the contact faces given as vertex loops of `mesh` (WholeOfPieces::contact_surface).
Figure pressure_figure(const Mesh3D& mesh, std::vector<std::vector<int>> faces, const ContactSolution3D& solution,
                       const RunInfo& info);

/// error.png: the element error indicators eta_E of an error estimate, each element filled with
/// its colour on a logarithmic viridis scale (the colour bar labelled "error indicator eta_E"),
/// the mesh's edges drawn thin (omitted above 20000 elements), the title solve_title("error indicators", info).
/// indicators has one entry per element (zeros drawn with the scale's lowest colour).
Figure indicator_figure(const Mesh& mesh, const std::vector<double>& indicators, const RunInfo& info);
/// The same where `mesh` is the first process's piece, over the whole mesh's elements and, where
/// drawn, edges gathered from the pieces (`whole`); indicators per element of the whole mesh.
Figure indicator_figure(const Mesh& mesh, const WholeOfPieces& whole, const std::vector<double>& indicators,
                        const RunInfo& info);
/// Whether error.png draws the edges of a mesh of `elements` elements (up to 20000).
bool indicator_draws_edges(long long elements);

/// mesh.png: the mesh's edges (e.g. the final mesh of an adaptive solve) at the width
/// mesh_line_width of its element count, equal axes, title solve_title(what, info) with `what`
/// e.g. "final mesh, 1234 elements". A mesh refined locally (at least 200 elements, the largest
/// diameter at least 8 times the smallest) gets a second panel: a square 40 smallest diameters
/// wide around the smallest element (moved into the mesh's bounding box), framed in red on the
/// first panel, enlarged, its lines as wide as the number of elements it shows allows.
Figure mesh_figure(const Mesh& mesh, const RunInfo& info, const std::string& what);

/// One curve of convergence_figure.
struct ConvergenceSeries {
  std::string name;               ///< key entry, e.g. "adaptive (estimate)", "uniform (estimate)", "uniform (true error)"
  std::vector<double> unknowns;   ///< free degrees of freedom per point
  std::vector<double> seconds;    ///< elapsed wall time per point
  std::vector<double> error;      ///< relative error per point (> 0; points with error <= 0 or non-finite are left out)
  bool dashed = false;            ///< true errors are drawn dashed, estimates solid
};
/// adapt.png (or any `png` name given): two panels side by side, relative error against unknowns and against
/// run time, both log-log, one curve per series (viridis colours by series order, points marked), with a
/// reference line of (unknowns)^(-1/d) in the first panel (the rate of h for a body of dimension d =
/// `dimension`), labelled "N^-1/2" or "N^-1/3"; title `title` (cut like the other titles). Series with no
/// point are left out of the key.
Figure convergence_figure(const std::vector<ConvergenceSeries>& series, const std::string& title,
                          const std::string& png = "adapt.png", int dimension = 2);

}  // namespace hemivem::app
