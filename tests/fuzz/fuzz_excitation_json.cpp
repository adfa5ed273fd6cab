// libFuzzer target: an excitation.json of dynid excite as simulate --trajectory and batch read it
// (analysis/records/excitation_record.hpp, excitationDesignFrom, excitationStandTiltsFrom), and a
// standing_excitation.json (standingDesignFrom). An accepted design must give a finite motion,
// accepted stand orientations be finite, within a right angle, at most 16, and an accepted
// standing design have six coordinates, a finite stance and contacts.
#include <algorithm>
#include <cstdint>
#include <vector>

#include "analysis/records/document.hpp"
#include "analysis/records/excitation_record.hpp"
#include "core/controllers.hpp"
#include "core/errors.hpp"
#include "data/json_reader.hpp"
#include "tests/fuzz/fuzz_input.hpp"

extern "C" int LLVMFuzzerTestOneInput(const std::uint8_t* data, std::size_t size) {
  try {
    const nlohmann::json doc =
        dynid::parseJsonDocument(dynid::fuzz::text(data, size), "excitation.json");
    if (dynid::isDocumentOfKind(doc, dynid::kStandingExcitationDocument)) {
      const dynid::StandingDesignRecord s = dynid::standingDesignFrom(doc, "s.json", 0);
      if (s.base.offset.size() != 6 || !s.stance.allFinite() || s.contacts.empty())
        __builtin_trap();
      Eigen::VectorXd c, dc, ddc;
      dynid::evaluateReference(s.base, s.base.period / 3.0, c, dc, ddc);
      if (!c.allFinite() || !dc.allFinite() || !ddc.allFinite()) __builtin_trap();
      return 0;
    }
    // The joint count the robot would have: the offsets' (as batch checks a manifest's designs).
    int joints = 6;
    if (doc.is_object() && doc.contains("design") && doc["design"].is_object() &&
        doc["design"].contains("offset") && doc["design"]["offset"].is_array())
      joints = static_cast<int>(std::min<std::size_t>(doc["design"]["offset"].size(), 64));
    const dynid::FourierSeries d = dynid::excitationDesignFrom(doc, "excitation.json", joints);
    Eigen::VectorXd q, dq, ddq;
    for (double t : {0.0, d.period / 3.0, d.period}) {
      dynid::evaluateReference(d, t, q, dq, ddq);
      if (!q.allFinite() || !dq.allFinite() || !ddq.allFinite()) __builtin_trap();
    }
    const std::vector<Eigen::Vector2d> tilts =
        dynid::excitationStandTiltsFrom(doc, "excitation.json");
    if (tilts.size() > 16) __builtin_trap();
    for (const Eigen::Vector2d& tilt : tilts)
      if (!tilt.allFinite() || tilt.cwiseAbs().maxCoeff() > 1.5707963267948966) __builtin_trap();
  } catch (const dynid::Error&) {
  }
  return 0;
}
