// The engines' names (cmake/HemivemEngines.cmake → hemivem/engine_names.hpp and the factories'
// registries) agree with the engines built and with what each engine calls itself.
#include <hemivem/engine_names.hpp>
#include <hemivem/error.hpp>
#include <hemivem/linear_backends.hpp>
#include <hemivem/nonsmooth_backends.hpp>
#include <hemivem/sparse_factorization.hpp>

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <string>
#include <vector>

namespace hemivem {
namespace {

template <class Known>
void expect_listed_in_order(const std::vector<std::string>& built, const Known& known) {
  std::size_t next = 0;
  for (const std::string& name : built) {
    const auto it = std::find(known.begin() + static_cast<std::ptrdiff_t>(next), known.end(), name);
    ASSERT_NE(it, known.end()) << name << " is built but not known, or out of the known order";
    next = static_cast<std::size_t>(it - known.begin()) + 1;
  }
}

template <class Known>
void expect_distinct_and_normalized(const Known& known) {
  EXPECT_FALSE(known.empty());
  std::set<std::string> seen;
  for (const auto& name : known) {
    EXPECT_EQ(normalized_engine_name(name), name);
    EXPECT_TRUE(seen.insert(std::string(name)).second) << name << " twice";
  }
}

TEST(EngineNames, KnownNamesAreDistinctAndNormalized) {
  expect_distinct_and_normalized(known_linear_engines());
  expect_distinct_and_normalized(known_minimizers());
  EXPECT_EQ(normalized_engine_name("Bundle_DCA"), "bundle-dca");
}

TEST(EngineNames, EveryLinearEngineBuiltIsKnownAndCallsItselfSo) {
  const auto built = available_factorizations();
  EXPECT_FALSE(built.empty());
  expect_listed_in_order(built, known_linear_engines());
  for (const std::string& name : built) {
    FactorizationOptions options;
    options.engine = name;
    EXPECT_EQ(make_factorization(options)->name(), name);
  }
}

TEST(EngineNames, EveryMinimizerBuiltIsKnownAndCallsItselfSo) {
  const auto built = available_minimizers();
  EXPECT_FALSE(built.empty());
  expect_listed_in_order(built, known_minimizers());
  for (const std::string& name : built) EXPECT_EQ(make_minimizer(name)->name(), name);
}

TEST(EngineNames, OptionsAcceptEveryKnownNameAndListThemForAnUnknownOne) {
  for (const auto& name : known_linear_engines()) {
    FactorizationOptions options;
    options.engine = std::string(name);
    std::string error;
    EXPECT_TRUE(options.is_valid(&error)) << name << ": " << error;
  }
  FactorizationOptions options;
  options.engine = "pardiso";
  std::string error;
  ASSERT_FALSE(options.is_valid(&error));
  for (const auto& name : known_linear_engines()) EXPECT_NE(error.find(std::string(name)), std::string::npos) << error;
}

TEST(EngineNames, UnknownMinimizerIsAnInputErrorListingThoseBuilt) {
  try {
    make_minimizer("simplex");
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("unknown minimizer 'simplex'"), std::string::npos) << message;
    for (const std::string& name : available_minimizers()) EXPECT_NE(message.find(name), std::string::npos) << message;
  }
}

}  // namespace
}  // namespace hemivem
