#include "analysis/records/fleet_manifest.hpp"

#include <filesystem>
#include <set>

#include "analysis/records/document.hpp"
#include "data/io.hpp"
#include "data/json_reader.hpp"

namespace dynid {

namespace {

/// A list of paths, each made relative to the manifest's folder when it is relative.
std::vector<std::string> paths(const JsonReader& read, const nlohmann::json& robot,
                               const std::string& path, const char* key,
                               const std::filesystem::path& dir) {
  std::vector<std::string> out;
  const std::string where = JsonReader::join(path, key);
  const nlohmann::json& list = read.field(robot, path, key);
  if (!list.is_array() || list.empty()) read.fail(where, "expected a non-empty list of paths");
  for (std::size_t i = 0; i < list.size(); ++i) {
    if (!list[i].is_string() || list[i].get<std::string>().empty())
      read.fail(JsonReader::index(where, i), "expected a path, not " + list[i].dump());
    const std::filesystem::path p = list[i].get<std::string>();
    out.push_back(p.is_absolute() || dir.empty() ? p.string() : (dir / p).string());
  }
  return out;
}

}  // namespace

std::vector<FleetManifestRobot> fleetManifestFrom(const std::string& text,
                                                  const std::string& file) {
  const nlohmann::json doc = parseJsonDocument(text, file);
  const JsonReader read(file);
  read.header(doc, kFleetManifestDocument.schema_version, kFleetManifestDocument.kind);
  read.onlyKeys(doc, "", {"schema_version", "kind", "description", "robots"});
  const nlohmann::json& robots = read.field(doc, "", "robots");
  if (!robots.is_array()) read.fail("robots", "expected a list of robots");
  const std::filesystem::path dir = std::filesystem::path(file).parent_path();
  std::vector<FleetManifestRobot> out;
  std::set<std::string> names;
  for (std::size_t i = 0; i < robots.size(); ++i) {
    const std::string path = JsonReader::index("robots", i);
    read.onlyKeys(robots[i], path, {"name", "data", "summaries"});
    FleetManifestRobot robot;
    robot.name = read.string(robots[i], path, "name");
    if (robot.name.empty()) read.fail(JsonReader::join(path, "name"), "empty");
    if (!names.insert(robot.name).second)
      read.fail(JsonReader::join(path, "name"), "'" + robot.name + "' names two robots");
    const bool data = robots[i].contains("data"), summaries = robots[i].contains("summaries");
    if (data == summaries)
      read.fail(path, "give the robot's \"data\" (logs) or its \"summaries\", one of the two");
    (data ? robot.data : robot.summaries) =
        paths(read, robots[i], path, data ? "data" : "summaries", dir);
    out.push_back(std::move(robot));
  }
  return out;
}

std::vector<FleetManifestRobot> readFleetManifest(const std::string& file) {
  return fleetManifestFrom(readFile(file), file);
}

}  // namespace dynid
