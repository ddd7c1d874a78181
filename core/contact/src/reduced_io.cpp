#include <hemivem/support/atomic_file.hpp>
#include <hemivem/support/output_folder.hpp>
#include <hemivem/error.hpp>
#include <hemivem/contact/piecewise_law.hpp>
#include <hemivem/contact/reduced_io.hpp>
#include <hemivem/uniqueness.hpp>

#include <charconv>
#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <optional>
#include <sstream>

namespace hemivem {

namespace fs = std::filesystem;

namespace {

std::string shortest(double v) {
  char buf[32];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

void write_file(const fs::path& path, const std::function<void(std::ostream&)>& body) {
  write_file_atomically(path, body);
}

// Lines of a text file with their numbers, comments ('#' or '%' first) and blanks skipped.
struct Line {
  int number;
  std::vector<std::string> tokens;
};

std::vector<Line> read_lines(const fs::path& path, bool percent_comments) {
  std::ifstream in(path);
  if (!in) throw InputError("cannot open the file", path.string());
  std::vector<Line> out;
  std::string s;
  int n = 0;
  while (std::getline(in, s)) {
    ++n;
    if (!s.empty() && s.back() == '\r') s.pop_back();
    const auto first = s.find_first_not_of(" \t");
    if (first == std::string::npos) continue;
    if (s[first] == '#' || (percent_comments && s[first] == '%')) {
      if (n == 1 && percent_comments && s.rfind("%%MatrixMarket", 0) == 0) out.push_back({n, {s}});
      continue;
    }
    std::istringstream ss(s);
    Line l{n, {}};
    for (std::string t; ss >> t;) l.tokens.push_back(t);
    out.push_back(std::move(l));
  }
  return out;
}

double number(const std::string& token, const fs::path& path, int line, const std::string& what) {
  double v = 0.0;
  const auto r = std::from_chars(token.data(), token.data() + token.size(), v);
  if (r.ec != std::errc() || r.ptr != token.data() + token.size())
    throw InputError(what + " '" + token + "' is not a number", path.string() + ":" + std::to_string(line));
  if (!std::isfinite(v)) throw InputError(what + " '" + token + "' is not finite", path.string() + ":" + std::to_string(line));
  return v;
}

long integer(const std::string& token, const fs::path& path, int line, const std::string& what) {
  long v = 0;
  const auto r = std::from_chars(token.data(), token.data() + token.size(), v);
  if (r.ec != std::errc() || r.ptr != token.data() + token.size() || v < 0)
    throw InputError(what + " '" + token + "' is not a non-negative integer", path.string() + ":" + std::to_string(line));
  return v;
}

/// One number per line; with `allow_infinity` the token "inf" reads as +inf.
Eigen::VectorXd read_vector(const fs::path& path, const std::string& what, bool allow_infinity = false) {
  const auto lines = read_lines(path, false);
  Eigen::VectorXd v(static_cast<Eigen::Index>(lines.size()));
  for (std::size_t i = 0; i < lines.size(); ++i) {
    if (lines[i].tokens.size() != 1)
      throw InputError("expected one number per line, found " + std::to_string(lines[i].tokens.size()),
                       path.string() + ":" + std::to_string(lines[i].number));
    const std::string& token = lines[i].tokens[0];
    v(static_cast<Eigen::Index>(i)) = allow_infinity && token == "inf" ? std::numeric_limits<double>::infinity()
                                                                        : number(token, path, lines[i].number, what);
  }
  return v;
}

Eigen::MatrixXd read_matrix_market(const fs::path& path) {
  const auto lines = read_lines(path, true);
  if (lines.empty() || lines[0].tokens.size() != 1 || lines[0].tokens[0].rfind("%%MatrixMarket", 0) != 0)
    throw InputError("expected a Matrix Market header '%%MatrixMarket matrix array|coordinate real general|symmetric'",
                     path.string() + ":1");
  std::istringstream hs(lines[0].tokens[0]);
  std::string banner, object, format, field, symmetry;
  hs >> banner >> object >> format >> field >> symmetry;
  auto lower = [](std::string s) {
    for (auto& ch : s) ch = static_cast<char>(std::tolower(static_cast<unsigned char>(ch)));
    return s;
  };
  object = lower(object), format = lower(format), field = lower(field), symmetry = lower(symmetry);
  const std::string where1 = path.string() + ":" + std::to_string(lines[0].number);
  if (object != "matrix" || (format != "array" && format != "coordinate") || (field != "real" && field != "double" && field != "integer") ||
      (symmetry != "general" && symmetry != "symmetric"))
    throw InputError("unsupported Matrix Market header (expected matrix, array|coordinate, real, general|symmetric)", where1);
  if (lines.size() < 2) throw InputError("the size line is missing", path.string());
  const Line& sz = lines[1];
  const std::string wsz = path.string() + ":" + std::to_string(sz.number);
  const bool array = format == "array";
  if (sz.tokens.size() != (array ? 2u : 3u)) throw InputError(array ? "expected 'rows cols'" : "expected 'rows cols entries'", wsz);
  const long rows = integer(sz.tokens[0], path, sz.number, "row count");
  const long cols = integer(sz.tokens[1], path, sz.number, "column count");
  if (rows != cols) throw InputError("S must be square, got " + std::to_string(rows) + " x " + std::to_string(cols), wsz);
  if (rows > 50000) throw InputError("S of size " + std::to_string(rows) + " is too large for a dense reduced problem", wsz);
  const bool sym = symmetry == "symmetric";
  Eigen::MatrixXd S = Eigen::MatrixXd::Zero(rows, cols);
  const std::size_t expected = array ? static_cast<std::size_t>(sym ? rows * (rows + 1) / 2 : rows * cols)
                                     : static_cast<std::size_t>(integer(sz.tokens[2], path, sz.number, "entry count"));
  if (lines.size() - 2 != expected)
    throw InputError("expected " + std::to_string(expected) + " entries after the size line, found " +
                         std::to_string(lines.size() - 2),
                     wsz);
  long r = 0, c = 0;
  for (std::size_t k = 2; k < lines.size(); ++k) {
    const Line& l = lines[k];
    const std::string where = path.string() + ":" + std::to_string(l.number);
    if (array) {
      if (l.tokens.size() != 1) throw InputError("expected one value per line", where);
      const double v = number(l.tokens[0], path, l.number, "entry");
      S(r, c) = v;
      if (sym) S(c, r) = v;
      if (++r == rows) r = sym ? ++c : (++c, 0);
    } else {
      if (l.tokens.size() != 3) throw InputError("expected 'row col value'", where);
      const long i = integer(l.tokens[0], path, l.number, "row"), j = integer(l.tokens[1], path, l.number, "column");
      if (i < 1 || i > rows || j < 1 || j > cols)
        throw InputError("entry (" + l.tokens[0] + ", " + l.tokens[1] + ") outside the " + std::to_string(rows) + " x " +
                             std::to_string(cols) + " matrix (indices are 1-based)",
                         where);
      const double v = number(l.tokens[2], path, l.number, "entry");
      S(i - 1, j - 1) = v;
      if (sym) S(j - 1, i - 1) = v;
    }
  }
  const double asym = (S - S.transpose()).cwiseAbs().maxCoeff();
  if (asym > 1e-12 * std::max(1.0, S.cwiseAbs().maxCoeff()))
    throw InputError("S is not symmetric (largest |S - S^T| entry " + shortest(asym) + ")", path.string());
  return S;
}

/// law.txt for law 0, lawK.txt for law K of a coordinate-wise problem.
std::string law_file_name(int k) { return k == 0 ? std::string("law.txt") : "law" + std::to_string(k) + ".txt"; }

/// A bound: a number, or inf / -inf.
std::string bound_text(double v) {
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  return shortest(v);
}
double bound(const std::string& token, const fs::path& path, int line, const std::string& what) {
  if (token == "inf") return std::numeric_limits<double>::infinity();
  if (token == "-inf") return -std::numeric_limits<double>::infinity();
  return number(token, path, line, what);
}

}  // namespace

void write_law(const fs::path& file, const ContactLaw& law) {
  const auto* pl = dynamic_cast<const PiecewisePolynomialLaw*>(&law);
  if (!pl) throw InputError("only piecewise-polynomial laws can be written", file.string());
  write_file(file, [&](std::ostream& out) {
    out << "# hemivem contact law: j = j1 - j2 on the pieces (-inf, b0], (b0, b1], ..., (b_last, inf)\n"
        << "# coefficients lowest degree first\n"
        << "name " << law.name() << "\nbreakpoints";
    for (double b : pl->breakpoints()) out << ' ' << shortest(b);
    out << '\n';
    const auto j1 = pl->pieces(LawPart::j1), j2 = pl->pieces(LawPart::j2);
    for (std::size_t k = 0; k < j1.size(); ++k) {
      out << "j1";
      for (double c : j1[k]) out << ' ' << shortest(c);
      out << "\nj2";
      for (double c : j2[k]) out << ' ' << shortest(c);
      out << '\n';
    }
  });
}

std::shared_ptr<const ContactLaw> read_law(const fs::path& file) {
  const auto lines = read_lines(file, false);
  std::string name;
  std::vector<double> breaks;
  std::vector<Polynomial> j1, j2;
  bool have_breaks = false;
  for (const auto& l : lines) {
    const std::string where = file.string() + ":" + std::to_string(l.number);
    const std::string& key = l.tokens[0];
    if (key == "name") {
      if (l.tokens.size() != 2) throw InputError("expected 'name NAME'", where);
      name = l.tokens[1];
    } else if (key == "breakpoints") {
      have_breaks = true;
      for (std::size_t i = 1; i < l.tokens.size(); ++i) breaks.push_back(number(l.tokens[i], file, l.number, "breakpoint"));
    } else if (key == "j1" || key == "j2") {
      Polynomial p;
      for (std::size_t i = 1; i < l.tokens.size(); ++i) p.push_back(number(l.tokens[i], file, l.number, "coefficient"));
      if (p.empty()) throw InputError("a piece needs at least one coefficient", where);
      (key == "j1" ? j1 : j2).push_back(std::move(p));
    } else {
      throw InputError("unknown key '" + key + "'; expected name, breakpoints, j1 or j2", where);
    }
  }
  if (name.empty()) throw InputError("the line 'name NAME' is missing", file.string());
  if (!have_breaks) throw InputError("the line 'breakpoints ...' is missing", file.string());
  try {
    return std::make_shared<PiecewisePolynomialLaw>(name, breaks, j1, j2);
  } catch (const InputError& e) {
    throw InputError(e.detail(), file.string());
  }
}

namespace {

// The files of a reduced problem in `folder` (an empty staging folder).
void write_reduced_files(const fs::path& folder, const ReducedProblem& p, const std::optional<UniformForm>& uniform) {
  const bool coordinatewise = !uniform;
  const Eigen::Index n = p.size();
  write_file(folder / "S.mtx", [&](std::ostream& out) {
    out << "%%MatrixMarket matrix array real symmetric\n% hemivem reduced problem: S (lower triangle, column by column)\n"
        << n << ' ' << n << '\n';
    for (Eigen::Index j = 0; j < n; ++j)
      for (Eigen::Index i = j; i < n; ++i) out << shortest(p.S(i, j)) << '\n';
  });
  auto vec = [&](const char* name, const Eigen::VectorXd& v) {
    write_file(folder / name, [&](std::ostream& out) {
      for (Eigen::Index i = 0; i < v.size(); ++i) out << shortest(v(i)) << '\n';
    });
  };
  vec("c.txt", p.c);
  vec("w.txt", p.w);
  for (int k = 0; k < p.num_laws(); ++k) write_law(folder / law_file_name(k), p.law_by_number(k));
  if (coordinatewise) {
    write_file(folder / "coordinates.txt", [&](std::ostream& out) {
      out << "# law lower upper (per coordinate; law k is law.txt for k = 0, lawK.txt otherwise)\n";
      for (Eigen::Index i = 0; i < n; ++i)
        out << p.law_index(i) << ' ' << bound_text(p.lo(i)) << ' ' << bound_text(p.hi(i)) << '\n';
    });
    if (!p.groups.empty())
      write_file(folder / "groups.txt", [&](std::ostream& out) {
        out << "# first second (coordinates, from 0, whose law acts on their Euclidean norm)\n";
        for (const CoordinateGroup& g : p.groups) out << g.first << ' ' << g.second << '\n';
      });
  } else {
    vec("g.txt", uniform->g);
  }
  write_file(folder / "problem.txt", [&](std::ostream& out) {
    out << "# hemivem reduced problem: min 1/2 a^T S a - c^T a + sum w_i j_i(a_i) over the constraint set\n"
        << "format " << reduced_format_version << '\n';
    if (coordinatewise) out << "form coordinate-wise\nlaws " << p.num_laws() << '\n';
    if (!p.groups.empty()) out << "groups " << p.groups.size() << '\n';
    if (!coordinatewise) out << "constraint " << to_string(uniform->constraint) << '\n';
    if (!std::isnan(p.uniqueness_margin)) out << "uniqueness_margin " << shortest(p.uniqueness_margin) << '\n';
  });
}

}  // namespace

void write_reduced_problem(const fs::path& folder, const ReducedProblem& p) {
  check_sizes(p, folder.string());
  const std::optional<UniformForm> uniform = p.uniform_form();
  std::error_code ec;
  if (folder.has_parent_path()) fs::create_directories(folder.parent_path(), ec);
  if (ec) throw InputError("cannot create the folder: " + ec.message(), folder.parent_path().string());
  // one transaction: the files of either form and every law file the folder holds are this
  // writer's; the new set replaces them at once, other files stay
  std::vector<std::string> owned{"S.mtx", "c.txt", "w.txt", "g.txt", "coordinates.txt", "groups.txt", "problem.txt"};
  for (int k = 0; k < p.num_laws() || fs::exists(folder / law_file_name(k), ec); ++k) owned.push_back(law_file_name(k));
  OutputTransaction tx(folder, owned);
  tx.stage([&](const fs::path& staging) { write_reduced_files(staging, p, uniform); });
  tx.commit();
}

namespace {

/// What problem.txt says (all optional: the uniform form with the box constraint).
struct ProblemHeader {
  bool coordinatewise = false;
  long laws = 1;
  long groups = 0;
  ConstraintKind constraint = ConstraintKind::box;
  double uniqueness_margin = std::numeric_limits<double>::quiet_NaN();
  std::string margin_where;  // file:line of the margin, when given
};

ProblemHeader read_problem_header(const fs::path& file) {
  ProblemHeader h;
  if (!fs::exists(file)) return h;
  bool have_constraint = false;
  for (const auto& l : read_lines(file, false)) {
    const std::string where = file.string() + ":" + std::to_string(l.number);
    if (l.tokens.size() != 2) throw InputError("expected 'key value'", where);
    const std::string& key = l.tokens[0];
    if (key == "format") {
      const long v = integer(l.tokens[1], file, l.number, "format");
      if (v < 1 || v > reduced_format_version)
        throw InputError("format " + l.tokens[1] + " is not one this program reads (1 to " +
                             std::to_string(reduced_format_version) + ")",
                         where);
    } else if (key == "form") {
      if (l.tokens[1] != "coordinate-wise" && l.tokens[1] != "uniform")
        throw InputError("unknown form '" + l.tokens[1] + "'; expected uniform or coordinate-wise", where);
      h.coordinatewise = l.tokens[1] == "coordinate-wise";
    } else if (key == "laws") {
      h.laws = integer(l.tokens[1], file, l.number, "number of laws");
      if (h.laws < 1 || h.laws > 100) throw InputError("expected 1 to 100 laws, got " + l.tokens[1], where);
    } else if (key == "groups") {
      h.groups = integer(l.tokens[1], file, l.number, "number of groups");
      if (h.groups < 0) throw InputError("expected a number of groups >= 0, got " + l.tokens[1], where);
    } else if (key == "constraint") {
      try {
        h.constraint = constraint_kind_from_string(l.tokens[1]);
      } catch (const InputError& e) {
        throw InputError(e.detail(), where);
      }
      have_constraint = true;
    } else if (key == "uniqueness_margin") {
      h.uniqueness_margin = l.tokens[1] == "-inf" ? -std::numeric_limits<double>::infinity()
                                                  : number(l.tokens[1], file, l.number, "margin");
      h.margin_where = where;
    } else {
      throw InputError("unknown key '" + key + "'; expected format, form, laws, groups, constraint or uniqueness_margin", where);
    }
  }
  if (h.coordinatewise && have_constraint)
    throw InputError("a coordinate-wise problem has its bounds in coordinates.txt, not a constraint", file.string());
  if (!h.coordinatewise && h.laws != 1) throw InputError("several laws need 'form coordinate-wise'", file.string());
  if (!h.coordinatewise && h.groups > 0) throw InputError("groups need 'form coordinate-wise'", file.string());
  return h;
}

/// coordinates.txt: the law index and the bounds of each of the n coordinates into *p.
void read_coordinates(const fs::path& file, Eigen::Index n, long laws, ReducedProblem* p) {
  const auto lines = read_lines(file, false);
  if (static_cast<Eigen::Index>(lines.size()) != n)
    throw InputError("has " + std::to_string(lines.size()) + " lines; S is " + std::to_string(n) + " x " + std::to_string(n),
                     file.string());
  p->law_index.resize(n);
  p->lo.resize(n);
  p->hi.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const Line& l = lines[static_cast<std::size_t>(i)];
    const std::string where = file.string() + ":" + std::to_string(l.number);
    if (l.tokens.size() != 3) throw InputError("expected 'law lower upper'", where);
    const long k = integer(l.tokens[0], file, l.number, "law");
    if (k >= laws) throw InputError("law " + l.tokens[0] + " out of range: problem.txt has " + std::to_string(laws) + " laws", where);
    p->law_index(i) = static_cast<int>(k);
    p->lo(i) = bound(l.tokens[1], file, l.number, "lower bound");
    p->hi(i) = bound(l.tokens[2], file, l.number, "upper bound");
    if (!(p->lo(i) <= p->hi(i))) throw InputError("lower bound " + l.tokens[1] + " above upper bound " + l.tokens[2], where);
  }
}

/// groups.txt: `count` lines "first second" (coordinates from 0) into p->groups, checked by
/// check_sizes with the rest.
void read_groups(const fs::path& file, long count, Eigen::Index n, ReducedProblem* p) {
  const auto lines = read_lines(file, false);
  if (static_cast<long>(lines.size()) != count)
    throw InputError("has " + std::to_string(lines.size()) + " lines; problem.txt says groups " + std::to_string(count),
                     file.string());
  for (const Line& l : lines) {
    const std::string where = file.string() + ":" + std::to_string(l.number);
    if (l.tokens.size() != 2) throw InputError("expected 'first second'", where);
    const long a = integer(l.tokens[0], file, l.number, "coordinate"), b = integer(l.tokens[1], file, l.number, "coordinate");
    if (a < 0 || a >= n || b < 0 || b >= n || a == b)
      throw InputError("expected two distinct coordinates in 0.." + std::to_string(n - 1), where);
    p->groups.push_back({a, b});
  }
  try {
    check_sizes(*p, file.string());
  } catch (const InputError& e) {
    throw InputError(e.detail(), file.string());
  }
}

/// The margin of p, computed. A margin in problem.txt must be that of the problem as read (an
/// InputError at its line otherwise); with a replaced law it belongs to another law and is
/// not used.
void settle_margin(ReducedProblem& p, const ProblemHeader& h, bool replaced_law) {
  const UniquenessMargin m = measure_uniqueness(p);
  if (!replaced_law && !std::isnan(h.uniqueness_margin) && !margin_agrees(h.uniqueness_margin, m))
    throw InputError("uniqueness_margin " + shortest(h.uniqueness_margin) + " is not the margin of this problem: " +
                         "lambda_min(S - alpha_j W) = " + shortest(m.margin) + " (round-off bound " +
                         shortest(m.roundoff) + ")",
                     h.margin_where);
  p.uniqueness_margin = m.margin;
  p.uniqueness_roundoff = m.roundoff;
}

}  // namespace

ReducedProblem read_reduced_problem(const fs::path& folder, std::shared_ptr<const ContactLaw> law) {
  if (!fs::is_directory(folder)) throw InputError("not a folder", folder.string());
  // problem.txt first: the form says which files follow
  const ProblemHeader h = read_problem_header(folder / "problem.txt");
  ReducedProblem p;
  p.S = read_matrix_market(folder / "S.mtx");
  p.c = read_vector(folder / "c.txt", "c");
  p.w = read_vector(folder / "w.txt", "w");
  Eigen::VectorXd g;
  if (!h.coordinatewise) g = read_vector(folder / "g.txt", "g", true);
  const Eigen::Index n = p.S.rows();
  std::vector<std::pair<const char*, const Eigen::VectorXd*>> vectors{{"c.txt", &p.c}, {"w.txt", &p.w}};
  if (!h.coordinatewise) vectors.push_back({"g.txt", &g});
  for (const auto& [name, v] : vectors)
    if (v->size() != n)
      throw InputError("has " + std::to_string(v->size()) + " numbers; S is " + std::to_string(n) + " x " + std::to_string(n),
                       (folder / name).string());
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!(p.w(i) > 0.0)) throw InputError("weight " + shortest(p.w(i)) + " must be > 0", (folder / "w.txt").string() + ": entry " + std::to_string(i + 1));
  }
  const bool replaced_law = law != nullptr;
  if (!law) law = read_law(folder / "law.txt");
  if (h.coordinatewise) {
    p.laws.push_back(std::move(law));
    for (long k = 1; k < h.laws; ++k) p.laws.push_back(read_law(folder / law_file_name(static_cast<int>(k))));
    read_coordinates(folder / "coordinates.txt", n, h.laws, &p);
    if (h.groups > 0) read_groups(folder / "groups.txt", h.groups, n, &p);
    settle_margin(p, h, replaced_law);
    return p;
  }
  // negative gaps (an obstacle pressed in) and +inf (a node that cannot touch it) bound a_i <= g_i
  // from one side only; the box |a_i| <= g_i needs 0 <= g_i < inf
  if (h.constraint == ConstraintKind::box)
    for (Eigen::Index i = 0; i < n; ++i)
      if (!(g(i) >= 0.0 && std::isfinite(g(i))))
        throw InputError("gap " + shortest(g(i)) + " must be finite and >= 0 with the box constraint",
                         (folder / "g.txt").string() + ": entry " + std::to_string(i + 1));
  p = ReducedProblem::uniform(std::move(p.S), std::move(p.c), std::move(p.w), std::move(law), h.constraint, g);
  settle_margin(p, h, replaced_law);
  return p;
}

}  // namespace hemivem
