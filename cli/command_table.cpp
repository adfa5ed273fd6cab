#include "cli/command_table.hpp"

#include <algorithm>
#include <iostream>
#include <set>

#include "cli/commands.hpp"
#include "reports/output.hpp"

namespace dynid::cli {

const std::vector<CommandEntry>& commandTable() {
  static const std::vector<CommandEntry> table = {
      {"model",
       "inspect a robot, check physical consistency, export URDF/JSON/MJCF, attach a known body",
       runModel,
       {"show", "check", "export", "attach"}},
      {"dynamics",
       "inverse dynamics, mass matrix and forward dynamics at a state",
       runDynamics,
       {}},
      {"simulate", "simulate a controlled robot and write a dataset CSV", runSimulate, {}},
      {"prepare",
       "a raw log (irregular stamps, no ddq) into a filtered dataset CSV",
       runPrepare,
       {}},
      {"identifiability",
       "base parameters: what the torques can and cannot determine",
       runIdentifiability,
       {}},
      {"excite", "design the motion that best determines the base parameters", runExcite, {}},
      {"identify",
       "least-squares (OLS/WLS/physically consistent) base parameters",
       runIdentify,
       {}},
      {"summarize",
       "least-squares summaries of logs: small, mergeable, what identify --summaries reads",
       runSummarize,
       {}},
      {"predict",
       "a model's or an estimate's torques on a dataset, errors and a figure",
       runPredict,
       {}},
      {"payload", "what was added at the flange of an identified arm; drive gains", runPayload, {}},
      {"monitor", "watch a log or live samples for external torques (collisions)", runMonitor, {}},
      {"audit", "do estimates from separate sessions agree within their sigma?", runAudit, {}},
      {"fleet",
       "many robots of one model: the fleet's prior, the robots outside it, each one's estimate",
       runFleet,
       {}},
      {"search", "the paper's GC-error search: nlo, ga or hybrid", runSearch, {}},
      {"refine",
       "Ceres least squares on the GC residuals from a search or estimate",
       runRefine,
       {}},
      {"demo", "the paper's study on the built-in PUMA 560, with a report", runDemo, {}},
      {"study", "every method on your own log: torque fit and motion prediction", runStudy, {}},
      {"batch",
       "a grid of study runs in parallel, resumable and shardable; merge",
       runBatch,
       {"merge"}},
      {"upgrade", "rewrite a document of an earlier version in the current one", runUpgrade, {}},
      {"rerun", "run a document's recorded command again and compare", runRerun, {}},
      {"completion", "a bash or zsh completion script for dynid", runCompletion, {}},
      {"man", "write dynid's man pages", runManPages, {}},
  };
  return table;
}

const CommandEntry* findCommand(const std::string& name) {
  for (const CommandEntry& entry : commandTable())
    if (name == entry.name) return &entry;
  return nullptr;
}

std::string usageText() {
  std::string text =
      "usage: dynid <command> [options]   (dynid help <command>, or dynid <command> --help, for "
      "its options)\n\ncommands:\n";
  for (const CommandEntry& entry : commandTable()) {
    std::string name = entry.name;
    for (std::size_t i = 0; i < entry.subcommands.size(); ++i)
      name.append(i == 0 ? " " : "|").append(entry.subcommands[i]);
    if (std::string(entry.name) == "batch") name = "batch [merge]";
    name.resize(std::max<std::size_t>(name.size() + 1, 25), ' ');
    text += "  " + name + entry.summary + "\n";
  }
  return text +
         "\nrobots: --robot puma560, puma560-consistent or panda (built in), a .urdf file, or a "
         "dynid .json model\n"
         "outputs: '-' names standard output wherever an option writes one file\n"
         "exit codes: 0 success, 1 runtime or data error, 2 usage error, 130 interrupted (Ctrl-C; "
         "the best result so far is written)\n"
         "version: dynid --version\n";
}

std::vector<CatalogueEntry> optionCatalogue() {
  std::vector<CatalogueEntry> out;
  std::vector<CommandOptions> recorded;
  setOptionCatalogue(&recorded);
  const auto record = [&](const CommandEntry& entry, const std::vector<std::string>& args,
                          const std::string& path) {
    recorded.clear();
    try {
      entry.run(args);
    } catch (...) {
      setOptionCatalogue(nullptr);
      throw;
    }
    for (CommandOptions& options : recorded)
      out.push_back({path, entry.summary, std::move(options)});
  };
  for (const CommandEntry& entry : commandTable()) {
    const std::string name = entry.name;
    if (entry.subcommands.empty() || name == "batch") record(entry, {}, name);
    for (const char* sub : entry.subcommands) record(entry, {sub}, name + " " + sub);
  }
  setOptionCatalogue(nullptr);
  return out;
}

namespace {

/// The options of `entry` that take a value, and all of them, as "--a --b".
std::string optionWords(const CatalogueEntry& entry, bool valued_only) {
  std::string words;
  for (const OptionEntry& o : entry.options.options)
    if (!valued_only || !o.parameter.empty()) words += (words.empty() ? "--" : " --") + o.name;
  return words;
}

/// "show check export": a command's subcommands, for a shell's word list.
std::string subcommandWords(const CommandEntry& entry) {
  std::string words;
  for (const char* sub : entry.subcommands) words.append(words.empty() ? "" : " ").append(sub);
  return words;
}

/// The options whose value is a robot: built-in names complete as well as files.
const std::set<std::string>& robotOptionNames() {
  static const std::set<std::string> names = {"robot", "init", "truth", "prior", "controller-robot",
                                              "arm"};
  return names;
}

/// `text` quoted for a zsh _arguments description inside single quotes.
std::string zshDescription(std::string text) {
  if (const std::size_t cut = text.find(" ("); cut != std::string::npos && cut > 20)
    text.resize(cut);
  if (text.size() > 70) text = text.substr(0, 67) + "...";
  std::string out;
  for (char c : text) {
    if (c == '\'') {
      out += "'\\''";
      continue;
    }
    if (c == '[' || c == ']' || c == ':' || c == '\\') out += '\\';
    out += c;
  }
  return out;
}

/// `text` for roff: backslashes and hyphens escaped, a leading '.' or '\'' neutralised.
std::string roff(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '\\')
      out += "\\e";
    else if (c == '-')
      out += "\\-";
    else
      out += c;
  }
  if (!out.empty() && (out[0] == '.' || out[0] == '\'')) out.insert(0, "\\&");
  return out;
}

