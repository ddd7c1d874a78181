#include "test_support.hpp"

#include <algorithm>

namespace hemivem::test {

std::filesystem::path shared_dir() {
  std::filesystem::path p = HEMIVEM_SHARED_DIR;
  std::error_code ec;
  if (std::filesystem::is_directory(p / "meshes", ec)) return std::filesystem::canonical(p);
  return {};
}

std::vector<std::filesystem::path> shared_meshes() {
  std::vector<std::filesystem::path> out;
  const auto dir = shared_dir();
  if (dir.empty()) return out;
  for (const auto& entry : std::filesystem::directory_iterator(dir / "meshes"))
    if (entry.path().extension() == ".poly2d") out.push_back(entry.path());
  std::sort(out.begin(), out.end());
  return out;
}

std::filesystem::path data_dir() { return HEMIVEM_TEST_DATA_DIR; }

std::filesystem::path scenes_dir() { return data_dir().parent_path().parent_path() / "scenes"; }

}  // namespace hemivem::test

#include <Eigen/SparseCholesky>
#include <gtest/gtest.h>

namespace hemivem::test {

Eigen::VectorXd solve(const LinearSystem& system) {
  Eigen::SimplicialLLT<SparseMatrix> llt(system.A);
  EXPECT_EQ(llt.info(), Eigen::Success) << "sparse Cholesky failed";
  const Eigen::VectorXd uf = llt.solve(system.b);
  return system.dofs.expand(uf);
}

double max_relative_nodal_error(const Mesh& mesh, const Eigen::VectorXd& u, const VectorField& exact) {
  double err = 0.0, ref = 0.0;
  for (int v = 0; v < mesh.num_vertices(); ++v) {
    const Vec2 e = exact(mesh.vertex(v));
    err = std::max(err, (u.segment<2>(2 * v) - e).cwiseAbs().maxCoeff());
    ref = std::max(ref, e.cwiseAbs().maxCoeff());
  }
  return err / ref;
}

DirichletCondition dirichlet_everywhere(const Mesh& mesh, VectorField u) {
  return {mesh.boundary_edges(), std::move(u), {true, true}};
}

bool identical(const Mesh& a, const Mesh& b) {
  if (a.num_vertices() != b.num_vertices() || a.elements() != b.elements()) return false;
  for (int v = 0; v < a.num_vertices(); ++v)
    if (!(a.vertex(v).x() == b.vertex(v).x() && a.vertex(v).y() == b.vertex(v).y())) return false;
  return true;
}

namespace {

// What `part` says of the InputError that f throws ("" when it throws none).
std::string of_input_error(const std::function<void()>& f, std::string (*part)(const InputError&)) {
  try {
    f();
  } catch (const InputError& e) {
    return part(e);
  }
  return "";
}

}  // namespace

std::string input_error_of(const std::function<void()>& f) {
  return of_input_error(f, [](const InputError& e) { return std::string(e.what()); });
}

std::string input_error_key(const std::function<void()>& f) {
  return of_input_error(f, [](const InputError& e) { return std::string(e.where()); });
}

}  // namespace hemivem::test

#include <hemivem/linear_backends.hpp>
#include <hemivem/mesh/generators.hpp>
#include <hemivem/scene/example.hpp>
#include <hemivem/scene/scene.hpp>
#include <hemivem/error.hpp>

namespace hemivem::test {

std::unique_ptr<Example> example(const std::string& kind, int n, const std::function<void(ContactProblem&)>& change) {
  auto ex = std::make_unique<Example>();
  ex->mesh = make_mesh(kind, n, Rectangle{}, 5);
  ex->problem = example_4_1(ex->mesh);
  if (change) change(ex->problem);
  ex->system = assemble(ex->problem.elasticity);
  ex->boundary = make_contact_boundary(ex->mesh, ex->problem.parts[0].facets, ex->system.dofs, ex->problem.parts[0].gap);
  FactorizationOptions fo;
  fo.engine = "eigen";
  ex->condensation = std::make_unique<Condensation>(ex->system, ex->boundary, make_factorization(fo), ex->problem.parts[0].law,
                                                    ex->problem.parts[0].constraint, ex->problem.parts[0].friction);
  return ex;
}

}  // namespace hemivem::test

#include <sys/wait.h>
#include <unistd.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <sstream>

