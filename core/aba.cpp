#include "core/aba-inl.hpp"

namespace dynid {
template const VectorX<double>& aba(const Model&, Data&, const ConstVectorRef<double>&,
                                    const ConstVectorRef<double>&, const ConstVectorRef<double>&);
}  // namespace dynid
