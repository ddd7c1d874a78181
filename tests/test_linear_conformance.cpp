// The conformance suite of the linear engines (support/linear_conformance.hpp) run by every
// linear engine that was built, each made by the factory in one process; plus the factory.
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/process_group.hpp>
#include <hemivem/sparse_factorization.hpp>

#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>

#include "linear_conformance.hpp"
#include "linear_support.hpp"

#include <algorithm>
#include <cctype>
#include <string>
#include <vector>

namespace hemivem {
namespace {

using test::LinearConformance;
using test::LinearEngine;

/// The engines of the factory that were built.
std::vector<LinearEngine> factory_engines() {
  std::vector<LinearEngine> engines;
  for (const std::string& name : available_factorizations())
    engines.push_back({name, [name] {
                         FactorizationOptions options;
                         options.engine = name;
                         return make_factorization(options);
                       }});
  return engines;
}

TEST_P(LinearConformance, RunsAcrossProcessesOnlyWhenItIsAProcessGroup) {
  auto f = make();
  const ProcessGroup& processes = processes_of(*f);
  const bool group = dynamic_cast<const ProcessGroup*>(f.get()) != nullptr;
  // mumps-mpi (loaded as a module, so the type is checked across the module boundary) is one;
  // without mpirun it runs on one process.
  EXPECT_EQ(group, engine() == "mumps-mpi");
  EXPECT_EQ(&processes == static_cast<const ProcessGroup*>(dynamic_cast<const ProcessGroup*>(f.get())), group);
  EXPECT_TRUE(processes.holds_results());
  EXPECT_EQ(processes.num_processes(), 1);
  EXPECT_EQ(processes.share(41), 41);
}

INSTANTIATE_TEST_SUITE_P(Engines, LinearConformance, ::testing::ValuesIn(factory_engines()), test::engine_test_name);

// ---- why every engine must check definiteness itself --------------------------------

TEST(LinearTrap, EigenSimplicialLdltFactorsAMatrixWithANegativeEigenvalue) {
  const SparseMatrix A = test::one_negative_eigenvalue(40, 11);
  Eigen::SimplicialLDLT<SparseMatrix> ldlt(A);
  EXPECT_EQ(ldlt.info(), Eigen::Success) << "SimplicialLDLT only fails on an exactly zero pivot";
  EXPECT_LT(ldlt.vectorD().minCoeff(), 0.0);
}

// ---- the factory ------------------------------------------------------------------------

TEST(LinearFactory, EigenIsAlwaysAvailable) {
  const auto names = available_factorizations();
  ASSERT_FALSE(names.empty());
  EXPECT_EQ(names.front(), "eigen");
}

TEST(LinearFactory, AutoIsTheFastestBuiltEngineInOneProcess) {
  const auto built = available_factorizations();
  // CHOLMOD first: whole solves in the plane and in a solid measured faster (docs/performance.md)
  std::string expected = "eigen";
  for (const char* e : {"mumps", "cholmod"})
    if (std::find(built.begin(), built.end(), e) != built.end()) expected = e;
  EXPECT_EQ(fastest_factorization(), expected);
  FactorizationOptions options;
  options.engine = "Auto";
  std::string error;
  EXPECT_TRUE(options.is_valid(&error)) << error;
  EXPECT_EQ(make_factorization(options)->name(), expected);
}

TEST(LinearFactory, UnknownEngineListsTheAvailableOnes) {
  FactorizationOptions options;
  options.engine = "superlu";
  try {
    (void)make_factorization(options);
    FAIL() << "no exception";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("superlu"), std::string::npos) << message;
    for (const std::string& name : available_factorizations())
      EXPECT_NE(message.find(name), std::string::npos) << message;
  }
}

TEST(LinearFactory, EngineNotBuiltListsTheAvailableOnes) {
  const auto built = available_factorizations();
  int checked = 0;
  for (const std::string name : {"eigen", "cholmod", "mumps", "mumps-mpi"}) {
    if (std::find(built.begin(), built.end(), name) != built.end()) continue;
    FactorizationOptions options;
    options.engine = name;
    try {
      (void)make_factorization(options);
      ADD_FAILURE() << name << ": no exception";
    } catch (const InputError& e) {
      const std::string message = e.what();
      EXPECT_NE(message.find("linear engine '" + name + "' was not built; available: "), std::string::npos)
          << message;
      for (const std::string& b : built) EXPECT_NE(message.find(b), std::string::npos) << message;
    }
    ++checked;
  }
  if (checked == 0) GTEST_SKIP() << "every engine was built";
}

TEST(LinearFactory, NamesAreCaseInsensitive) {
  for (const std::string& name : available_factorizations()) {
    std::string upper = name;
    std::transform(upper.begin(), upper.end(), upper.begin(), [](unsigned char c) { return std::toupper(c); });
    std::string mixed = upper;
    mixed[0] = static_cast<char>(std::tolower(static_cast<unsigned char>(mixed[0])));
    for (const std::string& spelling : {upper, mixed}) {
      FactorizationOptions options;
      options.engine = spelling;
      auto f = make_factorization(options);
      ASSERT_NE(f, nullptr);
      EXPECT_EQ(f->name(), name);
    }
  }
}

TEST(LinearFactory, InvalidOptionsNameTheField) {
  FactorizationOptions options;
  options.threads = -1;
  std::string error;
  EXPECT_FALSE(options.is_valid(&error));
  EXPECT_NE(error.find("threads"), std::string::npos) << error;
  EXPECT_THROW((void)make_factorization(options), InputError);

  options = {};
  options.verbosity = -2;
  EXPECT_FALSE(options.is_valid(&error));
  EXPECT_NE(error.find("verbosity"), std::string::npos) << error;

  options = {};
  options.engine = "nosuch";
  EXPECT_FALSE(options.is_valid(&error));
  EXPECT_NE(error.find("engine"), std::string::npos) << error;

  options = {};
  options.engine = "MUMPS_MPI";
  EXPECT_TRUE(options.is_valid(&error)) << error;
  EXPECT_TRUE(FactorizationOptions{}.is_valid(nullptr));
}

TEST(LinearFactory, StatusesHaveNames) {
  EXPECT_EQ(to_string(FactorizationStatus::success), "success");
  EXPECT_EQ(to_string(FactorizationStatus::not_positive_definite), "not_positive_definite");
  EXPECT_EQ(to_string(FactorizationStatus::numerical_failure), "numerical_failure");
  EXPECT_EQ(to_string(FactorizationStatus::out_of_memory), "out_of_memory");
  for (FactorizationStatus s : {FactorizationStatus::success, FactorizationStatus::not_positive_definite,
                                FactorizationStatus::numerical_failure, FactorizationStatus::out_of_memory})
    EXPECT_EQ(factorization_status_from_string(to_string(s)), s);
  EXPECT_THROW(factorization_status_from_string("not_ready"), InputError);
}

}  // namespace
}  // namespace hemivem
