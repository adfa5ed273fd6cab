#include "core/floating/floating_aba-inl.hpp"
#include "core/floating/floating_regressor-inl.hpp"
#include "core/floating/floating_rnea-inl.hpp"

namespace dynid {

std::vector<std::string> floatingParameterNames(const FloatingModel& model) {
  std::vector<std::string> names;
  names.reserve(static_cast<std::size_t>(model.numParameters()));
  for (auto name : kLinkParameterNames) names.push_back(std::string(name) + "0");
  for (std::string& name : standardParameterNames(model.limbs().parameterLayout()))
    names.push_back(std::move(name));
  return names;
}

template const VectorX<double>& floatingRnea(const FloatingModel&, FloatingData&, const BaseMotion&,
                                             const ConstVectorRef<double>&,
                                             const ConstVectorRef<double>&,
                                             const ConstVectorRef<double>&);
template const MatrixX<double>& floatingCrba(const FloatingModel&, FloatingData&,
                                             const ConstVectorRef<double>&);
template const VectorX<double>& floatingForwardDynamics(
    const FloatingModel&, FloatingData&, const BaseMotion&, const ConstVectorRef<double>&,
    const ConstVectorRef<double>&, const ConstVectorRef<double>&, const Vector6<double>&);
template const VectorX<double>& floatingAba(const FloatingModel&, FloatingData&, const BaseMotion&,
                                            const ConstVectorRef<double>&,
                                            const ConstVectorRef<double>&,
                                            const ConstVectorRef<double>&, const Vector6<double>&);
template const RowMatrixX<double>& floatingRegressor(const FloatingModel&, FloatingData&,
                                                     const BaseMotion&,
                                                     const ConstVectorRef<double>&,
                                                     const ConstVectorRef<double>&,
                                                     const ConstVectorRef<double>&);

}  // namespace dynid
