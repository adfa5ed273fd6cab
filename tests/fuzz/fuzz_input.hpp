// Shared by the libFuzzer targets: the input as a file (for readers that take a path), and the
// rule every target enforces: bad input may only end in a dynid::Error (which the CLI reports with
// exit 1 or 2); any other exception, a crash, a hang or a sanitizer report is a bug.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <string>

namespace dynid::fuzz {

/// Writes the input to this process's own file under $TMPDIR (or /tmp) and returns its path.
inline std::string inputFile(const std::uint8_t* data, std::size_t size, const char* suffix) {
  static const std::string path = [&] {
    const char* dir = std::getenv("TMPDIR");
    return std::string(dir != nullptr && *dir != '\0' ? dir : "/tmp") + "/dynid_fuzz_" +
           std::to_string(::getpid()) + suffix;
  }();
  std::FILE* f = std::fopen(path.c_str(), "wb");
  if (f == nullptr) std::abort();
  if (size > 0 && std::fwrite(data, 1, size, f) != size) std::abort();
  std::fclose(f);
  return path;
}

inline std::string text(const std::uint8_t* data, std::size_t size) {
  return std::string(reinterpret_cast<const char*>(data), size);
}

/// The floating targets' robot: a one-joint floating robot, base `b`, joint `j`, frames `l` and
/// `f` (a point below the limb).
inline constexpr const char* kOneJointFloatingRobot = R"(<robot name="r">
  <link name="b"><inertial><mass value="2"/>
    <inertia ixx="0.1" ixy="0" ixz="0" iyy="0.1" iyz="0" izz="0.1"/></inertial></link>
  <link name="l"><inertial><mass value="1"/>
    <inertia ixx="0.01" ixy="0" ixz="0" iyy="0.01" iyz="0" izz="0.01"/></inertial></link>
  <link name="f"/>
  <joint name="j" type="revolute"><parent link="b"/><child link="l"/><axis xyz="0 1 0"/>
    <limit lower="-1" upper="1" effort="10" velocity="1"/></joint>
  <joint name="s" type="fixed"><parent link="l"/><child link="f"/><origin xyz="0 0 -0.3"/></joint>
</robot>)";

}  // namespace dynid::fuzz
