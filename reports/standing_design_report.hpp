// standing_excitation.json, its report and its console lines (`dynid excite --floating-base
// --stance`, analysis/floating/standing_design.hpp): a standing robot's designed sway, the stance
// and feet it is for, and what every sensor set determines on it beside `dynid simulate
// --stance`'s default sway.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

#include "analysis/floating/standing_design.hpp"

namespace dynid {

/// What a design document records beside the outcome: the robot's spec and the contacts as they
/// were given (NAME, NAME:frame).
struct StandingDesignSource {
  std::string robot;
  std::vector<std::string> contacts;
};

nlohmann::json standingDesignJson(const StandingDesignRequest& request,
                                  const StandingDesign& design, const StandingDesignSource& source);
std::string standingDesignMarkdown(const StandingDesignRequest& request,
                                   const StandingDesign& design,
                                   const StandingDesignSource& source);
/// The console's lines: every set's counts beside the default sway's, the design's extremes and
/// the files in `dir` (the front end says how to simulate along it, in its own spelling).
std::string standingDesignSummary(const StandingDesignRequest& request,
                                  const StandingDesign& design, const std::string& dir);

}  // namespace dynid
