#include "reports/summary_report.hpp"

#include <gtest/gtest.h>

#include "analysis/runs/summarize.hpp"
#include "core/errors.hpp"
#include "core/simulate.hpp"
#include "data/digest/base64.hpp"
#include "data/puma560.hpp"
#include "tests/common/identification.hpp"

namespace dynid {
namespace {

/// A one-second PUMA summary from its data in memory (four batches of 256 samples).
const Summary& pumaSummary() {
  static const Summary summary = [] {
    const Model puma = makePuma560(true);
    static const Trajectory data = test::pumaTrajectory(puma, 1.0, 0.1, 1);
    SummarizeRequest request;
    request.model = puma;
    request.robot_spec = "puma560";
    request.data = &data;
    return summarizeRun(request).summaries.front();
  }();
  return summary;
}

TEST(SummaryReport, ReadsBackBitForBit) {
  const Summary& s = pumaSummary();
  const nlohmann::json doc = summaryJson(s);
  EXPECT_EQ(doc["kind"], "dynid.summary");
  const Summary back = summaryFrom(nlohmann::json::parse(doc.dump()), "s.json");
  ASSERT_EQ(back.factors.batches().size(), s.factors.batches().size());
  for (std::size_t b = 0; b < s.factors.batches().size(); ++b)
    for (std::size_t j = 0; j < 6; ++j)
      EXPECT_EQ(back.factors.batches()[b].factors[j], s.factors.batches()[b].factors[j]);
  EXPECT_EQ(back.factors.tauSquared(), s.factors.tauSquared());  // JSON's shortest round trip
  EXPECT_EQ(back.factors.fittedRows(), s.factors.fittedRows());
  EXPECT_EQ(back.base_names, s.base_names);
  EXPECT_EQ(back.sources.front().rest_velocity, s.sources.front().rest_velocity);
  EXPECT_EQ(back.model.standardParameters(), s.model.standardParameters());
  EXPECT_NO_THROW(summaryBase(back, "s.json"));
}

/// The ParseError's field for the document `edit` makes of a good one.
template <class Edit>
std::string fieldOf(Edit edit) {
  nlohmann::json doc = nlohmann::json::parse(summaryJson(pumaSummary()).dump());
  edit(doc);
  try {
    summaryFrom(doc, "s.json");
  } catch (const ParseError& e) {
    return e.element();
  }
  return "(read)";
}

TEST(SummaryReport, NamesTheFieldOfABadDocument) {
  using json = nlohmann::json;
  EXPECT_EQ(fieldOf([](json& d) { d["least_squares"]["encoding"] = "decimal"; }),
            "least_squares.encoding");
  EXPECT_EQ(fieldOf([](json& d) { d["least_squares"]["batches"][1]["factors"] = "Zm9v!"; }),
            "least_squares.batches[1].factors");
  EXPECT_EQ(fieldOf([](json& d) {
              const std::string text = d["least_squares"]["batches"][0]["factors"];
              d["least_squares"]["batches"][0]["factors"] = text.substr(0, text.size() - 12);
            }),
            "least_squares.batches[0].factors");
  EXPECT_EQ(fieldOf([](json& d) {
              std::vector<double> v =
                  doublesFromBase64(d["least_squares"]["batches"][0]["factors"].get<std::string>());
              v[0] = std::nan("");
              d["least_squares"]["batches"][0]["factors"] = doublesToBase64(v.data(), v.size());
            }),
            "least_squares");
  EXPECT_EQ(fieldOf([](json& d) { d["least_squares"]["support"][0][0] = 999; }),
            "least_squares.support[0][0]");
  EXPECT_EQ(fieldOf([](json& d) { d["samples"] = 5; }), "samples");
  EXPECT_EQ(fieldOf([](json& d) { d["sources"][0]["rest_velocity"] = json::array({0.1}); }),
            "sources[0].rest_velocity");
  EXPECT_EQ(fieldOf([](json& d) { d["extra"] = 1; }), "extra");
  EXPECT_EQ(fieldOf([](json& d) { d["schema_version"] = 2; }), "schema_version");
}

}  // namespace
}  // namespace dynid
