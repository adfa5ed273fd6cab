// The dynid commands in one table: the dispatcher, the general usage, `dynid help`, the shell
// completion and the man pages all read it, and each command's options come from the command
// itself (parseCommandLine's catalogue mode), so none of them can drift from what is parsed.
#pragma once

#include <string>
#include <vector>

#include "cli/common.hpp"

namespace dynid::cli {

struct CommandEntry {
  const char* name;
  const char* summary;  // one line
  int (*run)(const std::vector<std::string>& args);
  std::vector<const char*> subcommands;  // "show", "check", "export" for model; empty: none
};

/// Every command, in the order the usage lists them.
const std::vector<CommandEntry>& commandTable();
/// The command named `name`, or nullptr.
const CommandEntry* findCommand(const std::string& name);
/// The general usage (dynid --help).
std::string usageText();

/// One command or subcommand ("model export") and its options.
struct CatalogueEntry {
  std::string path;  // "identify", "model export"
  std::string summary;
  CommandOptions options;
};
/// Every command's and subcommand's options, read from the commands themselves.
std::vector<CatalogueEntry> optionCatalogue();

/// bash and zsh completion scripts, and a man page (roff) per command, from the catalogue.
std::string bashCompletion(const std::vector<CatalogueEntry>& catalogue);
std::string zshCompletion(const std::vector<CatalogueEntry>& catalogue);
/// (file name, roff) pairs: dynid.1 and dynid-<command>[-<subcommand>].1.
std::vector<std::pair<std::string, std::string>> manPages(
    const std::vector<CatalogueEntry>& catalogue);

int runCompletion(const std::vector<std::string>& args);
int runManPages(const std::vector<std::string>& args);

}  // namespace dynid::cli
