// A document's recorded command made ready to run again (`dynid rerun`): its provenance read
// back, its inputs checked by content, its outputs moved into a new folder. The front end starts
// the command (this wing starts no process) and compares the new document with the recorded one
// (provenance.hpp's rerunDifferences).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/records/provenance.hpp"

namespace dynid {

struct RerunRequest {
  std::string document;  // the document whose command runs again
  std::string out;       // the new output folder (absolute, or the current directory's)
  std::string version;   // this dynid's version and commit: a recorded other one is noted
  std::string commit;
  /// The front end's options whose value is a path a command writes, as its command lines spell
  /// them: the output folder's first (replaced by `out`), then files (moved into `out` by name).
  /// rerunDifferences leaves their values out.
  std::vector<std::string> output_options;
};

struct RerunPlan {
  nlohmann::json original;             // the document as recorded
  RunProvenance run;                   // its provenance
  std::string document_name;           // its file name: the rerun writes the same into `out`
  std::vector<std::string> arguments;  // the command after "dynid", its outputs in `out`
  std::string working_directory;       // where it runs (the recorded one, else the current)
  std::vector<std::string> notes;      // what differs from the recorded run, and why
};

/// Reads the document's provenance and prepares its command: every recorded input found (relative
/// to the recorded working directory, or the current one when that is gone) with the recorded
/// SHA-256. Throws ParseError for a document without a readable provenance, InputError for one
/// made by a Python call, an input that is a stream (standard input, "-", among them), missing or
/// changed (naming it and both digests), `out` the document's own folder, or a command with no
/// output folder.
RerunPlan planRerun(const RerunRequest& request);

}  // namespace dynid
