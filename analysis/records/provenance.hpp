// What made a document: every document a command writes carries "provenance" — which dynid
// (version and commit), the command line (or the Python call), the working directory, its inputs
// by content (SHA-256), the seed and thread count it ran with, when it started and how long it
// took, and which of the document's own fields are wall-clock times. `dynid rerun` reads it back,
// runs the command again and compares (rerunDifferences): two runs of a command give the same
// document apart from those time fields. The front ends say where a run begins (beginRun); the
// writers in reports/ stamp what they write (withProvenance).
#pragma once

#include <chrono>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace dynid {

/// An input by content: its path as named (relative to the working directory) and SHA-256 (empty
/// for a stream, which cannot be read again, or a file gone or replaced since it was read).
struct InputDigest {
  std::string file;
  std::string sha256;
};

/// One run of a command or call, as its documents record it.
struct RunProvenance {
  std::string interface;  // "cli" or "python"
  std::string version;    // dynid's, "0.2.0"
  std::string commit;     // the build's git commit ("unknown" outside a checkout)
  /// cli: the command line, "dynid" first; python: one element, the call ("dynid.identify(...)").
  std::vector<std::string> command;
  std::string working_directory;  // absolute
  std::vector<InputDigest> inputs;
  std::optional<std::uint64_t> seed;  // the seed the command ran with (its default included)
  std::optional<int> threads;         // the threads it ran on (0 resolved to the cores)
  std::string started;                // UTC, ISO 8601 to the second: "2026-12-02T17:04:05Z"
  double seconds = 0;                 // from the start to the document's writing
};

/// The JSON pointers of a document kind's wall-clock fields, "*" for every element of an array
/// ("/history/*/seconds"): what differs between two runs of the same command besides the
/// provenance's own started and seconds. Empty for a kind with none.
std::vector<std::string> timeFieldsOf(const std::string& kind);

/// "provenance" as documents write it: version, commit, interface, command, working_directory,
/// inputs [{file, sha256 (null for a stream)}], seed, threads (null where the command has none),
/// started, seconds and time_fields (timeFieldsOf(kind), each a pointer into the document).
nlohmann::json provenanceJson(const RunProvenance& run, const std::string& kind);

/// A document's provenance read back (`file` names it in messages). Throws ParseError naming the
/// file and the field for a missing or malformed one.
RunProvenance provenanceFrom(const nlohmann::json& document, const std::string& file);

/// The current time as RunProvenance::started writes it.
std::string utcTimestamp(std::chrono::system_clock::time_point when);

// The run of this process (the CLI: one command per process). A library caller that begins none
// writes documents without provenance.

/// Begins the run whose documents this process writes from now on: `run`'s interface, version,
/// commit, command and working directory (its inputs, seed, threads and times are filled as the
/// run goes: the inputs from data/io.hpp's commandInputs, hashed when a document is written).
void beginRun(RunProvenance run);
void noteRunSeed(std::uint64_t seed);
void noteRunThreads(int threads);
/// The current run as a document written now would record it (inputs hashed, seconds so far);
/// nullopt when no run has begun.
std::optional<RunProvenance> currentRun();

/// `document` (a dynid document: an object with "kind") with "provenance" set from the current
/// run; unchanged when no run has begun.
nlohmann::json withProvenance(nlohmann::json document);

/// What differs between a document and its rerun, after removing from both the provenance's
/// started and seconds and every field its time_fields name: each difference as "POINTER: A ->
/// B" (at most `limit`, then a count of the rest); empty when the two are byte-identical apart
/// from those. The values of `output_options` in the command (the word after each, or after its
/// "=": where each run wrote) are left out of the comparison; every other word is compared.
std::vector<std::string> rerunDifferences(const nlohmann::json& original,
                                          const nlohmann::json& rerun,
                                          const std::vector<std::string>& output_options,
                                          std::size_t limit = 20);

}  // namespace dynid
