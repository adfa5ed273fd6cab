// dynid model show's table: columns as wide as the model's names, every name whole.
#include "reports/model_report.hpp"

#include <sstream>
#include <string>
#include <vector>

#include <gtest/gtest.h>

#include "data/puma560.hpp"

namespace dynid {
namespace {

/// The lines of `text` from the one starting with `first` up to the next blank line.
std::vector<std::string> tableLines(const std::string& text, const std::string& first) {
  std::istringstream in(text);
  std::vector<std::string> lines;
  std::string line;
  bool inside = false;
  while (std::getline(in, line)) {
    if (!inside && line.rfind(first, 0) == 0) inside = true;
    if (inside && line.empty()) break;
    if (inside) lines.push_back(line);
  }
  return lines;
}

TEST(ModelShow, LongNamesKeepTheColumnsAlignedAndWhole) {
  Model model = makePuma560(false);
  // A URDF's names (longer than the old 16-character columns), and one of 600 characters (the
  // old line buffer held 512).
  model.joint_names[0] = "shoulder_pan_joint";
  model.link_names[1] = "upper_arm_link_with_a_long_name";
  model.link_names[5] = std::string(600, 'w');
  const std::string text = modelShowText(model);
  const std::vector<std::string> rows = tableLines(text, "#");
  ASSERT_EQ(rows.size(), 7u) << text;
  // The "type" column starts at the same offset on every row, the header's included.
  const std::size_t type_at = rows[0].find("type");
  ASSERT_NE(type_at, std::string::npos);
  for (std::size_t r = 1; r < rows.size(); ++r)
    EXPECT_EQ(rows[r].find("revolute"), type_at) << rows[r];
  EXPECT_NE(rows[1].find("shoulder_pan_joint revolute"), std::string::npos) << rows[1];
  EXPECT_NE(rows[6].find(std::string(600, 'w')), std::string::npos);
  // The frames' table: the origins line up too.
  const std::vector<std::string> frames = tableLines(text, "link frames");
  ASSERT_EQ(frames.size(), 7u) << text;
  const std::size_t origin_at = frames[1].find('(');
  for (std::size_t r = 2; r < frames.size(); ++r) EXPECT_EQ(frames[r].find('('), origin_at);
  // The standard parameters, five to a line: each line's second entry starts at one offset (the
  // values padded to the widest, "-7.08e-05" among "4" and "0").
  const std::vector<std::string> parameters = tableLines(text, "standard parameters");
  ASSERT_EQ(parameters.size(), 1u + 6u * 2u) << text;
  const std::size_t second_at = parameters[1].find("mx1");
  ASSERT_NE(second_at, std::string::npos);
  for (std::size_t r = 2; r < parameters.size(); ++r) {
    const std::size_t name = parameters[r].find_first_not_of(' ', 2);
    const std::size_t next = parameters[r].find_first_not_of(' ', parameters[r].find(' ', name));
    const std::size_t second = parameters[r].find_first_not_of(' ', parameters[r].find(' ', next));
    EXPECT_EQ(second, second_at) << parameters[r];
  }
}

}  // namespace
}  // namespace dynid
