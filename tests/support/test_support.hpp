// Helpers shared by the test programs.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

namespace hemivem::test {

/// The shared folder (meshes, paper), or an empty path when it is absent.
std::filesystem::path shared_dir();
/// The *.poly2d files under shared/meshes, sorted; empty when shared/ is absent.
std::vector<std::filesystem::path> shared_meshes();
/// tests/data
std::filesystem::path data_dir();
/// The shipped scenes (scenes/ of the project).
std::filesystem::path scenes_dir();

}  // namespace hemivem::test

#include <hemivem/vem/assembly.hpp>

#include <functional>
#include <string>

namespace hemivem::test {

/// Solves a reduced system with Eigen's sparse Cholesky and returns the full nodal
/// displacement (prescribed values included). Fails the calling test on a failed factorization.
Eigen::VectorXd solve(const LinearSystem& system);

/// Dirichlet condition with value u on every boundary edge of the mesh.
DirichletCondition dirichlet_everywhere(const Mesh& mesh, VectorField u);
/// The largest nodal error of u (2 per vertex) against the field `exact`, relative to the
/// field's largest component at the vertices.
double max_relative_nodal_error(const Mesh& mesh, const Eigen::VectorXd& u, const VectorField& exact);

/// The same vertices bit for bit (== on every coordinate) and the same elements.
bool identical(const Mesh& a, const Mesh& b);

/// The message of the InputError that f throws ("" when it throws none).
std::string input_error_of(const std::function<void()>& f);
/// Where the InputError that f throws is (InputError::where: a scene key or a file:line; ""
/// when it throws none).
std::string input_error_key(const std::function<void()>& f);

}  // namespace hemivem::test

#include <hemivem/contact/condensation.hpp>
#include <hemivem/contact/problem.hpp>

#include <functional>
#include <memory>

namespace hemivem::test {

/// Example 4.1 on a generated mesh (seed 5), condensed with the eigen engine.
struct Example {
  Mesh mesh;
  ContactProblem problem;
  LinearSystem system;
  ContactBoundary boundary;
  std::unique_ptr<Condensation> condensation;
};

/// `change` may modify the problem (law, gap, loads, constraint) before assembly.
std::unique_ptr<Example> example(const std::string& kind, int n, const std::function<void(ContactProblem&)>& change = {});

}  // namespace hemivem::test

namespace hemivem::test {

/// A run of the built hemivem binary: exit code, standard output and standard error.
struct CommandRun {
  int code = -1;
  std::string out;
  std::string err;
};
/// Runs a shell command line, capturing its standard output and standard error.
CommandRun run_command(const std::string& command);
/// Runs `hemivem ARGS` (ARGS as on a shell command line).
CommandRun run_hemivem(const std::string& args);
/// The contents of a file ("" when it cannot be read).
std::string slurp(const std::filesystem::path& file);
/// The bytes of base64 text (the encoding of the VTU files' binary arrays); characters outside
/// the alphabet are skipped, '=' ends it.
std::vector<unsigned char> from_base64(const std::string& text);
/// A fresh, absent path in the temporary folder, unique to this process and `name`.
std::filesystem::path scratch(const std::string& name);
/// The shipped scene `name` (in scenes_dir()) with `from` replaced by `to` (once), parsed: the
/// InputError's message, "accepted", or "scene text not found: FROM".
std::string scene_refusal(const std::string& name, const std::string& from, const std::string& to);

}  // namespace hemivem::test

#include <functional>
#include <ostream>
#include <span>

namespace hemivem::test {

// ---- corpora of malformed files (tests/data/malformed, tests/data/gmsh/malformed) ----------

enum class MalformedKind { input, mesh };

/// A file of a corpus and the error reading it must throw: an InputError at `file:line`
/// whose message holds `fragment`; of kind mesh, a MeshError whose element() is `element`.
struct Malformed {
  const char* file;      // in the corpus folder
  int line;              // expected line in where()
  const char* fragment;  // expected in what()
  MalformedKind kind = MalformedKind::input;
  int element = -1;
};

std::ostream& operator<<(std::ostream& os, const Malformed& m);

/// Reads `dir`/`c.file` with `read` and expects the error `c` describes.
void expect_rejected_at_its_line(const std::filesystem::path& dir, const Malformed& c,
                                 const std::function<void(const std::filesystem::path&)>& read);

/// The files of `dir` ending in `extension` are those of `table`, each once, and the
/// README.md of `dir` names each file (in backquotes) and its fragment.
void expect_table_covers_corpus(const std::filesystem::path& dir, const std::string& extension,
                                std::span<const Malformed> table);

/// A test name for a file of a corpus: `prefix` and the file's stem, '-' and '.' as '_'.
std::string corpus_test_name(const char* file, const std::string& prefix = "");

}  // namespace hemivem::test

#include <hemivem/reduced_problem.hpp>

#include <memory>

namespace hemivem::test {

// ---- reduced problems with groups of coordinates (a solid's friction) ----------------------

/// Shaped as a solid's frictional contact on `nodes` nodes: coordinates 0..nodes-1 the normal
/// displacements (law `normal`, one-sided bounds a_i <= g_i with g_i in [0, 0.02]), then per node
/// the group (nodes + 2k, nodes + 2k + 1) of its tangential displacements with law `friction`
/// (weight w_i in [0.5, 1.5], shared by the node's three coordinates); S symmetric positive
/// definite with a dominant diagonal (about 100) and random couplings, c random with entries
/// of size about `load`. Reproducible for a seed.
ReducedProblem frictional_solid_problem(int nodes, std::shared_ptr<const ContactLaw> normal,
                                        std::shared_ptr<const ContactLaw> friction, unsigned seed, double load = 2.0);

/// `groups` uncoupled groups on springs: S = diag(k_i) with k_i in [1, 3] equal within a group,
/// c random (about half the groups stuck under Tresca's bound `bound` with weight 1), the
/// coordinates (2k, 2k + 1) in group k.
ReducedProblem tresca_springs(int groups, double bound, unsigned seed);
/// Their solution: group k stuck (0) when |c_G| <= bound, else slipping along c_G by
/// (|c_G| - bound) / k_i.
Eigen::VectorXd tresca_springs_solution(const ReducedProblem& springs, double bound);

}  // namespace hemivem::test

#include <hemivem/mesh/mesh3d.hpp>

namespace hemivem::test {

/// The P1 finite-element stiffness of tetrahedron `cell` of `mesh` (12 x 12: the x, y, z dofs of
/// its vertices in cell_vertices order) for the Lame constants lambda, mu: V B^T C B with the
/// gradients of the barycentric coordinates from the inverse of [1 x y z]; its volume V into
/// *volume when given. An independent code for the tests of the virtual elements on tetrahedra.
Eigen::Matrix<double, 12, 12> p1_tetrahedron_stiffness(const Mesh3D& mesh, int cell, double lambda, double mu,
                                                       double* volume = nullptr);

}  // namespace hemivem::test
