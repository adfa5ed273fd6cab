// The runs wing's shared room for the commands that fit a training set (identify, summarize): what
// a fit takes from one dataset besides its samples.
#pragma once

#include <memory>
#include <string>
#include <vector>

#include "analysis/estimation/training_rows.hpp"
#include "analysis/logs/rest.hpp"
#include "analysis/records/prepare_record.hpp"
#include "core/model.hpp"
#include "core/parallel.hpp"
#include "core/trajectory.hpp"
#include "data/dataset_csv.hpp"
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

/// A dataset file of at most kWholeHeadSamples samples (a 60 s log at 1 kHz) read whole for its
/// rest velocities, kept as the stream's chunks with its reader (at the end), so that the stream
/// takes them and the file is parsed once (summarize). A longer file keeps nothing (`reader` null):
/// the stream reads it again, its first samples' every column not held (46 MB at kRestSamples
/// Panda samples, where a second parse saves nothing against first-touching that memory). Null
/// too for data in memory, or a filtered torque whose rows need every sample's velocity first.
inline constexpr int kWholeHeadSamples = 1 << 16;
struct DatasetHead {
  ThreadPool* pool = nullptr;      // the caller's: the rows are parsed on its threads
  std::vector<Trajectory> chunks;  // kStreamChunkSamples samples each (the last fewer)
  std::unique_ptr<DatasetReader> reader;
};

/// The training set of the dataset `file` (or of `data` in memory, which `file` then only names):
/// rest velocities from `rest_velocity` (one for all, or per joint; empty: measured on the
/// first kRestSamples samples), the torque's filter from `choice` (std::nullopt: the prepare.json
/// beside the file's; data in memory: none), reproduced on the friction columns when the model has
/// a drive term that needs sign(dq). InputErrors name the file. With `head`, the file's first
/// samples are read into it when the rest velocities need only them (DatasetHead).
TrainingSet trainingSetOf(const Model& model, const std::string& file, const Trajectory* data,
                          const std::vector<double>& rest_velocity,
                          const TorqueFilterChoice& choice, DatasetHead* head = nullptr);

}  // namespace dynid
