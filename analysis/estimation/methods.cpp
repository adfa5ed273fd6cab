#include "analysis/estimation/methods.hpp"

#include <algorithm>

#include "core/errors.hpp"

namespace dynid {

namespace {
struct Entry {
  Method method;
  const char* name;
  const char* description;
};
// The one name table.
constexpr Entry kTable[] = {
    {Method::kOls, "ols", "ordinary least squares on the torques"},
    {Method::kWls, "wls", "weighted least squares (per-joint noise)"},
    {Method::kPc, "pc", "physically consistent least squares (entropic prior)"},
    {Method::kNlo, "nlo", "GC-error search: multistart COBYLA"},
    {Method::kGa, "ga", "GC-error search: genetic algorithm"},
    {Method::kHybrid, "hybrid", "GC-error search: GA, then COBYLA"},
    {Method::kNloRefined, "nlo_refined", "NLO result refined by Ceres"},
    {Method::kGaRefined, "ga_refined", "GA result refined by Ceres"},
    {Method::kHybridRefined, "hybrid_refined", "hybrid result refined by Ceres"},
    {Method::kCombined, "combined",
     "torques and motion (GC residuals) fitted together, physically consistent"}};
}  // namespace

const std::vector<Method>& allMethods() {
  static const std::vector<Method> all = [] {
    std::vector<Method> out;
    for (const Entry& e : kTable) out.push_back(e.method);
    return out;
  }();
  return all;
}

const std::vector<Method>& leastSquaresMethods() {
  static const std::vector<Method> methods = {Method::kOls, Method::kWls, Method::kPc};
  return methods;
}

const std::vector<Method>& identifyMethods() {
  static const std::vector<Method> methods = {Method::kOls, Method::kWls, Method::kPc,
                                              Method::kCombined};
  return methods;
}

const std::vector<Method>& searchMethods() {
  static const std::vector<Method> methods = {Method::kNlo, Method::kGa, Method::kHybrid};
  return methods;
}

const char* methodName(Method method) {
  for (const Entry& e : kTable)
    if (e.method == method) return e.name;
  return "unknown";
}

const char* methodDescription(Method method) {
  for (const Entry& e : kTable)
    if (e.method == method) return e.description;
  return "";
}

std::string methodList(const std::vector<Method>& methods) {
  std::string out;
  for (std::size_t i = 0; i < methods.size(); ++i) {
    if (i > 0) out += i + 1 == methods.size() ? " or " : ", ";
    out += methodName(methods[i]);
  }
  return out;
}

Method parseMethod(const std::string& name, const std::vector<Method>& allowed) {
  for (Method m : allowed)
    if (name == methodName(m)) return m;
  throw InputError("unknown method '" + name + "' (expected " + methodList(allowed) + ")");
}

std::vector<Method> parseMethods(const std::string& list, const std::vector<Method>& allowed) {
  if (list == "all") return allowed;
  std::vector<Method> out;
  std::size_t start = 0;
  while (true) {
    const std::size_t comma = list.find(',', start);
    const Method m = parseMethod(list.substr(start, comma - start), allowed);
    if (std::find(out.begin(), out.end(), m) != out.end())
      throw InputError(std::string("method '") + methodName(m) + "' is listed twice");
    out.push_back(m);
    if (comma == std::string::npos) return out;
    start = comma + 1;
  }
}

bool isSearch(Method method) {
  return method == Method::kNlo || method == Method::kGa || method == Method::kHybrid;
}

bool isRefined(Method method) {
  return method == Method::kNloRefined || method == Method::kGaRefined ||
         method == Method::kHybridRefined;
}

bool takesPrior(Method method) { return method == Method::kPc || method == Method::kCombined; }

bool needsGc(Method method) {
  return isSearch(method) || isRefined(method) || method == Method::kCombined;
}

Method searchOf(Method method) {
  switch (method) {
    case Method::kNloRefined:
      return Method::kNlo;
    case Method::kGaRefined:
      return Method::kGa;
    case Method::kHybridRefined:
      return Method::kHybrid;
    default:
      return method;
  }
}

}  // namespace dynid
