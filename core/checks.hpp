// Boundary checks shared by the public algorithms: sizes and model/data consistency. They throw
// InputError with the argument named ("q has 5 entries, model has 6 joints").
#pragma once

#include <string>

#include "core/data.hpp"
#include "core/errors.hpp"

namespace dynid {

template <typename Scalar, typename Vector>
void checkSize(const ModelTpl<Scalar>& model, const Vector& x, const char* name) {
  if (x.size() != model.numJoints())
    throw InputError(std::string(name) + " has " + std::to_string(x.size()) + " entries, model '" +
                     model.name + "' has " + std::to_string(model.numJoints()) + " joints");
}

template <typename Scalar>
void checkData(const ModelTpl<Scalar>& model, const DataTpl<Scalar>& data) {
  if (static_cast<int>(data.liMi.size()) != model.numJoints() ||
      static_cast<int>(model.motion_subspaces.size()) != model.numJoints())
    throw InputError("Data was built for another model, or the model '" + model.name +
                     "' was not finalized");
}

}  // namespace dynid
