// The command line's parsing for every command (declared in cli/common.hpp): full option names
// with suggestions for unknown ones, ranges from the option table (core/option_ranges.hpp), help
// and long help, and the option catalogue that completion and man pages read.
#include <algorithm>
#include <cmath>
#include <iostream>
#include <limits>
#include <sstream>

#include <boost/make_shared.hpp>

#include "analysis/records/provenance.hpp"
#include "cli/common.hpp"
#include "core/format.hpp"
#include "core/option_ranges.hpp"

namespace dynid::cli {

namespace {
std::vector<CommandOptions>* catalogue = nullptr;

/// Boost converts "-1" to an unsigned option as 2^64 - 1; an unsigned option (--seed) given a
/// negative value is a usage error instead.
void rejectNegativeUnsigned(const po::parsed_options& parsed,
                            const po::options_description& options) {
  for (const po::option& o : parsed.options) {
    const po::option_description* d = options.find_nothrow(o.string_key, false);
    if (d == nullptr) continue;
    const po::value_semantic* semantic = d->semantic().get();
    const bool is_unsigned =
        dynamic_cast<const po::typed_value<std::uint64_t>*>(semantic) != nullptr ||
        dynamic_cast<const po::typed_value<unsigned>*>(semantic) != nullptr;
    for (const std::string& v : o.value)
      if (is_unsigned && v.find('-') != std::string::npos)
        throw po::error("--" + o.string_key + " must be a non-negative integer, not '" + v + "'");
  }
}

/// The numeric value of an option as a double (false when it is not numeric).
bool numericValue(const boost::any& value, double* x) {
  if (const auto* d = boost::any_cast<double>(&value))
    *x = *d;
  else if (const auto* i = boost::any_cast<int>(&value))
    *x = *i;
  else if (const auto* l = boost::any_cast<long>(&value))
    *x = static_cast<double>(*l);
  else if (const auto* ll = boost::any_cast<long long>(&value))
    *x = static_cast<double>(*ll);
  else
    return false;
  return true;
}

/// Every numeric option finite and within its range (core/option_ranges.hpp), defaults included.
void checkRanges(const po::variables_map& vm, const std::string& command) {
  for (const auto& [name, entry] : vm) {
    double x = 0.0;
    if (!numericValue(entry.value(), &x)) continue;
    if (!std::isfinite(x)) throw po::error("--" + name + " must be a finite number");
    try {
      checkOption(command, name, x, "--" + name);
    } catch (const InputError& e) {
      throw po::error(e.what());
    }
  }
}

/// "arg (=0.050000000000000003)" -> "arg (=0.05)": a numeric default in its shortest exact form.
std::string shownDefault(std::string name) {
  const std::size_t open = name.find("(="), close = name.rfind(')');
  if (open == std::string::npos || close == std::string::npos || close < open) return name;
  const std::string value = name.substr(open + 2, close - open - 2);
  char* end = nullptr;
  const double x = std::strtod(value.c_str(), &end);
  if (value.empty() || end != value.c_str() + value.size()) return name;  // not a number
  return name.replace(open + 2, close - open - 2, formatNumber(x));
}

/// An option as --help shows it: the original's parameter text ("arg (=10)"), nothing else (it
/// parses nothing; the help's copy of the options is never parsed with).
class ShownValue : public po::value_semantic {
 public:
  explicit ShownValue(const po::value_semantic& original)
      : name_(shownDefault(original.name())),
        min_(original.min_tokens()),
        max_(original.max_tokens()),
        composing_(original.is_composing()),
        required_(original.is_required()) {}
  std::string name() const override { return name_; }
  unsigned min_tokens() const override { return min_; }
  unsigned max_tokens() const override { return max_; }
  bool is_composing() const override { return composing_; }
  bool is_required() const override { return required_; }
  void parse(boost::any&, const std::vector<std::string>&, bool) const override {}
  bool apply_default(boost::any&) const override { return false; }
  void notify(const boost::any&) const override {}

