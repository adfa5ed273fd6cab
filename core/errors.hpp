// dynid's exception hierarchy. Every error dynid throws derives from dynid::Error, so a caller can
// catch one type; the subclasses say whose fault it was.
//   InputError      a caller passed something invalid (sizes, non-finite values, bad options).
//   ParseError      a file is malformed; carries the file, the line or row (0 when unknown) and the
//                   element, field or column at fault.
//   NumericalError  a computation failed on valid input (singular matrix, diverging rollout).
// A message names a request's field in backquotes, as its snake_case name ("`cutoff` must be > 0",
// "give `torque_constants`"), never as one front end spells it: the CLI and the Python module
// respell those names for their users (respellFields) when they report the message.
#pragma once

#include <cctype>
#include <sstream>
#include <stdexcept>
#include <string>
#include <string_view>

namespace dynid {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

class InputError : public Error {
 public:
  using Error::Error;
};

class NumericalError : public Error {
 public:
  using Error::Error;
};

class ParseError : public Error {
 public:
  /// `line` is 1-based; 0 means the position is unknown. `element` names the XML element, JSON key
  /// or CSV column at fault (may be empty).
  ParseError(std::string file, int line, std::string element, const std::string& message)
      : Error(format(file, line, element, message)),
        file_(std::move(file)),
        line_(line),
        element_(std::move(element)) {}

  const std::string& file() const { return file_; }
  int line() const { return line_; }
  const std::string& element() const { return element_; }

 private:
  static std::string format(const std::string& file, int line, const std::string& element,
                            const std::string& message) {
    std::ostringstream out;
    out << file;
    if (line > 0) out << ':' << line;
    out << ": ";
    if (!element.empty()) out << element << ": ";
    out << message;
    return out.str();
  }
  std::string file_;
  int line_;
  std::string element_;
};

/// `text` with every field name in backquotes (`name`: lowercase letters, digits and '_', starting
/// with a letter) replaced by spell(name); other backquoted text is left as it is.
template <typename Spell>
std::string respellFields(std::string_view text, const Spell& spell) {
  std::string out;
  out.reserve(text.size());
  std::size_t at = 0;
  while (at < text.size()) {
    const std::size_t open = text.find('`', at);
    if (open == std::string_view::npos) break;
    const std::size_t close = text.find('`', open + 1);
    if (close == std::string_view::npos) break;
    const std::string_view name = text.substr(open + 1, close - open - 1);
    bool field = !name.empty() && std::islower(static_cast<unsigned char>(name[0]));
    for (const char c : name)
      field = field && (std::islower(static_cast<unsigned char>(c)) ||
                        std::isdigit(static_cast<unsigned char>(c)) || c == '_');
    out.append(text.substr(at, open - at));
    if (field) {
      out += spell(name);
      at = close + 1;
    } else {
      out += '`';
      at = open + 1;
    }
  }
  out.append(text.substr(at));
  return out;
}

}  // namespace dynid
