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

/// Throws InputError unless `data` was built for this model as it is now: every workspace sized
/// for its joints and the regressor as wide as its parameter layout (a Data built before
/// setDriveTerms changed the layout is refused), and the model finalized.
template <typename Scalar>
void checkData(const ModelTpl<Scalar>& model, const DataTpl<Scalar>& data) {
  const int n = model.numJoints();
  const auto joints = static_cast<std::size_t>(n);
  if (!model.finalized() || data.liMi.size() != joints || data.v.size() != joints ||
      data.composite.size() != joints || data.articulated_inertia.size() != joints ||
      data.articulated_written.size() != joints || data.column_force.size() != joints ||
      data.column_frame.size() != joints || data.joint_axes.size() != joints * joints ||
      data.tau.size() != n || data.ddq.size() != n || data.M.rows() != n || data.D.size() != n ||
      data.q_stage.size() != n || data.Y.rows() != n)
    throw InputError("Data was built for another model, or the model '" + model.name +
                     "' was not finalized");
  if (data.Y.cols() != model.parameterLayout().size())
    throw InputError("Data's regressor has " + std::to_string(data.Y.cols()) + " columns, model '" +
                     model.name + "' has " + std::to_string(model.parameterLayout().size()) +
                     " parameters (drive terms " + driveTermsText(model.driveTerms()) +
                     "): build the Data after setDriveTerms");
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
