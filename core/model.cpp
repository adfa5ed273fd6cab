#include "core/model-inl.hpp"

namespace dynid {

const char* jointTypeName(JointType type) {
  switch (type) {
    case JointType::kRevolute:
      return "revolute";
    case JointType::kContinuous:
      return "continuous";
    case JointType::kPrismatic:
      return "prismatic";
  }
  return "unknown";
}

template class ModelTpl<double>;

}  // namespace dynid
