// The runs wing's shared room for the commands that fit a training set (identify, summarize): what
// a fit takes from one dataset besides its samples.
#pragma once

#include <string>
#include <vector>

#include "analysis/estimation/training_rows.hpp"
#include "analysis/logs/rest.hpp"
#include "analysis/records/prepare_record.hpp"
#include "core/model.hpp"
#include "core/trajectory.hpp"
#include "identifiability/rows/fit_rows.hpp"

namespace dynid {

/// What a fit takes from one training set besides its samples: the rest velocities (given or
/// measured on it), the torque filter it reproduces and the rows it fits.
struct TrainingSet {
  explicit TrainingSet(const Model& m) : model(m), rows(m) {}
  PreparationFound preparation;  // the prepare.json beside the file (none for data in memory)
  /// The filter the rows reproduce (rows.filter()), or the one found when nothing needs it.
  TorqueFilter torque_filter;
  std::string torque_filter_source;  // where it came from, or why there is none
  int filter_reach = 0;              // [samples]; 0 when no row is filtered
  std::vector<RestVelocity> rest;    // per joint
  Model model;                       // the model with those rest velocities
  FitRows rows;
};

/// The training set of the dataset `file` (or of `data` in memory, which `file` then only names):
/// rest velocities from `rest_velocity` (one for all, or per joint; empty: measured on the
/// first kRestSamples samples), the torque's filter from `choice` (std::nullopt: the prepare.json
/// beside the file's; data in memory: none), reproduced on the friction columns when the model has
/// a drive term that needs sign(dq). InputErrors name the file.
TrainingSet trainingSetOf(const Model& model, const std::string& file, const Trajectory* data,
                          const std::vector<double>& rest_velocity,
                          const TorqueFilterChoice& choice);

}  // namespace dynid