namespace hemivem::test {

std::string slurp(const std::filesystem::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

std::vector<unsigned char> from_base64(const std::string& text) {
  static const std::string digits = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::vector<unsigned char> out;
  std::uint32_t word = 0;
  int bits = 0;
  for (char c : text) {
    if (c == '=') break;
    const auto at = digits.find(c);
    if (at == std::string::npos) continue;
    word = (word << 6) | static_cast<std::uint32_t>(at);
    bits += 6;
    if (bits >= 8) {
      bits -= 8;
      out.push_back(static_cast<unsigned char>((word >> bits) & 0xFF));
    }
  }
  return out;
}

std::string scene_refusal(const std::string& name, const std::string& from, const std::string& to) {
  std::string text = slurp(scenes_dir() / name);
  const auto at = text.find(from);
  if (at == std::string::npos) return "scene text not found: " + from;
  text.replace(at, from.size(), to);
  try {
    parse_scene_string(text, name);
  } catch (const InputError& e) {
    return e.what();
  }
  return "accepted";
}

std::filesystem::path scratch(const std::string& name) {
  const auto p = std::filesystem::temp_directory_path() / ("hemivem-test-" + std::to_string(::getpid()) + "-" + name);
  std::filesystem::remove_all(p);
  return p;
}

CommandRun run_command(const std::string& command) {
  const auto err = std::filesystem::temp_directory_path() / ("hemivem-test-stderr-" + std::to_string(::getpid()) + ".txt");
  CommandRun r;
  FILE* p = popen((command + " 2>" + err.string()).c_str(), "r");
  if (!p) return r;
  std::array<char, 4096> buf{};
  while (std::size_t n = std::fread(buf.data(), 1, buf.size(), p)) r.out.append(buf.data(), n);
  const int status = pclose(p);
  r.code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  r.err = slurp(err);
  std::filesystem::remove(err);
  return r;
}

CommandRun run_hemivem(const std::string& args) { return run_command(std::string(HEMIVEM_BINARY) + " " + args); }

}  // namespace hemivem::test

#include <fstream>
#include <iterator>
#include <set>

namespace hemivem::test {

std::ostream& operator<<(std::ostream& os, const Malformed& m) { return os << m.file; }

void expect_rejected_at_its_line(const std::filesystem::path& dir, const Malformed& c,
                                 const std::function<void(const std::filesystem::path&)>& read) {
  const std::filesystem::path file = dir / c.file;
  ASSERT_TRUE(std::filesystem::is_regular_file(file)) << file;
  try {
    read(file);
    FAIL() << "read without error: " << file;
  } catch (const InputError& e) {
    const std::string what = e.what();
    const std::string where = file.string() + ":" + std::to_string(c.line);
    EXPECT_EQ(e.where(), where) << what;
    EXPECT_EQ(what.rfind(where + ": ", 0), 0u) << what;
    EXPECT_NE(what.find(c.file), std::string::npos) << what;
    EXPECT_NE(what.find(c.fragment), std::string::npos) << what;
    const auto* mesh_error = dynamic_cast<const MeshError*>(&e);
    if (c.kind == MalformedKind::mesh) {
      ASSERT_NE(mesh_error, nullptr) << "expected a MeshError: " << what;
      EXPECT_EQ(mesh_error->element(), c.element) << what;
    } else {
      EXPECT_EQ(mesh_error, nullptr) << "expected a plain InputError: " << what;
    }
  }
}

void expect_table_covers_corpus(const std::filesystem::path& dir, const std::string& extension,
                                std::span<const Malformed> table) {
  std::set<std::string> in_table;
  for (const auto& c : table) in_table.insert(c.file);
  EXPECT_EQ(in_table.size(), table.size()) << "a file is listed twice";
  std::set<std::string> on_disk;
  for (const auto& e : std::filesystem::directory_iterator(dir))
    if (e.path().extension() == extension) on_disk.insert(e.path().filename().string());
  EXPECT_EQ(on_disk, in_table);
  std::ifstream readme(dir / "README.md");
  ASSERT_TRUE(readme) << dir / "README.md" << " is missing";
  const std::string text((std::istreambuf_iterator<char>(readme)), std::istreambuf_iterator<char>());
  for (const auto& c : table) {
    EXPECT_NE(text.find(std::string("`") + c.file + "`"), std::string::npos) << c.file << " is not in the README";
    EXPECT_NE(text.find(c.fragment), std::string::npos) << "the README lacks the fragment of " << c.file;
  }
}

std::string corpus_test_name(const char* file, const std::string& prefix) {
  std::string name = std::filesystem::path(file).stem().string();
  std::replace(name.begin(), name.end(), '-', '_');
  std::replace(name.begin(), name.end(), '.', '_');
  return prefix + name;
}

}  // namespace hemivem::test

#include <hemivem/contact/piecewise_law.hpp>

#include <limits>
#include <random>

namespace hemivem::test {

ReducedProblem frictional_solid_problem(int nodes, std::shared_ptr<const ContactLaw> normal,
                                        std::shared_ptr<const ContactLaw> friction, unsigned seed, double load) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const int n = 3 * nodes;
  Eigen::MatrixXd B(n, n);
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j) B(i, j) = unit(gen);
  Eigen::MatrixXd S = 2.0 * B * B.transpose() / n;
  S.diagonal().array() += 100.0;
  Eigen::VectorXd c(n), w(n), g(n);
  for (int i = 0; i < n; ++i) c(i) = load * unit(gen);
  for (int k = 0; k < nodes; ++k) {
    const double wk = 1.0 + 0.5 * unit(gen);
    w(k) = w(nodes + 2 * k) = w(nodes + 2 * k + 1) = wk;
    g(k) = 0.01 * (1.0 + unit(gen));
  }
  ReducedProblem p;
  p.S = std::move(S);
  p.c = std::move(c);
  p.w = std::move(w);
  p.laws = {std::move(normal), std::move(friction)};
  p.law_index = Eigen::VectorXi::Ones(n);
  p.law_index.head(nodes).setZero();
  p.lo = Eigen::VectorXd::Constant(n, -std::numeric_limits<double>::infinity());
  p.hi = Eigen::VectorXd::Constant(n, std::numeric_limits<double>::infinity());
  p.hi.head(nodes) = g.head(nodes);
  for (int k = 0; k < nodes; ++k) p.groups.push_back({nodes + 2 * k, nodes + 2 * k + 1});
  return p;
}