std::string upper(std::string text) {
  for (char& c : text)
    if (c >= 'a' && c <= 'z') c = static_cast<char>(c - 'a' + 'A');
  return text;
}

std::string joined(std::string path, char separator) {
  std::replace(path.begin(), path.end(), ' ', separator);
  return path;
}

}  // namespace

std::string bashCompletion(const std::vector<CatalogueEntry>& catalogue) {
  std::string commands = "help";
  for (const CommandEntry& entry : commandTable()) commands += std::string(" ") + entry.name;
  std::string text =
      "# bash completion for dynid, generated by `dynid completion bash` from the commands' own\n"
      "# option tables.\n"
      "_dynid() {\n"
      "  local cur=${COMP_WORDS[COMP_CWORD]} prev=${COMP_WORDS[COMP_CWORD-1]}\n"
      "  if (( COMP_CWORD == 1 )); then\n"
      "    COMPREPLY=($(compgen -W '" +
      commands +
      " --help --version' -- \"$cur\"))\n"
      "    return\n"
      "  fi\n"
      "  local path=${COMP_WORDS[1]} subs= plain=\n"
      "  case $path in\n";
  for (const CommandEntry& entry : commandTable()) {
    if (entry.subcommands.empty()) continue;
    const std::string subs = subcommandWords(entry);
    // A command that also runs without a subcommand (batch MANIFEST) completes files there too.
    const bool plain = std::string(entry.name) == "batch";
    text += "    " + std::string(entry.name) + ") subs='" + subs + "' plain=" + (plain ? "1" : "") +
            " ;;\n";
  }
  text += "    help) COMPREPLY=($(compgen -W '" + commands.substr(5) +
          "' -- \"$cur\")); return ;;\n"
          "  esac\n"
          "  if [[ -n $subs && \" $subs \" == *\" ${COMP_WORDS[2]} \"* ]]; then\n"
          "    path=\"$path ${COMP_WORDS[2]}\"\n"
          "  elif [[ -n $subs ]] && (( COMP_CWORD == 2 )) && [[ $cur != -* ]]; then\n"
          "    COMPREPLY=($(compgen -W \"$subs\" -- \"$cur\"))\n"
          "    [[ -n $plain ]] && COMPREPLY+=($(compgen -f -- \"$cur\"))\n"
          "    return\n"
          "  fi\n"
          "  local opts= valued=\n"
          "  case $path in\n";
  for (const CatalogueEntry& entry : catalogue)
    text += "    '" + entry.path + "') opts='" + optionWords(entry, false) + "' valued=' " +
            optionWords(entry, true) + " ' ;;\n";
  std::string robots;
  for (const std::string& r : robotOptionNames()) robots += (robots.empty() ? "--" : "|--") + r;
  text +=
      "  esac\n"
      "  if [[ $prev == --* && $valued == *\" $prev \"* ]]; then\n"
      "    case $prev in\n"
      "      " +
      robots +
      ") COMPREPLY=($(compgen -W 'puma560 puma560-consistent panda' -- \"$cur\")"
      " $(compgen -f -- \"$cur\")) ;;\n"
      "      *) COMPREPLY=($(compgen -f -- \"$cur\")) ;;\n"
      "    esac\n"
      "  elif [[ $cur == -* ]]; then\n"
      "    COMPREPLY=($(compgen -W \"$opts\" -- \"$cur\"))\n"
      "  else\n"
      "    COMPREPLY=($(compgen -f -- \"$cur\"))\n"
      "  fi\n"
      "}\n"
      "complete -o filenames -F _dynid dynid\n";
  return text;
}

