#include "core/kinematics-inl.hpp"

namespace dynid {
template const std::vector<Pose<double>>& forwardKinematics(const Model&, Data&,
                                                            const ConstVectorRef<double>&);
}  // namespace dynid
