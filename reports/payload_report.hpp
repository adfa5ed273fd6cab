// What `dynid payload` writes: payload.json (every quantity with its 95 % interval, what the motion
// determines, the drive gains), report.md / report.html (the verdict first, then the table, the
// identifiability, advice, friction, gains and the torques), payload_torques.svg, and the payload
// in the controllers' conventions (docs/PAYLOAD.md, "Export"): payload.urscript (UR),
// payload.franka.json (Franka setLoad), payload.kuka.dat (KUKA LOAD_DATA), payload.abb.mod (ABB
// loaddata) and payload.body.json (dynid's own, read back by --prior).
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "analysis/payload/payload.hpp"

namespace dynid {

/// payload.json.
nlohmann::json payloadJson(const PayloadOutcome& outcome);

/// The accepted --format names: ur, franka, kuka, abb, json.
const std::vector<std::string>& payloadFormats();
/// The formats named in `items` (each one or several comma-separated), in order, each once.
/// Throws InputError for an unknown one (naming the accepted ones).
std::vector<std::string> payloadFormatList(const std::vector<std::string>& items);
/// The payload in one controller's convention: (file name, content). Throws InputError for an
/// unknown format (naming the accepted ones).
std::pair<std::string, std::string> payloadVendorFile(const PayloadOutcome& outcome,
                                                      const std::string& format);

/// Writes payload.json, the report, its figure (when gnuplot works) and the `formats`' files into
/// `dir` as one set; the URDF carrying the payload to `urdf_path` when the outcome has one.
/// Returns the console summary.
std::string writePayload(const std::string& dir, const PayloadOutcome& outcome,
                         const std::vector<std::string>& formats, const std::string& urdf_path);

}  // namespace dynid
