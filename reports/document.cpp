#include "reports/document.hpp"

#include <sstream>

#include "core/format.hpp"
#include "data/io.hpp"

namespace dynid {

void Document::verdict(const std::vector<std::pair<std::string, std::string>>& lines) {
  std::vector<std::string> text;
  for (const auto& [label, line] : lines) {
    text.push_back(label);
    text.push_back(line);
  }
  blocks_.insert(blocks_.begin(), {Kind::kVerdict, text, {}, -1});
}
void Document::heading(const std::string& text) {
  blocks_.push_back({Kind::kHeading, {text}, {}, -1});
}
void Document::paragraph(const std::string& text) {
  blocks_.push_back({Kind::kParagraph, {text}, {}, -1});
}
void Document::bullets(const std::vector<std::string>& items) {
  if (!items.empty()) blocks_.push_back({Kind::kBullets, items, {}, -1});
}
void Document::table(const DocumentTable& table) {
  blocks_.push_back({Kind::kTable, {}, table, -1});
}
void Document::figure(const Figure& figure) {
  figures_.push_back(figure);
  blocks_.push_back({Kind::kFigure, {}, {}, static_cast<int>(figures_.size()) - 1});
}

std::string percentText(double fraction) { return formatNumber(100.0 * fraction, 3, "n/a") + " %"; }

namespace {
/// A Markdown table cell: pipes escaped, line breaks flattened.
std::string markdownCell(const std::string& text) {
  std::string out;
  for (char c : text) {
    if (c == '|')
      out += "\\|";
    else
      out += c == '\n' ? ' ' : c;
  }
  return out;
}
/// A Markdown line of text: line breaks flattened, so that a name read from a file or folder
/// (a robot's, a log's) cannot start a heading, a list or a quote of its own.
std::string markdownLine(const std::string& text) {
  std::string out = text;
  for (char& c : out)
    if (c == '\n' || c == '\r') c = ' ';
  return out;
}
/// What a folded table shows before it is opened: its caption's first sentence and its size.
std::string tableSummary(const DocumentTable& table) {
  std::string caption = table.caption.substr(0, table.caption.find(". "));
  if (caption.empty()) caption = "Table";
  return caption + " (" + std::to_string(table.rows.size()) + " rows; click to show)";
}
}  // namespace

std::string Document::markdown() const {
  std::ostringstream out;
  out << "# " << markdownLine(title_) << "\n";
  for (const Block& b : blocks_) {
    out << "\n";
    switch (b.kind) {
      case Kind::kVerdict:
        out << "> **Verdict**\n>\n";
        for (std::size_t k = 0; k + 1 < b.text.size(); k += 2)
          out << "> - **" << markdownLine(b.text[k]) << ":** " << markdownLine(b.text[k + 1])
              << "\n";
        break;
      case Kind::kHeading:
        out << "## " << markdownLine(b.text[0]) << "\n";
        break;
      case Kind::kParagraph:
        out << markdownLine(b.text[0]) << "\n";
        break;
      case Kind::kBullets:
        for (const std::string& item : b.text) out << "- " << markdownLine(item) << "\n";
        break;
      case Kind::kTable: {
        const bool folded = b.table.rows.size() > kFoldRows;
        if (folded)
          out << "<details><summary>" << escapeXml(tableSummary(b.table)) << "</summary>\n\n";
        out << "|";
        for (const std::string& h : b.table.header) out << " " << markdownCell(h) << " |";
        out << "\n|";
        for (std::size_t c = 0; c < b.table.header.size(); ++c) out << "---|";
        out << "\n";
        for (const auto& row : b.table.rows) {
          out << "|";
          for (const std::string& cell : row) out << " " << markdownCell(cell) << " |";
          out << "\n";
        }
        if (!b.table.caption.empty()) out << "\n" << markdownLine(b.table.caption) << "\n";
        if (folded) out << "\n</details>\n";
        break;
      }
      case Kind::kFigure:
        out << markdownFigure(figures_[static_cast<std::size_t>(b.figure)], b.figure + 1);
        break;
    }
  }
  return out.str();
}

std::string markdownFigure(const Figure& figure, int number) {
  const std::string label = "Figure " + std::to_string(number);
  return "![" + label + "](" + figure.name + ".svg)\n\n**" + label + ".** " + figure.caption + "\n";
}

std::string htmlHead(const std::string& title) {
  return "<!DOCTYPE html>\n<html lang=\"en\">\n<head>\n<meta charset=\"utf-8\">\n<title>" +
         escapeXml(title) +
         "</title>\n<style>body{font-family:sans-serif;max-width:70em;margin:2em auto;padding:0 "
         "1em}table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:"
         "0.2em 0.6em;text-align:right}td:first-child,th:first-child{text-align:left}"
         "caption{caption-side:bottom;text-align:left;font-size:0.9em;padding-top:0.4em}"
         "figure{margin:1.5em 0}figure svg{max-width:100%;height:auto}"
         ".verdict{border:2px solid #2a6;border-radius:6px;background:#f3fbf6;padding:0.2em 1em;"
         "margin:1em 0}.verdict h2{margin:0.4em 0}.verdict dt{font-weight:bold;float:left;"
         "clear:left;width:9em}.verdict dd{margin:0 0 0.4em 9.5em}"
         "summary{cursor:pointer;margin:0.6em 0}</style>\n</head>\n"
         "<body>\n<h1>" +
         escapeXml(title) + "</h1>\n";
}

std::string htmlFigure(const Figure& figure, int number) {
  // Inline: the SVG element without gnuplot's XML prolog.
  const std::size_t start = figure.svg.find("<svg");
  return "<figure id=\"" + escapeXml(figure.name) + "\">\n" +
         figure.svg.substr(start == std::string::npos ? 0 : start) + "\n<figcaption><b>Figure " +
         std::to_string(number) + ".</b> " + escapeXml(figure.caption) +
         "</figcaption>\n</figure>\n";
}

std::string Document::html() const {
  std::ostringstream out;
  out << htmlHead(title_);
  for (const Block& b : blocks_) {
    switch (b.kind) {
      case Kind::kVerdict:
        out << "<section class=\"verdict\" id=\"verdict\">\n<h2>Verdict</h2>\n<dl>\n";
        for (std::size_t k = 0; k + 1 < b.text.size(); k += 2)
          out << "<dt>" << escapeXml(b.text[k]) << "</dt><dd>" << escapeXml(b.text[k + 1])
              << "</dd>\n";
        out << "</dl>\n</section>\n";
        break;
      case Kind::kHeading:
        out << "<h2>" << escapeXml(b.text[0]) << "</h2>\n";
        break;
      case Kind::kParagraph:
        out << "<p>" << escapeXml(b.text[0]) << "</p>\n";
        break;
      case Kind::kBullets:
        out << "<ul>\n";
        for (const std::string& item : b.text) out << "<li>" << escapeXml(item) << "</li>\n";
        out << "</ul>\n";
        break;
      case Kind::kTable:
        if (b.table.rows.size() > kFoldRows)
          out << "<details><summary>" << escapeXml(tableSummary(b.table)) << "</summary>\n";
        out << "<table>\n<tr>";
        for (const std::string& h : b.table.header) out << "<th>" << escapeXml(h) << "</th>";
        out << "</tr>\n";
        for (const auto& row : b.table.rows) {
          out << "<tr>";
          for (const std::string& cell : row) out << "<td>" << escapeXml(cell) << "</td>";
          out << "</tr>\n";
        }
        if (!b.table.caption.empty())
          out << "<caption>" << escapeXml(b.table.caption) << "</caption>\n";
        out << "</table>\n";
        if (b.table.rows.size() > kFoldRows) out << "</details>\n";
        break;
      case Kind::kFigure:
        out << htmlFigure(figures_[static_cast<std::size_t>(b.figure)], b.figure + 1);
        break;
    }
  }
  out << "</body>\n</html>\n";
  return out.str();
}

}  // namespace dynid
