// Reduced problems as files, to compare hemivem's minimizers with other solvers on
// identical input. A folder holds:
//
//   S.mtx            Matrix Market, "array real general|symmetric" (written) or
//                    "coordinate real general|symmetric" (also read)
//   c.txt, w.txt     one number per line (n lines)
//   law.txt          the contact law (format below); in the coordinate-wise form law 0, and
//                    law1.txt, law2.txt ... the others
//   problem.txt      "format 3"; "constraint none|one-sided|box|bilateral" (uniform form) or
//                    "form coordinate-wise", "laws L" and "groups K" (K > 0 only, read as 0
//                    when absent); "uniqueness_margin X" (all optional
//                    when read: without them the uniform form with the box constraint)
//   g.txt            the gaps, one per line (uniform form)
//   coordinates.txt  "law lower upper" per coordinate, bounds numbers or inf / -inf
//                    (coordinate-wise form: friction, docs/friction.md)
//   groups.txt       "first second" per group (coordinates from 0 whose law acts on their
//                    norm: a solid's friction; written when K > 0)
//
// Format 1 (no "format" line) is the uniform form and format 2 has no groups; both are still read.
//
// law.txt: '#' comments, then "name NAME", "breakpoints b0 b1 ..." (possibly none), and one
// line "j1 c0 c1 ..." and one line "j2 c0 c1 ..." per piece, in piece order (coefficients
// lowest degree first; j = j1 - j2).
#pragma once

#include <filesystem>
#include <memory>

#include <hemivem/contact_law.hpp>
#include <hemivem/reduced_problem.hpp>

namespace hemivem {

/// The version of the folder format written (the "format" line of problem.txt).
inline constexpr int reduced_format_version = 3;

/// Writes the folder (created if needed) as one transaction (hemivem/support/output_folder.hpp):
/// the whole set is written beside it, every write checked, and then replaces the files of a
/// reduced problem the folder held (either form, every law file) at once; other files stay. A
/// failed write leaves the previous set. Every law must be a PiecewisePolynomialLaw (all
/// shipped laws are). Throws InputError for arrays whose sizes do not fit (check_sizes) and a
/// WriteError (an InputError) for a failed write.
void write_reduced_problem(const std::filesystem::path& folder, const ReducedProblem& problem);

/// Reads a folder written by write_reduced_problem (or by hand in the same format). `law`,
/// when given, replaces law.txt (law 0; the file may then be absent). Throws InputError naming the
/// file and line of any defect (sizes that disagree, non-finite numbers, an S that is not
/// square or not symmetric to 1e-12 relative, negative gaps, non-positive weights).
/// The uniqueness margin is always computed from the problem as read (measure_uniqueness,
/// hemivem/uniqueness.hpp); a "uniqueness_margin" in problem.txt that disagrees with it (beyond
/// its round-off bound) is an InputError at its line. With `law` given the file's margin
/// belongs to another law and is ignored.
ReducedProblem read_reduced_problem(const std::filesystem::path& folder,
                                    std::shared_ptr<const ContactLaw> law = nullptr);

/// The law file format on its own.
void write_law(const std::filesystem::path& file, const ContactLaw& law);
std::shared_ptr<const ContactLaw> read_law(const std::filesystem::path& file);

}  // namespace hemivem
