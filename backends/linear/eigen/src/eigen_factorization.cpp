#include <hemivem/eigen_factorization.hpp>

#include "cholesky_engine.hpp"

#include <Eigen/OrderingMethods>
#include <Eigen/SparseCholesky>

#include <cmath>

namespace hemivem {

using namespace linear_detail;

namespace {

using MainSolver = Eigen::SimplicialLLT<SparseMatrix, Eigen::Lower, Eigen::AMDOrdering<int>>;
// The ordered factorization receives a matrix that is already in elimination order.
using OrderedSolver = Eigen::SimplicialLLT<SparseMatrix, Eigen::Lower, Eigen::NaturalOrdering<int>>;

template <class Solver>
const SparseMatrix& factor(const Solver& solver) {
  return solver.matrixL().nestedExpression();
}

template <class Solver>
FactorizationResult analyze_with(Solver& solver, const SparseMatrix& A) {
  solver.analyzePattern(A);
  if (solver.info() != Eigen::Success)
    return make_result(FactorizationStatus::numerical_failure, "SimplicialLLT::analyzePattern failed");
  return FactorizationResult::good();
}

template <class Solver>
FactorizationResult factorize_with(Solver& solver, const SparseMatrix& A) {
  solver.factorize(A);
  if (solver.info() == Eigen::NumericalIssue)
    return make_result(FactorizationStatus::not_positive_definite,
                       "the matrix is not positive definite (SimplicialLLT met a pivot <= 0)");
  if (solver.info() != Eigen::Success)
    return make_result(FactorizationStatus::numerical_failure, "SimplicialLLT failed");
  const SparseMatrix& L = factor(solver);
  if (!Eigen::Map<const Eigen::VectorXd>(L.valuePtr(), L.nonZeros()).allFinite())
    return make_result(FactorizationStatus::numerical_failure, "the Cholesky factor has entries that are not finite");
  return FactorizationResult::good();
}

class EigenKernel final : public CholeskyKernel {
 public:
  FactorizationResult analyze(const SparseMatrix& A) override { return analyze_with(main_, A); }
  FactorizationResult factorize(const SparseMatrix& A) override { return factorize_with(main_, A); }
  FactorizationResult solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const override {
    *X = main_.solve(B);
    return FactorizationResult::good();
  }

  FactorizationResult order(const SparseMatrix& lower, std::vector<int>* perm) override {
    Eigen::PermutationMatrix<Eigen::Dynamic, Eigen::Dynamic, int> inverse;
    Eigen::AMDOrdering<int> amd;
    amd(lower, inverse);
    perm->assign(inverse.indices().data(), inverse.indices().data() + inverse.size());
    return FactorizationResult::good();
  }
  FactorizationResult analyze_ordered(const SparseMatrix& P) override { return analyze_with(ordered_, P); }
  FactorizationResult factorize_ordered(const SparseMatrix& P) override { return factorize_with(ordered_, P); }
  FactorColumn column(int j) const override {
    const SparseMatrix& L = factor(ordered_);
    const int begin = L.outerIndexPtr()[j];
    return {L.innerIndexPtr() + begin, L.valuePtr() + begin, L.outerIndexPtr()[j + 1] - begin};
  }

 private:
  MainSolver main_;
  OrderedSolver ordered_;
};

}  // namespace

struct EigenFactorization::Impl : CholeskyEngine {
  Impl() : CholeskyEngine(std::make_unique<EigenKernel>(), "eigen") {}
};

EigenFactorization::EigenFactorization(const FactorizationOptions&) : impl_(std::make_unique<Impl>()) {}
EigenFactorization::~EigenFactorization() = default;
EigenFactorization::EigenFactorization(EigenFactorization&&) noexcept = default;
EigenFactorization& EigenFactorization::operator=(EigenFactorization&&) noexcept = default;

int EigenFactorization::num_analyses() const { return impl_->num_analyses(); }

FactorizationResult EigenFactorization::analyze(const SparseMatrix& A) { return impl_->analyze(A); }

FactorizationResult EigenFactorization::factorize(const SparseMatrix& A) { return impl_->factorize(A); }

FactorizationResult EigenFactorization::solve(const Eigen::MatrixXd& B, Eigen::MatrixXd* X) const {
  return impl_->solve(B, X);
}

FactorizationResult EigenFactorization::schur_complement(const SparseMatrix& A, std::span<const int> block1,
                                                         Eigen::MatrixXd* S) {
  return impl_->schur_complement(A, block1, S);
}

FactorizationResult EigenFactorization::solve_interior(const Eigen::MatrixXd& B2, Eigen::MatrixXd* X2) const {
  return impl_->solve_interior(B2, X2);
}

FactorizationResult EigenFactorization::condense_rhs(const Eigen::VectorXd& b1, const Eigen::VectorXd& b2, Eigen::VectorXd* c) {
  return impl_->condense_rhs(b1, b2, c);
}

FactorizationResult EigenFactorization::expand(const Eigen::VectorXd& x1, Eigen::VectorXd* x2) const {
  return impl_->expand(x1, x2);
}

}  // namespace hemivem
