// JSON pieces shared by dynid search and dynid refine.
#pragma once

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "search/parameter_space.hpp"

namespace dynid::cli {

/// The estimate at free parameters x in the paper (7 per link) and standard (10) forms, keyed by
/// parameter name.
nlohmann::json searchEstimateJson(const ParameterSpace& space, const Eigen::VectorXd& x);

}  // namespace dynid::cli
