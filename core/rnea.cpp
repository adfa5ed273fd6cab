#include "core/rnea-inl.hpp"

namespace dynid {
template const VectorX<double>& rnea(const Model&, Data&, const ConstVectorRef<double>&,
                                     const ConstVectorRef<double>&, const ConstVectorRef<double>&);
}  // namespace dynid
