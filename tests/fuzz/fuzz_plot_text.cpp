// libFuzzer target: the one way text enters a gnuplot script (reports/plots.hpp), with an
// injection oracle. Whatever the bytes, gnuplotString must give single-quoted pieces joined by
// ."'". (a quote) and nothing else, with no control character (a newline would end the command),
// valid UTF-8 and a bounded length; gnuplotDataString one double-quoted column without an inner
// double quote. Either failing is a way from a name to gnuplot code.
#include <cstdint>
#include <string>

#include "data/io.hpp"
#include "reports/plot_script.hpp"

namespace {

/// The text a gnuplotString token stands for, or false when the token is anything but quoted
/// pieces and joins (an operator, a name, an unclosed string: code).
bool readPlotText(const std::string& token, std::string& text) {
  const std::string join = ".\"'\".";
  std::size_t i = 0;
  while (true) {
    if (i >= token.size() || token[i] != '\'') return false;
    const std::size_t end = token.find('\'', i + 1);
    if (end == std::string::npos) return false;
    text += token.substr(i + 1, end - i - 1);
    i = end + 1;
    if (i == token.size()) return true;
    if (token.compare(i, join.size(), join) != 0) return false;
    text += '\'';
    i += join.size();
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  const std::string input(reinterpret_cast<const char*>(data), size);
  const std::string quoted = dynid::gnuplotString(input).quoted();
  std::string text;
  if (!readPlotText(quoted, text)) __builtin_trap();
  if (!dynid::isPrintableUtf8(quoted)) __builtin_trap();  // no control character, valid UTF-8
  if (quoted.size() > 2 + 7 * 204 + 3) __builtin_trap();  // 200 bytes kept (+ one sequence)
  const std::string column = dynid::gnuplotDataString(input).quoted();
  if (column.size() < 2 || column.front() != '"' || column.back() != '"' ||
      column.find('"', 1) != column.size() - 1 || !dynid::isPrintableUtf8(column))
    __builtin_trap();
  return 0;
}
