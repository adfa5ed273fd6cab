#include "cli/search_output.hpp"

#include "core/parameters.hpp"

namespace dynid::cli {

nlohmann::json searchEstimateJson(const ParameterSpace& space, const Eigen::VectorXd& x) {
  const Model model = space.modelAt(x);
  nlohmann::json paper = nlohmann::json::object(), standard = nlohmann::json::object();
  const std::vector<std::string> paper_names = paperParameterNames(model.numJoints());
  for (int i = 0; i < model.numJoints(); ++i) {
    const auto p = standardToPaper(toStandardVector(model.inertias[i]));
    for (int k = 0; k < 7; ++k) paper[paper_names[7 * i + k]] = p[k];
  }
  const std::vector<std::string> names = standardParameterNames(model.parameterLayout());
  const Eigen::VectorXd theta = model.standardParameters();
  for (int k = 0; k < theta.size(); ++k) standard[names[k]] = theta[k];
  return {{"paper", paper}, {"standard", standard}};
}

}  // namespace dynid::cli
