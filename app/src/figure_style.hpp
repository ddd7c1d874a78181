// The house style the figures share (figures.cpp, estimate_figures.cpp): titles, the colour
// map, numbers as gnuplot reads them. Private to hemivem::app.
#pragma once

#include <array>
#include <cstddef>
#include <functional>
#include <string>
#include <vector>

#include <hemivem/app/outputs.hpp>

namespace hemivem::app::detail {

/// A number as gnuplot reads it back exactly.
std::string num(double v);

/// `text` with every word that is a file path (a word with a '/' that starts with '/', '.' or
/// '~' or ends in a file name with an extension) cut to its file name: a title names a mesh
/// file, not the folders it was found in.
std::string without_folders(const std::string& text);

/// `text` cut to 160 bytes (at a character boundary of UTF-8) followed by "...", when longer.
std::string cut_title(std::string text);

/// `t` with its '"' and '\\' escaped, a newline as \\n (a line break in the figure) and other
/// control characters as spaces, for a double-quoted gnuplot string.
std::string double_quoted_escape(const std::string& t);

/// The title of a solve's figure as a gnuplot string: what it shows on the first line, the
/// scene and the mesh on the second (a long scene name would not fit on one).
std::string solve_title(const std::string& what, const RunInfo& info);

/// A perceptually uniform colour map (matplotlib's viridis, sampled at nine points) as a
/// gnuplot palette.
inline constexpr const char* kViridis =
    "set palette defined (0 '#440154', 1 '#472d7b', 2 '#3b528b', 3 '#2c728e', 4 '#21918c', 5 '#28ae80', "
    "6 '#5ec962', 7 '#addc30', 8 '#fde725')\n";

/// The edges of a plane's mesh that its figures draw, each visited as its two end vertices: the
/// mesh's own, or the whole mesh's gathered from the processes' pieces (WholeOfPieces).
struct PlaneEdges {
  using Visit = std::function<void(int, int)>;
  std::size_t count = 0;                       ///< the mesh's edges
  std::function<void(const Visit&)> boundary;  ///< visits its boundary edges, in order
  std::function<void(const Visit&)> every;     ///< visits every edge, in order
};
PlaneEdges plane_edges(const Mesh& mesh);
/// Those of `whole` (size.facets, boundary, edges); visiting every edge where they were not
/// gathered (WholeOfPieces::edges empty, a mesh with edges) is an InternalError.
PlaneEdges plane_edges(const WholeOfPieces& whole);

/// The boundary edges of `edges` whose both ends are contact nodes of `solution` (a mesh of
/// `vertices` vertices), as vertex pairs: contact_lines of outputs.hpp.
std::vector<std::array<int, 2>> contact_lines(int vertices, const PlaneEdges& edges, const ContactSolution& solution);

}  // namespace hemivem::app::detail
