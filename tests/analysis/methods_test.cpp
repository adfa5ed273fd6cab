#include "analysis/methods.hpp"

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
  // Nine methods with nine distinct names, in the demo's table order.
  EXPECT_EQ(names.size(), 9u);
  EXPECT_STREQ(methodName(allMethods().front()), "ols");
  EXPECT_STREQ(methodName(allMethods().back()), "hybrid_refined");
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

}  // namespace
}  // namespace dynid
