#include "reports/document.hpp"

#include <gtest/gtest.h>

#include "tests/common/text.hpp"

namespace dynid {
namespace {

using test::contains;

Document sampleDocument() {
  Document doc("fit <of> a | b");
  doc.heading("Torque & fit");
  doc.paragraph("relative error 1.01 %");
  doc.bullets({});  // nothing for an empty list
  doc.bullets({"first", "x < y"});
  doc.table({{"name", "combination"}, {{"Izz1R", "Izz1 + Iyy2"}, {"p|q", "a<b"}}, "cap"});
  doc.figure({"residuals", "the residuals", "<?xml version='1.0'?>\n<svg id='r'></svg>"});
  doc.figure({"torques", "the torques", "<svg id='t'></svg>"});
  return doc;
}

TEST(Document, MarkdownEscapesTableCellsAndNumbersFigures) {
  const std::string md = sampleDocument().markdown();
  EXPECT_EQ(md.rfind("# fit <of> a | b\n", 0), 0u) << md;
  EXPECT_TRUE(contains(md, "\n## Torque & fit\n"));
  EXPECT_TRUE(contains(md, "\n- first\n- x < y\n"));
  EXPECT_FALSE(contains(md, "\n- \n"));
  // A pipe inside a cell would split the row: escaped.
  EXPECT_TRUE(contains(md, "| p\\|q | a<b |"));
  EXPECT_TRUE(contains(md, "|---|---|\n| Izz1R | Izz1 + Iyy2 |"));
  EXPECT_TRUE(contains(md, "![Figure 1](residuals.svg)\n\n**Figure 1.** the residuals"));
  EXPECT_TRUE(contains(md, "![Figure 2](torques.svg)\n\n**Figure 2.** the torques"));
}

// A name read from a folder or file (a robot's, a log's) with a line break must not start a
// heading, a list or a quote of its own: every line of text is flattened, as table cells are.
TEST(Document, MarkdownTextCannotStartBlocksOfItsOwn) {
  Document doc("fleet\n# title");
  doc.verdict({{"Outside", "robot\n# injected"}});
  doc.heading("h\n- item");
  doc.paragraph("a\n> quote");
  doc.bullets({"b\n## heading"});
  const std::string md = doc.markdown();
  for (const char* start : {"\n# ", "\n- item", "\n> quote", "\n## heading"})
    EXPECT_FALSE(contains(md, start)) << start << " in\n" << md;
  EXPECT_TRUE(contains(md, "robot # injected")) << md;
}

TEST(Document, HtmlIsSelfContainedAndEscaped) {
  const Document doc = sampleDocument();
  const std::string html = doc.html();
  EXPECT_TRUE(contains(html, "<h1>fit &lt;of&gt; a | b</h1>"));
  EXPECT_TRUE(contains(html, "<h2>Torque &amp; fit</h2>"));
  EXPECT_TRUE(contains(html, "<td>p|q</td><td>a&lt;b</td>"));
  EXPECT_TRUE(contains(html, "<li>x &lt; y</li>"));
  // Figures inline without their XML prolog, numbered in order.
  EXPECT_TRUE(contains(html, "<figure id=\"residuals\">\n<svg id='r'></svg>"));
  EXPECT_FALSE(contains(html, "<?xml"));
  EXPECT_TRUE(contains(html, "<b>Figure 2.</b> the torques"));
  for (const char* external : {"<script", "<link", "src=\"http", "@import"})
    EXPECT_FALSE(contains(html, external)) << external;
  EXPECT_EQ(doc.figures().size(), 2u);
}

TEST(Document, TheVerdictComesFirstAndLongTablesFold) {
  Document doc = sampleDocument();
  DocumentTable big{{"k", "v"}, {}, "Forty rows. More words"};
  for (int k = 0; k < 40; ++k) big.rows.push_back({std::to_string(k), "x"});
  doc.table(big);
  doc.verdict({{"Estimated", "36 <base> parameters"}, {"Next", "predict"}});  // called last
  const std::string md = doc.markdown(), html = doc.html();
  // Right after the title, before the first section, whatever the order of calls.
  EXPECT_LT(md.find("> **Verdict**"), md.find("## Torque & fit")) << md;
  EXPECT_TRUE(contains(md, "> - **Estimated:** 36 <base> parameters\n> - **Next:** predict\n"));
  EXPECT_LT(html.find("<section class=\"verdict\""), html.find("<h2>Torque &amp; fit</h2>"));
  EXPECT_TRUE(contains(html, "<dt>Estimated</dt><dd>36 &lt;base&gt; parameters</dd>"));
  // The 40-row table folds, with its caption's first sentence and size; the 2-row one does not.
  EXPECT_TRUE(contains(html, "<details><summary>Forty rows (40 rows; click to show)</summary>"));
  EXPECT_TRUE(contains(md, "<details><summary>Forty rows (40 rows; click to show)</summary>\n\n|"));
  EXPECT_EQ(html.find("<details>"), html.rfind("<details>"));
}

}  // namespace
}  // namespace dynid
