#include "analysis/records/rerun.hpp"

#include <filesystem>

#include "analysis/records/document.hpp"
#include "core/errors.hpp"
#include "data/digest/sha256.hpp"
#include "data/io.hpp"

namespace dynid {

namespace {

namespace fs = std::filesystem;

/// Puts the value of `option` (the word after it, or after its "=" in one word) through `change`;
/// whether it was there.
template <class Change>
bool changeValue(std::vector<std::string>& arguments, const std::string& option, Change change) {
  for (std::size_t i = 0; i < arguments.size(); ++i) {
    if (arguments[i] == option && i + 1 < arguments.size()) {
      arguments[i + 1] = change(arguments[i + 1]);
      return true;
    }
    if (arguments[i].rfind(option + "=", 0) == 0) {
      arguments[i] = option + "=" + change(arguments[i].substr(option.size() + 1));
      return true;
    }
  }
  return false;
}

/// Each recorded input, found from `dir` with its recorded content.
void checkInputs(const RunProvenance& run, const fs::path& dir, const std::string& document) {
  for (const InputDigest& input : run.inputs) {
    if (input.sha256.empty())
      throw InputError(document + ": its input '" + input.file +
                       "' was read from a stream (a pipe or standard input), which cannot be "
                       "read again: run the command yourself with that input saved to a file");
    const fs::path path =
        fs::path(input.file).is_absolute() ? fs::path(input.file) : dir / input.file;
    std::error_code error;
    if (!fs::is_regular_file(path, error))
      throw InputError(document + ": its input '" + input.file + "' is not found (looked for " +
                       path.string() + "; recorded SHA-256 " + input.sha256 + ")");
    const std::string now = sha256OfFile(path.string());
    if (now != input.sha256)
      throw InputError(document + ": its input '" + path.string() +
                       "' changed since the document was made (SHA-256 recorded " + input.sha256 +
                       ", now " + now + "): a rerun would not be the same run");
  }
}

}  // namespace

RerunPlan planRerun(const RerunRequest& request) {
  RerunPlan plan;
  plan.original = parseJson(readFile(request.document), request.document);
  plan.run = provenanceFrom(plan.original, request.document);
  const RunProvenance& run = plan.run;
  if (run.interface != "cli" || run.command.empty() || run.command[0] != "dynid")
    throw InputError(request.document + ": made by a " + run.interface +
                     " call, not a dynid command: a rerun runs commands; call it again "
                     "(provenance.command records the call)");
  plan.document_name = fs::path(request.document).filename().string();
  std::error_code error;
  const fs::path out = fs::absolute(request.out, error);
  const fs::path here = fs::weakly_canonical(fs::absolute(request.document).parent_path(), error);
  if (fs::weakly_canonical(out, error) == here)
    throw InputError("`out` is the folder the document is in ('" + here.string() +
                     "'): name another; the rerun is compared with the document there");
  plan.working_directory = run.working_directory;
  if (!fs::is_directory(run.working_directory, error)) {
    plan.working_directory = fs::current_path(error).string();
    plan.notes.push_back("the recorded working directory " + run.working_directory +
                         " is not here: the command runs from " + plan.working_directory +
                         ", its relative inputs found from there");
  }
  checkInputs(run, plan.working_directory, request.document);
  plan.arguments.assign(run.command.begin() + 1, run.command.end());
  const std::vector<std::string>& outputs = request.output_options;
  if (outputs.empty()) throw InputError("`output_options`: none given");
  if (!changeValue(plan.arguments, outputs[0], [&](const std::string&) { return out.string(); }))
    throw InputError(request.document + ": its command (provenance.command) writes no " +
                     "output folder: nothing to compare");
  for (std::size_t k = 1; k < outputs.size(); ++k)
    if (changeValue(plan.arguments, outputs[k], [&](const std::string& value) {
          return (out / fs::path(value).filename()).string();
        }))
      plan.notes.push_back("the file its " + outputs[k] + " names goes into the new folder too");
  // Standard input ("-" for an input: a monitor reading a live stream) is not the recorded
  // stream: the rerun would wait on this terminal's.
  for (const std::string& word : plan.arguments)
    if (word == "-" || (word.size() > 2 && word.compare(word.size() - 2, 2, "=-") == 0))
      throw InputError(request.document +
                       ": its command read standard input ('-'), which cannot be read again: "
                       "run the command yourself with that input saved to a file");
  if (run.version != request.version || run.commit != request.commit)
    plan.notes.push_back("made by dynid " + run.version + " (commit " + run.commit +
                         "); this is dynid " + request.version + " (commit " + request.commit +
                         "): numbers may differ where the two do");
  return plan;
}

}  // namespace dynid
