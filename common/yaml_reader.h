// Schema-checked reading of YAML configuration. Every key read is marked; finish() rejects the
// keys nobody read, so a misspelt option is an error instead of a silent default. Errors name
// the file, the line and the dotted key path.
#pragma once

#include "common/error.h"
#include "common/geometry.h"

#include <yaml-cpp/yaml.h>

#include <fmt/format.h>

#include <cmath>
#include <map>
#include <memory>
#include <set>
#include <string>
#include <vector>

namespace rtsim {

// One command-line override, "a.b.c=value": the value is parsed as YAML ("16", "[480, 270]",
// "off"), the dotted path names map keys below one document's top level.
struct ConfigOverride {
  std::vector<std::string> keys;
  YAML::Node value;
  std::string text;  // "--set path=value" as the user wrote it, for error messages
};
// Parses "path=value"; a malformed one is an InputError naming it.
ConfigOverride parse_override(const std::string& text);

class YamlMap {
 public:
  // Parses a whole file, then applies `overrides` to it; a missing file or a syntax error is an
  // InputError. Errors about an overridden key name the override instead of a line.
  static YamlMap load_file(const std::string& path,
                           const std::vector<ConfigOverride>& overrides = {});
  // A map built in memory (a document's section, or one assembled from command-line flags).
  static YamlMap from_node(const YAML::Node& node, std::string file, std::string path,
                           const std::vector<ConfigOverride>& overrides = {});
  YamlMap(const YAML::Node& node, std::string file, std::string path);

  // A key given without a value ("key: ~") counts as absent.
  bool has(const std::string& key) const {
    const YAML::Node n = node_[key];
    return n.IsDefined() && !n.IsNull();
  }
  const std::string& file() const { return file_; }
  std::string key_path(const std::string& key) const {
    return path_.empty() ? key : path_ + "." + key;
  }
  std::vector<std::string> keys() const;

  template <class T>
  T get(const std::string& key, const T& fallback) {
    if (!has(key)) {
      mark(key);
      return fallback;
    }
    T v = require<T>(key);
    if constexpr (std::is_floating_point_v<T>) {
      if (!std::isfinite(v)) fail(key, "expected a finite number");
    }
    return v;
  }
  template <class T>
  T require(const std::string& key) {
    const YAML::Node n = child(key);
    try {
      return n.as<T>();
    } catch (const YAML::Exception&) {
      fail(key, fmt::format("expected {}", type_name<T>()), n);
    }
  }
  // Numbers with an inclusive range check.
  template <class T>
  T get_in_range(const std::string& key, const T& fallback, const T& lo, const T& hi) {
    T v = get<T>(key, fallback);
    // NaN too
    if (!(v >= lo && v <= hi))
      fail(key, fmt::format("expected a value in [{}, {}], got {}", lo, hi, v));
    return v;
  }
  Vec3 require_vec3(const std::string& key);
  Vec3 get_vec3(const std::string& key, const Vec3& fallback) {
    return has(key) ? require_vec3(key) : (mark(key), fallback);
  }

  YamlMap map(const std::string& key);  // a required nested map
  std::vector<YamlMap> list_of_maps(const std::string& key);
  YAML::Node raw(const std::string& key) { return child(key); }
  YAML::Node raw_sequence(const std::string& key);  // a required list

  // Throws for every key of this map that was never read.
  void finish() const;

  [[noreturn]] void fail(const std::string& key, const std::string& message) const {
    fail(key, message, node_[key]);
  }
  [[noreturn]] void fail(const std::string& key, const std::string& message,
                         const YAML::Node& at) const;

 private:
  YAML::Node child(const std::string& key);
  void mark(const std::string& key) { used_->insert(key); }
  YamlMap sub(const YAML::Node& n, std::string path) const;
  [[noreturn]] void throw_for(const std::string& key, long line, const std::string& message) const;
  template <class T>
  static const char* type_name() {
    if constexpr (std::is_same_v<T, bool>)
      return "true or false";
    else if constexpr (std::is_integral_v<T>)
      return "an integer";
    else if constexpr (std::is_floating_point_v<T>)
      return "a number";
    else if constexpr (std::is_same_v<T, std::string>)
      return "a string";
    else
      return "a value of another type";
  }

  YAML::Node node_;
  std::string file_, path_;
  std::shared_ptr<std::set<std::string>> used_ = std::make_shared<std::set<std::string>>();
  // Key path -> the override that set it (shared by a document's maps).
  std::shared_ptr<const std::map<std::string, std::string>> overridden_;
};

}  // namespace rtsim
