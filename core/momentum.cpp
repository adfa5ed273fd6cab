#include "core/momentum-inl.hpp"

namespace dynid {
template void momentumTerms(const Model&, Data&, const ConstVectorRef<double>&,
                            const ConstVectorRef<double>&, VectorX<double>&, VectorX<double>&);
}  // namespace dynid
