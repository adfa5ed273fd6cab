#include "core/crba-inl.hpp"

namespace dynid {
template const MatrixX<double>& crba(const Model&, Data&, const ConstVectorRef<double>&);
}  // namespace dynid
