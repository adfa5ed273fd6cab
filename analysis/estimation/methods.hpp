// The estimation methods dynid compares, with their one name table: what `identify --method`,
// `search --method`, a batch manifest's "method" and the demo's table rows all use.
#pragma once

#include <string>
#include <vector>

namespace dynid {

enum class Method {
  kOls,            // ordinary least squares on the torques
  kWls,            // weighted least squares (Gautier)
  kPc,             // physically consistent least squares (entropic divergence from a prior)
  kNlo,            // the paper's multistart COBYLA on the GC error
  kGa,             // the paper's genetic algorithm
  kHybrid,         // GA, then NLO from its best
  kNloRefined,     // NLO, then Ceres refinement on the GC residuals
  kGaRefined,      // GA, then refinement
  kHybridRefined,  // hybrid, then refinement
  kCombined,       // pc's torque fit and the GC residuals together, physically consistent
};

/// Every method in table order (ols, wls, pc, nlo, ga, hybrid, nlo_refined, ga_refined,
/// hybrid_refined, combined).
const std::vector<Method>& allMethods();
/// The methods of one command: least squares (ols, wls, pc) or searches (nlo, ga, hybrid).
const std::vector<Method>& leastSquaresMethods();
/// `dynid identify`'s: least squares and combined.
const std::vector<Method>& identifyMethods();
const std::vector<Method>& searchMethods();

/// "ols", "nlo_refined", ...
const char* methodName(Method method);
/// One line for tables: "ordinary least squares on the torques", ...
const char* methodDescription(Method method);
/// The method named `name` among `allowed`. Throws InputError listing them otherwise ("unknown
/// method 'x' (expected ols, wls or pc)").
Method parseMethod(const std::string& name, const std::vector<Method>& allowed = allMethods());
/// Comma-separated names ("ols,nlo_refined"), each parsed by parseMethod, in order; "all" is
/// every allowed method. Throws InputError for an unknown, repeated or empty name.
std::vector<Method> parseMethods(const std::string& list,
                                 const std::vector<Method>& allowed = allMethods());
/// "ols, wls or pc".
std::string methodList(const std::vector<Method>& methods);

bool isSearch(Method method);   // nlo, ga, hybrid
bool isRefined(Method method);  // *_refined
/// Whether `method` is physically consistent and so takes a prior and its weight (pc, combined).
bool takesPrior(Method method);
/// Whether `method` needs a GC-error problem (the searches, their refinements, combined).
bool needsGc(Method method);
/// The search a refined method starts from (kNloRefined -> kNlo); the method itself otherwise.
Method searchOf(Method method);

}  // namespace dynid
