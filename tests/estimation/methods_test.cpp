#include "analysis/estimation/methods.hpp"

#include <gtest/gtest.h>

#include <set>
#include <string>

#include "core/errors.hpp"

namespace dynid {
namespace {

TEST(Methods, EveryNameParsesBackToItsMethod) {
  std::set<std::string> names;
  for (Method m : allMethods()) {
    EXPECT_EQ(parseMethod(methodName(m)), m) << methodName(m);
    names.insert(methodName(m));
  }
  // Ten methods with ten distinct names, in table order: the paper's nine, then combined.
  EXPECT_EQ(names.size(), 10u);
  EXPECT_STREQ(methodName(allMethods().front()), "ols");
  EXPECT_STREQ(methodName(allMethods().back()), "combined");
  EXPECT_TRUE(needsGc(Method::kCombined) && needsGc(Method::kGaRefined) && !needsGc(Method::kPc));
}

TEST(Methods, ParsingIsLimitedToTheAllowedSetAndListsIt) {
  EXPECT_EQ(parseMethod("wls", leastSquaresMethods()), Method::kWls);
  try {
    parseMethod("nlo", leastSquaresMethods());
    FAIL() << "expected InputError";
  } catch (const InputError& e) {
    EXPECT_EQ(std::string(e.what()), "unknown method 'nlo' (expected ols, wls or pc)");
  }
  EXPECT_THROW(parseMethod("NLO"), InputError);
  EXPECT_THROW(parseMethod(""), InputError);
}

TEST(Methods, RefinedMethodsStartFromTheirSearch) {
  EXPECT_EQ(searchOf(Method::kNloRefined), Method::kNlo);
  EXPECT_EQ(searchOf(Method::kGaRefined), Method::kGa);
  EXPECT_EQ(searchOf(Method::kHybridRefined), Method::kHybrid);
  EXPECT_EQ(searchOf(Method::kOls), Method::kOls);
  for (Method m : searchMethods()) EXPECT_TRUE(isSearch(m) && !isRefined(m));
  for (Method m : leastSquaresMethods()) EXPECT_FALSE(isSearch(m) || isRefined(m));
  EXPECT_TRUE(isRefined(Method::kHybridRefined));
}

TEST(Methods, ThePhysicallyConsistentOnesTakeAPrior) {
  std::vector<Method> with_prior;
  for (Method m : allMethods())
    if (takesPrior(m)) with_prior.push_back(m);
  EXPECT_EQ(with_prior, (std::vector<Method>{Method::kPc, Method::kCombined}));
}

}  // namespace
}  // namespace dynid
