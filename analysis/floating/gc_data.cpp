#include "analysis/floating/gc_data.hpp"

#include <string>

#include "analysis/floating/identifiability.hpp"
#include "core/errors.hpp"

namespace dynid {

FloatingGcData floatingGcData(const FloatingDataset& dataset,
                              const std::vector<Contact>& contacts) {
  const std::string file = dataset.file.empty() ? "the dataset" : dataset.file;
  if (!dataset.hasTorques())
    throw InputError(file +
                     ": the GC error rolls the motion out with the joint torques, and it "
                     "has none (tau:J columns)");
  FloatingGcData out{dataset.time, dataset.orientation, dataset.twist, dataset.q,
                     dataset.dq,   dataset.tau,         contacts,      {}};
  for (const Contact& c : contacts) {
    const FloatingDataset::Wrench* w = dataset.findWrench(c.name);
    if (w == nullptr || w->values.rows() != c.dimension())
      throw InputError(file + ": the GC error needs the " + std::to_string(c.dimension()) +
                       "-component wrench measured at the contact '" + c.name +
                       "' (wrench:" + c.name +
                       ":...); a contact known by its flag alone holds "
                       "by forces no measurement gives");
    out.wrenches.push_back(w->values);
  }
  return out;
}

FloatingGcData floatingGcData(const FloatingModel& model, const FloatingDataset& dataset,
                              const std::vector<std::string>& contacts) {
  std::vector<std::string> specs = contacts;
  if (specs.empty())
    for (const FloatingDataset::Wrench& w : dataset.wrenches)
      specs.push_back(w.frame + (w.values.rows() == 6 ? ":frame" : ""));
  return floatingGcData(dataset, contactsOf(model, specs));
}

}  // namespace dynid