 private:
  std::string name_;
  unsigned min_, max_;
  bool composing_, required_;
};

/// The options as --help shows them: each numeric option's help and range from the one option
/// table (core/option_ranges.hpp; the commands declare them without a description), so the help
/// shows the range checked.
po::options_description helpOptions(const po::options_description& all,
                                    const std::string& command) {
  po::options_description shown;
  for (const auto& option : all.options()) {
    std::string text = option->description();
    if (const OptionRule* rule = findOptionRule(command, option->long_name())) {
      // Appended piece by piece: GCC 12 warns (-Wrestrict, falsely) on the concatenated form.
      text.assign(rule->help).append(" (").append(optionRangeText(*rule)).append(")");
    }
    std::string name = option->long_name();
    const std::string display = option->format_name();  // "-h [ --help ]" when it has a short one
    if (display.size() > 1 && display[0] == '-' && display[1] != '-')
      name.append(1, ',').append(1, display[1]);
    shown.add(boost::make_shared<po::option_description>(
        name.c_str(), new ShownValue(*option->semantic()), text.c_str()));
  }
  return shown;
}

/// "-h" where an option may stand becomes "--help" (the only short option; short options are
/// otherwise off so that negative numbers are values). A "-h" that is the value of an option
/// ("--out -h") stays.
std::vector<std::string> withLongHelp(const std::vector<std::string>& args,
                                      const po::options_description& all) {
  std::vector<std::string> out;
  bool value_next = false;
  for (std::size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    if (a == "--") {
      out.insert(out.end(), args.begin() + static_cast<std::ptrdiff_t>(i), args.end());
      break;
    }
    if (!value_next && a == "-h") {
      out.emplace_back("--help");
      continue;
    }
    out.push_back(a);
    if (value_next) {
      value_next = false;
      continue;
    }
    if (a.size() > 2 && a.compare(0, 2, "--") == 0 && a.find('=') == std::string::npos) {
      const po::option_description* d = all.find_nothrow(a.substr(2), false);
      value_next = d != nullptr && d->semantic()->min_tokens() > 0;
    }
  }
  return out;
}

/// Edit distance of two short strings (the option names a typo may mean).
std::size_t editDistance(const std::string& a, const std::string& b) {
  std::vector<std::size_t> row(b.size() + 1);
  for (std::size_t j = 0; j <= b.size(); ++j) row[j] = j;
  for (std::size_t i = 1; i <= a.size(); ++i) {
    std::size_t diagonal = row[0];
    row[0] = i;
    for (std::size_t j = 1; j <= b.size(); ++j) {
      const std::size_t up = row[j];
      row[j] = std::min({row[j] + 1, row[j - 1] + 1, diagonal + (a[i - 1] == b[j - 1] ? 0 : 1)});
      diagonal = up;
    }
  }
  return row[b.size()];
}

/// " (did you mean --method?)" for an unknown option that starts one (an abbreviation) or is
/// within two edits of one; empty when none is close.
std::string suggestion(const std::string& given, const po::options_description& all) {
  std::string name = given;
  while (!name.empty() && name[0] == '-') name.erase(0, 1);
  if (const std::size_t eq = name.find('='); eq != std::string::npos) name.resize(eq);
  if (name.empty()) return "";
  std::vector<std::string> close;
  for (const auto& option : all.options()) {
    const std::string& candidate = option->long_name();
    if (candidate.compare(0, name.size(), name) == 0 || editDistance(name, candidate) <= 2)
      close.push_back("--" + candidate);
  }
  if (close.empty() || close.size() > 6) return "";
  std::string text = " (options are written in full; did you mean ";
  for (std::size_t i = 0; i < close.size(); ++i)
    text += (i == 0 ? "" : i + 1 == close.size() ? " or " : ", ") + close[i];
  return text + "?)";
}

/// The command: the usage line's second word ("dynid simulate ...").
std::string commandOf(const std::string& usage) {
  const std::size_t start = usage.find(' ') + 1, end = usage.find(' ', start);
  return usage.substr(start, end - start);
}

}  // namespace

bool parseCommandLine(const std::vector<std::string>& args, const po::options_description& options,
                      const std::string& usage, po::variables_map& vm,
                      const po::positional_options_description* positional) {
  po::options_description all;
  all.add_options()("help,h", "show this help")("version", "print dynid's version and commit");
  all.add(options);
  const std::string command = commandOf(usage);
  if (catalogue != nullptr) {
    CommandOptions entry{usage, {}};
    const po::options_description shown = helpOptions(all, command);
    for (const auto& option : shown.options())
      entry.options.push_back(
          {option->long_name(),
           option->semantic()->max_tokens() > 0 ? option->semantic()->name() : std::string(),
           option->description()});
    catalogue->push_back(std::move(entry));
    return false;
  }
  try {
    // Long options only, written in full: no short options (so negative numbers such as
    // "--q -0.5,1" are values, and -h is translated before parsing), no abbreviations (a typo must
    // not select another option).
    const auto style = (po::command_line_style::unix_style ^ po::command_line_style::allow_short) &
                       ~po::command_line_style::allow_guessing;
    po::command_line_parser parser(withLongHelp(args, all));
    parser.options(all).style(style);
    if (positional != nullptr) parser.positional(*positional);
    po::parsed_options parsed = [&] {
      try {
        return parser.run();
      } catch (const po::unknown_option& e) {
        throw po::error(e.what() + suggestion(e.get_option_name(), all));
      }
    }();
    rejectNegativeUnsigned(parsed, all);
    po::store(parsed, vm);
    if (vm.count("help")) {
      std::cout << "usage: " << usage << "\n\n" << helpOptions(all, command) << "\n";
      return false;
    }
    if (vm.count("version")) {
      std::cout << "dynid " << versionText() << "\n";
      return false;
    }
    po::notify(vm);
    checkRanges(vm, command);
    // An empty value given on the command line ("--out ''", an unset shell variable) is a usage
    // error, not a file named "".
    for (const auto& [name, value] : vm) {
      if (value.defaulted()) continue;
      const auto* text = boost::any_cast<std::string>(&value.value());
      if (text != nullptr && text->empty()) throw UsageError("--" + name + " is empty");
      const auto* texts = boost::any_cast<std::vector<std::string>>(&value.value());
      if (texts != nullptr)
        for (const std::string& t : *texts)
          if (t.empty()) throw UsageError("--" + name + " has an empty value");
    }
    // The seed and threads the command runs with, defaults included: its documents' provenance.
    if (vm.count("seed"))
      if (const auto* seed = boost::any_cast<std::uint64_t>(&vm["seed"].value()))
        noteRunSeed(*seed);
    if (vm.count("threads"))
      if (const auto* threads = boost::any_cast<int>(&vm["threads"].value()))
        noteRunThreads(*threads);
  } catch (const po::error& e) {
    throw UsageError(std::string(e.what()) + "\nusage: " + usage + " (--help for the options)");
  }
  return true;
}

void setOptionCatalogue(std::vector<CommandOptions>* c) { catalogue = c; }

}  // namespace dynid::cli
