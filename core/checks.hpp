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
  if (static_cast<int>(data.liMi.size()) != model.numJoints() || !model.finalized())
    throw InputError("Data was built for another model, or the model '" + model.name +
                     "' was not finalized");
}

/// The checks of every (q, dq, x) algorithm: Data for this model, and n entries in each vector.
template <typename Scalar, typename Q, typename DQ, typename X>
void checkState(const ModelTpl<Scalar>& model, const DataTpl<Scalar>& data, const Q& q,
                const DQ& dq, const X& x, const char* x_name) {
  checkData(model, data);
  checkSize(model, q, "q");
  checkSize(model, dq, "dq");
  checkSize(model, x, x_name);
}

}  // namespace dynid
