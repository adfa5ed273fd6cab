#include "analysis/runs/summarize.hpp"

#include <algorithm>
#include <memory>
#include <optional>

#include "analysis/estimation/streaming.hpp"
#include "analysis/runs/arm.hpp"
#include "analysis/runs/training.hpp"
#include "core/errors.hpp"
#include "core/format.hpp"
#include "data/dataset_csv.hpp"
#include "data/digest/sha256.hpp"

namespace dynid {

namespace {

/// The base parameters' names, in order.
std::vector<std::string> baseNames(const BaseParameters& base) {
  std::vector<std::string> out;
  for (int j = 0; j < base.numBase(); ++j) out.push_back(base.baseName(j));
  return out;
}

/// One log's summary: its training set as identify takes it, then its samples streamed; nullopt
/// when stopped first.
std::optional<Summary> summarizeOne(const SummarizeRequest& request, const BaseParameters& base,
                                    const std::string& file, const Trajectory* data,
                                    ThreadPool& pool) {
  DatasetHead head;  // the file read once where the training set allows
  head.pool = &pool;
  const TrainingSet training =
      trainingSetOf(request.model, file, data, request.rest_velocity, request.torque_filter, &head);
  const Model& model = training.model;
  SummaryBuilder builder(base, model);
  try {
    if (data) {
      builder.addTrajectory(model, *data, &pool, &training.rows);
    } else {
      for (Trajectory& chunk : head.chunks) {
        if (request.control.check()) return std::nullopt;
        builder.addTrajectory(model, chunk, &pool, &training.rows);
        chunk = Trajectory();
      }
      std::unique_ptr<DatasetReader> reader =
          head.reader ? std::move(head.reader)
                      : std::make_unique<DatasetReader>(file, model.numJoints());
      Trajectory chunk;
      while (reader->read(chunk, kStreamChunkSamples, &pool) > 0) {
        if (request.control.check()) return std::nullopt;
        builder.addTrajectory(model, chunk, &pool, &training.rows);
      }
    }
  } catch (const InputError& e) {
    throw InputError(file + ": " + e.what());
  }
  Summary out;
  out.model = request.model;
  out.model_source = modelSourceOf(request.robot_spec);
  out.structural = request.structural;
  out.base_names = baseNames(base);
  out.factors = builder.finish();
  SummarySource source;
  source.file = data ? std::string() : file;
  source.sha256 = data ? std::string() : sha256OfFile(file);
  source.samples = out.factors.numSamples();
  source.rest_velocity = model.rest_velocities;
  if (training.filter_reach > 0) source.torque_filter = training.torque_filter;
  source.torque_filter_source = training.torque_filter_source;
  out.sources.push_back(std::move(source));
  return out;
}

}  // namespace

SummarizeOutcome summarizeRun(const SummarizeRequest& request) {
  request.check();
  const BaseParameters base = structuralBaseParameters(request.model, request.structural);
  ThreadPool pool(resolveThreads(request.threads));
  SummarizeOutcome out;
  if (request.data) {
    out.summaries.push_back(*summarizeOne(request, base, request.data_name, request.data, pool));
    return out;
  }
  for (std::size_t i = 0; i < request.data_files.size(); ++i) {
    const std::string& file = request.data_files[i];
    request.control.say("summarize: " + file + " (" + std::to_string(i + 1) + " of " +
                        std::to_string(request.data_files.size()) + ")");
    std::optional<Summary> one = summarizeOne(request, base, file, nullptr, pool);
    if (!one) {
      out.interrupted = true;
      return out;
    }
    out.summaries.push_back(std::move(*one));
  }
  return out;
}

Summary mergeSummaries(const std::vector<const Summary*>& summaries,
                       const std::vector<std::string>& names) {
  if (summaries.empty()) throw InputError("no summary to merge");
  const Summary& first = *summaries.front();
  Summary out = first;
  for (std::size_t i = 1; i < summaries.size(); ++i) {
    const Summary& next = *summaries[i];
    const std::string name = i < names.size() ? names[i] : "summary " + std::to_string(i + 1);
    const std::string first_name = names.empty() ? "the first summary" : names.front();
    std::string why = kinematicsDifference(first.model, next.model, first_name + "'s robot");
    if (why.empty() && first.model.driveTerms().mask != next.model.driveTerms().mask)
      why = "its drive terms are " + driveTermsText(next.model.driveTerms()) + ", " + first_name +
            "'s " + driveTermsText(first.model.driveTerms());
    if (why.empty() && (first.structural.samples != next.structural.samples ||
                        first.structural.seed != next.structural.seed ||
                        first.structural.tolerance != next.structural.tolerance ||
                        first.base_names != next.base_names))
      why = "its base parameters are not " + first_name + "'s";
    if (!why.empty()) throw InputError(name + " cannot be merged with " + first_name + ": " + why);
    out.factors.merge(next.factors);
    out.sources.insert(out.sources.end(), next.sources.begin(), next.sources.end());
  }
  return out;
}

BaseParameters summaryBase(const Summary& summary, const std::string& name) {
  BaseParameters base = structuralBaseParameters(summary.model, summary.structural);
  std::vector<std::string> names = baseNames(base);
  if (names != summary.base_names ||
      jointSupport(base, summary.model).support != summary.factors.support())
    throw InputError(name + ": its base parameters (" + std::to_string(summary.base_names.size()) +
                     ") are not those of its robot here (" + std::to_string(names.size()) +
                     "): made by another version of dynid?");
  return base;
}

}  // namespace dynid