std::string zshCompletion(const std::vector<CatalogueEntry>& catalogue) {
  std::string text =
      "#compdef dynid\n"
      "# zsh completion for dynid, generated by `dynid completion zsh` from the commands' own\n"
      "# option tables.\n"
      "_dynid() {\n"
      "  local -a commands\n"
      "  commands=(\n";
  for (const CommandEntry& entry : commandTable())
    text += "    '" + std::string(entry.name) + ":" + zshDescription(entry.summary) + "'\n";
  text +=
      "  )\n"
      "  if (( CURRENT == 2 )); then\n"
      "    _describe 'dynid command' commands\n"
      "    return\n"
      "  fi\n"
      "  local path=$words[2]\n"
      "  case $path in\n";
  for (const CommandEntry& entry : commandTable()) {
    if (entry.subcommands.empty()) continue;
    const std::string subs = subcommandWords(entry);
    text += "    " + std::string(entry.name) +
            ")\n"
            "      if (( CURRENT == 3 )); then _values 'subcommand' " +
            subs +
            "; return; fi\n"
            "      if [[ \" " +
            subs +
            " \" == *\" $words[3] \"* ]]; then path=\"$path $words[3]\"; shift words; "
            "(( CURRENT-- )); fi ;;\n";
  }
  text +=
      "  esac\n"
      "  shift words\n"
      "  (( CURRENT-- ))\n"
      "  case $path in\n";
  for (const CatalogueEntry& entry : catalogue) {
    text += "    '" + entry.path + "')\n      _arguments -s";
    for (const OptionEntry& o : entry.options.options) {
      text += " \\\n        '--" + o.name + "[" + zshDescription(o.help) + "]";
      if (!o.parameter.empty())
        text += robotOptionNames().count(o.name) ? ":robot:_files" : ":value:_files";
      text += "'";
    }
    text += " \\\n        '*:file:_files' ;;\n";
  }
  text +=
      "  esac\n"
      "}\n"
      "_dynid \"$@\"\n";
  return text;
}

