// Strict reading of the JSON documents dynid reads back (models, search.json, checkpoints,
// estimates, batch results): every field checked for its type and documented range, unknown keys
// refused, and every error a ParseError naming the file and the JSON path of the field
// ("settings.step", "population[2]").
#pragma once

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <limits>
#include <set>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "core/errors.hpp"
#include "core/format.hpp"

namespace dynid {

/// Parses a JSON document dynid reads. Throws ParseError naming `file` for invalid JSON (with
/// nlohmann's line and column), a number beyond a double (1e400), and a key given twice in one
/// object (which value was meant cannot be known; nlohmann would keep the last silently).
inline nlohmann::json parseJsonDocument(const std::string& text, const std::string& file) {
  using json = nlohmann::json;
  std::vector<std::set<std::string>> keys;  // the keys seen in each open object
  const json::parser_callback_t check = [&](int, json::parse_event_t event, json& parsed) {
    if (event == json::parse_event_t::object_start) keys.emplace_back();
    if (event == json::parse_event_t::object_end && !keys.empty()) keys.pop_back();
    if (event == json::parse_event_t::key && !keys.empty() &&
        !keys.back().insert(parsed.get<std::string>()).second)
      throw ParseError(file, 0, parsed.get<std::string>(),
                       "appears twice in one object: which value is meant?");
    return true;
  };
  try {
    return json::parse(text, check);
  } catch (const json::exception& e) {  // parse_error, or out_of_range for a number like 1e400
    throw ParseError(file, 0, "", std::string("invalid JSON: ") + e.what());
  }
}

class JsonReader {
 public:
  using json = nlohmann::json;
  explicit JsonReader(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }

  static std::string join(const std::string& path, const std::string& key) {
    return path.empty() ? key : path + "." + key;
  }
  static std::string index(const std::string& path, std::size_t i) {
    return path + "[" + std::to_string(i) + "]";
  }

  [[noreturn]] void fail(const std::string& path, const std::string& message) const {
    throw ParseError(file_, 0, path, message);
  }
  const json& object(const json& value, const std::string& path) const {
    if (!value.is_object()) fail(path, "expected an object");
    return value;
  }
  const json& field(const json& object, const std::string& path, const std::string& key) const {
    if (!object.is_object()) fail(path, "expected an object");
    const auto it = object.find(key);
    if (it == object.end()) fail(join(path, key), "missing");
    return *it;
  }
  /// Fails on a key of `object` not in `allowed` (a misspelt key must not pass silently).
  void onlyKeys(const json& object, const std::string& path,
                std::initializer_list<const char*> allowed) const {
    onlyKeysIn(object, path, allowed);
  }
  /// The same for any range of names (const char*, std::string_view, std::string).
  template <typename Names>
  void onlyKeysIn(const json& object, const std::string& path, const Names& allowed) const {
    this->object(object, path);
    for (const auto& [key, value] : object.items()) {
      bool known = false;
      for (const auto& a : allowed) known = known || key == a;
      if (!known) {
        std::string list;
        for (const auto& a : allowed)
          list += std::string(list.empty() ? "" : ", ") + std::string(a);
        fail(join(path, key), "unknown key (expected " + list + ")");
      }
    }
  }
  /// The document's schema_version (exactly `version`, an integer) and kind (when given).
  void header(const json& document, int version, const char* kind) const {
    object(document, "");
    const json& v = field(document, "", "schema_version");
    if (!v.is_number_integer() || v.get<long long>() != version)
      fail("schema_version", "must be " + std::to_string(version) + ", not " + v.dump());
    if (kind != nullptr) {
      const json& k = field(document, "", "kind");
      if (!k.is_string() || k.get<std::string>() != kind)
        fail("kind", std::string("must be \"") + kind + "\", not " + k.dump());
    }
  }
  double number(const json& value, const std::string& path,
                double lo = -std::numeric_limits<double>::max(),
                double hi = std::numeric_limits<double>::max()) const {
    if (!value.is_number()) fail(path, "expected a number, not " + value.dump());
    const double x = value.get<double>();
    if (!std::isfinite(x)) fail(path, "not finite");
    if (x < lo || x > hi) fail(path, outOfRange(value, lo, hi));
    return x;
  }
  double number(const json& object, const std::string& path, const std::string& key,
                double lo = -std::numeric_limits<double>::max(),
                double hi = std::numeric_limits<double>::max()) const {
    return number(field(object, path, key), join(path, key), lo, hi);
  }
  long long integer(const json& value, const std::string& path, long long lo, long long hi) const {
    if (!value.is_number_integer()) fail(path, "expected an integer, not " + value.dump());
    if (value.is_number_unsigned() &&
        value.get<std::uint64_t>() >
            static_cast<std::uint64_t>(std::numeric_limits<long long>::max()))
      fail(path, outOfRange(value, static_cast<double>(lo), static_cast<double>(hi)));
    const long long x = value.get<long long>();
    if (x < lo || x > hi)
      fail(path, outOfRange(value, static_cast<double>(lo), static_cast<double>(hi)));
    return x;
  }
  long long integer(const json& object, const std::string& path, const std::string& key,
                    long long lo, long long hi) const {
    return integer(field(object, path, key), join(path, key), lo, hi);
  }
  std::uint64_t unsignedInteger(const json& object, const std::string& path,
                                const std::string& key) const {
    const json& value = field(object, path, key);
    if (!value.is_number_unsigned())
      fail(join(path, key), "expected a non-negative integer, not " + value.dump());
    return value.get<std::uint64_t>();
  }
  std::string string(const json& object, const std::string& path, const std::string& key) const {
    const json& value = field(object, path, key);
    if (!value.is_string()) fail(join(path, key), "expected a string, not " + value.dump());
    return value.get<std::string>();
  }
  bool boolean(const json& object, const std::string& path, const std::string& key) const {
    const json& value = field(object, path, key);
    if (!value.is_boolean()) fail(join(path, key), "expected true or false, not " + value.dump());
    return value.get<bool>();
  }
  const json& array(const json& value, const std::string& path) const {
    if (!value.is_array()) fail(path, "expected an array");
    return value;
  }
  /// An array of finite numbers, of exactly `size` entries when size >= 0.
  Eigen::VectorXd vector(const json& value, const std::string& path, long size = -1) const {
    array(value, path);
    if (size >= 0 && static_cast<long>(value.size()) != size)
      fail(path,
           "expected " + std::to_string(size) + " numbers, not " + std::to_string(value.size()));
    Eigen::VectorXd out(static_cast<Eigen::Index>(value.size()));
    for (std::size_t i = 0; i < value.size(); ++i)
      out[static_cast<Eigen::Index>(i)] = number(value[i], index(path, i));
    return out;
  }
  std::vector<std::string> strings(const json& value, const std::string& path) const {
    array(value, path);
    std::vector<std::string> out;
    for (std::size_t i = 0; i < value.size(); ++i) {
      if (!value[i].is_string()) fail(index(path, i), "expected a string, not " + value[i].dump());
      out.push_back(value[i].get<std::string>());
    }
    return out;
  }

 private:
  static std::string outOfRange(const json& value, double lo, double hi) {
    std::string text = value.dump() + " is out of range (";
    if (lo > -std::numeric_limits<double>::max()) text += ">= " + formatNumber(lo);
    if (hi < std::numeric_limits<double>::max())
      text += std::string(lo > -std::numeric_limits<double>::max() ? ", " : "") +
              "<= " + formatNumber(hi);
    return text + ")";
  }
  std::string file_;
};

}  // namespace dynid
