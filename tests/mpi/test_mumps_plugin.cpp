// The sequential MUMPS engine (linked) and the MPI one (a module loaded with RTLD_LOCAL |
// RTLD_DEEPBIND) in one program: each must use its own MUMPS build, and both must agree with
// each other and with a dense reference. Run as a singleton and under mpiexec; only rank 0
// holds the MPI engine's outputs, the sequential engine runs on every rank.
#include <hemivem/mumps_factorization.hpp>
#include <hemivem/mumps_mpi_plugin.hpp>

#include <Eigen/Cholesky>
#include <Eigen/Dense>
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#ifndef HEMIVEM_MUMPS_MPI_PLUGIN
#error "HEMIVEM_MUMPS_MPI_PLUGIN (path of the module) must be defined"
#endif

namespace {

using hemivem::SparseMatrix;

void* g_module = nullptr;
int g_rank = 0;

SparseMatrix test_matrix(int n) {
  std::vector<Eigen::Triplet<double>> t;
  for (int i = 0; i < n; ++i) {
    t.emplace_back(i, i, 4.5);
    for (int d : {1, 17}) {
      if (i + d < n) {
        t.emplace_back(i, i + d, -1.0);
        t.emplace_back(i + d, i, -1.0);
      }
    }
  }
  SparseMatrix A(n, n);
  A.setFromTriplets(t.begin(), t.end());
  return A;
}

TEST(MumpsPlugin, SequentialAndMpiEnginesCoexist) {
  ASSERT_NE(g_module, nullptr);
  auto create = reinterpret_cast<hemivem::CreateMumpsMpiFunction>(dlsym(g_module, hemivem::kCreateMumpsMpiSymbol));
  ASSERT_NE(create, nullptr) << dlerror();

  const int n = 300;
  const SparseMatrix A = test_matrix(n);
  const std::vector<int> block1{5, 100, 299, 0};
  const Eigen::MatrixXd B = Eigen::MatrixXd::Ones(n, 2);
  const Eigen::MatrixXd D = A;

  hemivem::MumpsFactorization seq;
  std::unique_ptr<hemivem::SparseFactorization> mpi(create(nullptr));
  ASSERT_EQ(mpi->name(), "mumps-mpi");

  // Interleave the two engines.
  Eigen::MatrixXd X_seq, X_mpi, S_seq, S_mpi;
  ASSERT_TRUE(seq.factorize(A).ok());
  ASSERT_TRUE(mpi->factorize(A).ok());
  ASSERT_TRUE(seq.solve(B, &X_seq).ok());
  ASSERT_TRUE(mpi->solve(B, &X_mpi).ok());
  ASSERT_TRUE(mpi->schur_complement(A, block1, &S_mpi).ok());
  ASSERT_TRUE(seq.schur_complement(A, block1, &S_seq).ok());

  const Eigen::MatrixXd X_ref = Eigen::LLT<Eigen::MatrixXd>(D).solve(B);
  EXPECT_LT((X_seq - X_ref).norm() / X_ref.norm(), 1e-10);
  if (g_rank == 0) {
    ASSERT_EQ(X_mpi.rows(), n);
    ASSERT_EQ(S_mpi.rows(), 4);
    EXPECT_LT((X_mpi - X_ref).norm() / X_ref.norm(), 1e-10);
    EXPECT_LT((S_mpi - S_seq).norm() / S_seq.norm(), 1e-10);
  }
}

TEST(MumpsPlugin, EachEngineSeesItsOwnMumps) {
  ASSERT_NE(g_module, nullptr);
  auto library_of = [](void* symbol) {
    Dl_info info{};
    return symbol != nullptr && dladdr(symbol, &info) != 0 && info.dli_fname ? std::string(info.dli_fname)
                                                                            : std::string("?");
  };
  const std::string global = library_of(dlsym(RTLD_DEFAULT, "dmumps_c"));
  const std::string module = library_of(dlsym(g_module, "dmumps_c"));
  EXPECT_NE(global.find("dmumps_seq"), std::string::npos) << global;
  EXPECT_NE(module.find("libdmumps"), std::string::npos) << module;
  EXPECT_EQ(module.find("_seq"), std::string::npos) << module;
}

}  // namespace

int main(int argc, char** argv) {
  ::testing::InitGoogleTest(&argc, argv);
  g_module = dlopen(HEMIVEM_MUMPS_MPI_PLUGIN, RTLD_NOW | RTLD_LOCAL | RTLD_DEEPBIND);
  if (g_module == nullptr) {
    std::fprintf(stderr, "cannot load %s: %s\n", HEMIVEM_MUMPS_MPI_PLUGIN, dlerror());
    return 1;
  }
  auto rank = reinterpret_cast<hemivem::MumpsMpiRankFunction>(dlsym(g_module, hemivem::kMumpsMpiRankSymbol));
  g_rank = rank ? rank() : 0;
  if (g_rank != 0) {  // one report: rank 0's (a failure elsewhere still gives a non-zero exit)
    auto& listeners = ::testing::UnitTest::GetInstance()->listeners();
    delete listeners.Release(listeners.default_result_printer());
  }
  return RUN_ALL_TESTS();
  // The module stays loaded: MPI is finalized at exit by a static guard inside it.
}
