#include "core/regressor-inl.hpp"

namespace dynid {
template const MatrixX<double>& jointTorqueRegressor(const Model&, Data&,
                                                     const ConstVectorRef<double>&,
                                                     const ConstVectorRef<double>&,
                                                     const ConstVectorRef<double>&);
}  // namespace dynid
