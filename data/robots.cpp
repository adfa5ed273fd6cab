#include "data/robots.hpp"

#include "core/errors.hpp"
#include "data/io.hpp"
#include "data/model_json.hpp"
#include "data/panda.hpp"
#include "data/puma560.hpp"
#include "data/urdf.hpp"

namespace dynid {

namespace {
bool endsWith(const std::string& s, const std::string& suffix) {
  return s.size() >= suffix.size() &&
         s.compare(s.size() - suffix.size(), suffix.size(), suffix) == 0;
}
}  // namespace

Model loadRobot(const std::string& spec, const RobotOptions& options,
                std::vector<std::string>* warnings) {
  if (spec == "puma560") return makePuma560(options.drives);
  if (spec == "puma560-consistent") return makePuma560Consistent(options.drives);
  if (spec == "panda") return makePanda(options.drives);
  if (endsWith(spec, ".urdf") || endsWith(spec, ".xml"))
    return loadUrdf(spec, {options.drives, options.strict}, warnings);
  if (endsWith(spec, ".json")) {
    Model model = modelFromJson(readFile(spec), spec);
    if (options.drives && !model.drives_enabled) {
      model.drives_enabled = true;
      model.finalize();
    }
    return model;
  }
  throw InputError(
      "unknown robot '" + spec +
      "': expected puma560, puma560-consistent, panda, a .urdf file or a dynid .json model");
}

}  // namespace dynid