ReducedProblem tresca_springs(int groups, double bound, unsigned seed) {
  std::mt19937 gen(seed);
  std::uniform_real_distribution<double> unit(-1.0, 1.0);
  const int n = 2 * groups;
  Eigen::VectorXd k(n), c(n);
  for (int i = 0; i < groups; ++i) {
    k(2 * i) = k(2 * i + 1) = 2.0 + unit(gen);
    c(2 * i) = 1.5 * bound * unit(gen);
    c(2 * i + 1) = 1.5 * bound * unit(gen);
  }
  ReducedProblem p = ReducedProblem::uniform(k.asDiagonal(), c, Eigen::VectorXd::Ones(n), tresca_law(bound),
                                             ConstraintKind::none);
  for (int i = 0; i < groups; ++i) p.groups.push_back({2 * i, 2 * i + 1});
  return p;
}

Eigen::VectorXd tresca_springs_solution(const ReducedProblem& springs, double bound) {
  Eigen::VectorXd a = Eigen::VectorXd::Zero(springs.size());
  for (const CoordinateGroup& g : springs.groups) {
    const Eigen::Vector2d cg(springs.c(g.first), springs.c(g.second));
    const double m = cg.norm();
    if (m <= bound) continue;
    const Eigen::Vector2d ag = cg * ((m - bound) / (springs.S(g.first, g.first) * m));
    a(g.first) = ag(0);
    a(g.second) = ag(1);
  }
  return a;
}

}  // namespace hemivem::test

namespace hemivem::test {

Eigen::Matrix<double, 12, 12> p1_tetrahedron_stiffness(const Mesh3D& mesh, int cell, double lambda, double mu,
                                                       double* volume) {
  Eigen::Matrix<double, 6, 6> C = Eigen::Matrix<double, 6, 6>::Zero();
  for (int a = 0; a < 3; ++a) {
    for (int c = 0; c < 3; ++c) C(a, c) = lambda;
    C(a, a) += 2 * mu;
    C(3 + a, 3 + a) = mu;
  }
  const auto& v = mesh.cell_vertices(cell);
  EXPECT_EQ(v.size(), 4u);
  Eigen::Matrix4d P;
  for (int i = 0; i < 4; ++i) P.row(i) << 1.0, (mesh.vertex(v[i]) - mesh.vertex(v[0])).transpose();
  const double V = std::abs(P.determinant()) / 6.0;
  const Eigen::Matrix4d G = P.inverse();  // column i: the coefficients of barycentric i
  Eigen::Matrix<double, 6, 12> B = Eigen::Matrix<double, 6, 12>::Zero();
  for (int i = 0; i < 4; ++i) {
    const Vec3 g = G.col(i).tail<3>();
    B(0, 3 * i) = g.x(), B(1, 3 * i + 1) = g.y(), B(2, 3 * i + 2) = g.z();
    B(3, 3 * i + 1) = g.z(), B(3, 3 * i + 2) = g.y();
    B(4, 3 * i) = g.z(), B(4, 3 * i + 2) = g.x();
    B(5, 3 * i) = g.y(), B(5, 3 * i + 1) = g.x();
  }
  if (volume) *volume = V;
  return V * B.transpose() * C * B;
}

}  // namespace hemivem::test
