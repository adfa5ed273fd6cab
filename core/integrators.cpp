#include "core/integrators-inl.hpp"

#include "core/errors.hpp"

namespace dynid {

const char* integratorName(IntegratorType type) {
  return type == IntegratorType::kRk4 ? "rk4" : "euler";
}

IntegratorType parseIntegrator(const std::string& name) {
  if (name == "rk4") return IntegratorType::kRk4;
  if (name == "euler") return IntegratorType::kSemiImplicitEuler;
  throw InputError("unknown integrator '" + name + "' (expected rk4 or euler)");
}

template void rk4Step(const Model&, Data&, VectorRef<double>, VectorRef<double>,
                      const ConstVectorRef<double>&, const double&);
template void semiImplicitEulerStep(const Model&, Data&, VectorRef<double>, VectorRef<double>,
                                    const ConstVectorRef<double>&, const double&);

}  // namespace dynid
