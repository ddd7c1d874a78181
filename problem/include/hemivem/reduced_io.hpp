// Reduced problems as files, to compare hemivem's minimizers with other solvers on
// identical input. A folder holds:
//
//   S.mtx        Matrix Market, "array real general|symmetric" (written) or
//                "coordinate real general|symmetric" (also read)
//   c.txt        one number per line (N1 lines); likewise w.txt and g.txt
//   law.txt      the contact law (format below)
//   problem.txt  "constraint none|one-sided|box" and "uniqueness_margin X" (optional when read)
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

/// Writes the folder (created if needed); each file is written to a temporary name and
/// renamed. The law must be a PiecewisePolynomialLaw (all shipped laws are).
void write_reduced_problem(const std::filesystem::path& folder, const ReducedProblem& problem);

/// Reads a folder written by write_reduced_problem (or by hand in the same format). `law`,
/// when given, replaces law.txt (which may then be absent). Throws InputError naming the
/// file and line of any defect (sizes that disagree, non-finite numbers, an S that is not
/// square or not symmetric to 1e-12 relative, negative gaps, non-positive weights).
ReducedProblem read_reduced_problem(const std::filesystem::path& folder,
                                    std::shared_ptr<const ContactLaw> law = nullptr);

/// The law file format on its own.
void write_law(const std::filesystem::path& file, const ContactLaw& law);
std::shared_ptr<const ContactLaw> read_law(const std::filesystem::path& file);

}  // namespace hemivem