std::vector<std::pair<std::string, std::string>> manPages(
    const std::vector<CatalogueEntry>& catalogue) {
  const std::string header_tail = "\" 1 \"\" \"dynid " + roff(versionText()) + "\" \"dynid\"\n";
  const std::string exit_status =
      ".SH EXIT STATUS\n0 success, 1 runtime or data error, 2 usage error, 130 interrupted "
      "(Ctrl\\-C; the best result so far is written).\n";
  std::vector<std::pair<std::string, std::string>> pages;
  std::string overview = ".TH \"DYNID" + header_tail +
                         ".SH NAME\ndynid \\- estimate and explain the inertial parameters of "
                         "robot manipulators\n.SH SYNOPSIS\n.B dynid\n\\fIcommand\\fR "
                         "[\\fIoptions\\fR]\n.SH COMMANDS\n";
  for (const CommandEntry& entry : commandTable())
    overview += ".TP\n.B " + roff(entry.name) + "\n" + roff(entry.summary) + "\n";
  std::string see_also;
  for (const CatalogueEntry& entry : catalogue)
    see_also += (see_also.empty() ? "" : ",\n") + roff("dynid-" + joined(entry.path, '-')) + "(1)";
  overview += exit_status + ".SH SEE ALSO\n" + see_also + "\n";
  pages.emplace_back("dynid.1", overview);
  for (const CatalogueEntry& entry : catalogue) {
    const std::string name = "dynid-" + joined(entry.path, '-');
    std::string page = ".TH \"" + upper(roff(name)) + header_tail + ".SH NAME\n" + roff(name) +
                       " \\- " + roff(entry.summary) + "\n.SH SYNOPSIS\n" +
                       roff(entry.options.usage) + "\n.SH OPTIONS\n";
    for (const OptionEntry& o : entry.options.options) {
      // Appended piece by piece: GCC 12 warns (-Wrestrict, falsely) on "literal" + string.
      page.append(".TP\n.B \\-\\-").append(roff(o.name));
      if (!o.parameter.empty()) page.append(" \\fI").append(roff(o.parameter)).append("\\fR");
      page.append("\n").append(roff(o.help)).append("\n");
    }
    page += exit_status + ".SH SEE ALSO\ndynid(1)\n";
    pages.emplace_back(name + ".1", page);
  }
  return pages;
}

int runCompletion(const std::vector<std::string>& args) {
  po::options_description options("dynid completion");
  options.add_options()("shell", po::value<std::string>()->required(), "bash or zsh")(
      "out", po::value<std::string>()->default_value("-"),
      "file to write, or - for standard output");
  po::positional_options_description positional;
  positional.add("shell", 1);
  po::variables_map vm;
  if (!parseCommandLine(args, options, "dynid completion bash|zsh [--out FILE]", vm, &positional))
    return kExitOk;
  const std::string shell = vm["shell"].as<std::string>();
  if (shell != "bash" && shell != "zsh")
    throw UsageError("the shell must be bash or zsh, not '" + shell + "'");
  const std::vector<CatalogueEntry> catalogue = optionCatalogue();
  const std::string out = vm["out"].as<std::string>();
  if (writeOutput(out, shell == "bash" ? bashCompletion(catalogue) : zshCompletion(catalogue)))
    std::cerr << "wrote " << out << "\n";
  return kExitOk;
}

int runManPages(const std::vector<std::string>& args) {
  po::options_description options("dynid man");
  options.add_options()("out", po::value<std::string>()->required(),
                        "directory to write dynid.1 and dynid-<command>.1 into");
  po::variables_map vm;
  if (!parseCommandLine(args, options, "dynid man --out DIR", vm)) return kExitOk;
  const std::string dir = outputDirectoryOption(vm);
  const std::vector<std::pair<std::string, std::string>> pages = manPages(optionCatalogue());
  writeReportFiles(dir, pages);
  std::cout << "wrote " << pages.size() << " man pages to " << dir << "\n";
  return kExitOk;
}

}  // namespace dynid::cli
