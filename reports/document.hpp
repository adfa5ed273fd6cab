// A report written once and rendered twice: to Markdown (figures referenced as NAME.svg files
// beside it) and to one self-contained HTML file (inline CSS and SVG, no external resources).
// Text is plain: each renderer escapes what its format needs.
#pragma once

#include <string>
#include <vector>

#include "reports/plots.hpp"

namespace dynid {

/// A fraction as a percentage for a report: 3 significant digits and " %" ("n/a" when not finite).
std::string percentText(double fraction);

struct DocumentTable {
  std::vector<std::string> header;
  std::vector<std::vector<std::string>> rows;  // each as long as the header
  std::string caption;                         // empty: none
};

class Document {
 public:
  explicit Document(std::string title) : title_(std::move(title)) {}
  /// The verdict box, always first whatever the order of calls: (label, text) lines such as
  /// ("Estimated", ...), ("How well", ...), ("Not determined", ...), ("Next", ...).
  void verdict(const std::vector<std::pair<std::string, std::string>>& lines);
  void heading(const std::string& text);  // a section (level 2)
  void paragraph(const std::string& text);
  void bullets(const std::vector<std::string>& items);  // nothing for an empty list
  /// A table; one of more than kFoldRows rows is folded (<details>: its caption and row count
  /// shown, the rows on a click), so that it does not push what follows off the screen.
  void table(const DocumentTable& table);
  static constexpr std::size_t kFoldRows = 12;
  void figure(const Figure& figure);  // numbered in order
  const std::vector<Figure>& figures() const { return figures_; }

  std::string markdown() const;
  std::string html() const;

 private:
  enum class Kind { kVerdict, kHeading, kParagraph, kBullets, kTable, kFigure };
  struct Block {
    Kind kind;
    std::vector<std::string> text;  // heading/paragraph: one entry; bullets: the items;
                                    // verdict: label, text, label, text, ...
    DocumentTable table;
    int figure = -1;  // index into figures_
  };
  std::string title_;
  std::vector<Block> blocks_;
  std::vector<Figure> figures_;
};

/// The HTML documents' common opening, through <body> and the title as <h1>.
std::string htmlHead(const std::string& title);
/// A figure as Markdown: the image NAME.svg and its numbered caption.
std::string markdownFigure(const Figure& figure, int number);
/// A figure inlined as <figure> with its numbered caption.
std::string htmlFigure(const Figure& figure, int number);

}  // namespace dynid
