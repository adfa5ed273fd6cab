// dynid's exception hierarchy. Every error dynid throws derives from dynid::Error, so a caller can
// catch one type; the subclasses say whose fault it was.
//   InputError      a caller passed something invalid (sizes, non-finite values, bad options).
//   ParseError      a file is malformed; carries the file, the line or row (0 when unknown) and the
//                   element, field or column at fault.
//   NumericalError  a computation failed on valid input (singular matrix, diverging rollout).
#pragma once

#include <sstream>
#include <stdexcept>
#include <string>

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

}  // namespace dynid
