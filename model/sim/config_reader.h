// A YAML reader for any config struct with a describe() (model/sim/config_description.h).
#pragma once

#include "common/yaml_reader.h"
#include "model/sim/config_description.h"

#include <fmt/format.h>

#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace rtsim::model {

template <class E>
std::string choice_names(Choices<E> choices) {
  std::vector<std::string> names;
  for (const auto& [name, value] : choices) names.push_back(fmt::format("'{}'", name));
  std::string s = names.back();
  if (names.size() > 1)
    s = fmt::format("{} or {}", fmt::join(names.begin(), names.end() - 1, ", "), names.back());
  return s;
}

template <class E>
const char* choice_name_of(const E& value, Choices<E> choices) {
  for (const auto& [name, v] : choices)
    if (v == value) return name;
  return "?";
}

// Reads a YAML map into the config the description names; absent keys keep their defaults,
// unknown keys are errors (YamlMap::finish), and a section whose fields do not fit together is
// reported at its first key. The hardware-file reader (config_loader/hw_config.cpp) adds a dram
// section's preset; the DRAM presets (model/memory/dram_presets.cpp) use it as it is.
class ConfigReader {
 public:
  explicit ConfigReader(YamlMap top) { maps_.push_back(std::move(top)); }
  void finish() { maps_.back().finish(); }

  template <class T>
  void number(const char* key, T& field, double lo, double hi, const char*, const char*) {
    YamlMap& m = at(key);
    // Integers are read as int64 so that a negative value is reported as out of range.
    if constexpr (std::is_integral_v<T>)
      field = T(m.get_in_range<int64_t>(key, int64_t(field), int64_t(lo), int64_t(hi)));
    else
      field = T(m.get_in_range<double>(key, double(field), lo, hi));
  }
  void kib(const char* key, uint32_t& bytes, double lo, double hi, const char*) {
    bytes =
        uint32_t(at(key).get_in_range<int64_t>(key, bytes / 1024, int64_t(lo), int64_t(hi))) * 1024;
  }
  void flag(const char* key, bool& field, const char*) { field = at(key).get<bool>(key, field); }
  void text(const char* key, std::string& field, const char*) {
    field = at(key).get<std::string>(key, field);
  }
  template <class E>
  void choice(const char* key, E& field, Choices<E> choices, const char*) {
    YamlMap& m = at(key);
    const std::string v = m.get<std::string>(key, choice_name_of(field, choices));
    for (const auto& [name, value] : choices)
      if (v == name) {
        field = value;
        return;
      }
    m.fail(key, "expected " + choice_names(choices));
  }
  void registered(const char* key, std::string& field, const std::vector<RegisteredName>& names,
                  const char*) {
    YamlMap& m = at(key);
    field = m.get<std::string>(key, field);
    for (const RegisteredName& n : names)
      if (n.name == field) return;
    m.fail(key, "expected " + quoted_names(names));
  }
  template <class F>
  void section(const char* key, const char* meaning, F&& body) {
    section(key, meaning, body, [] {});
  }
  // A section whose fields do not fit together is reported at its first key.
  template <class F, class G>
  void section(const char* key, const char*, F&& body, G&& check) {
    if (!maps_.back().has(key)) return;
    maps_.push_back(maps_.back().map(key));
    first_.push_back("");
    body();
    maps_.back().finish();
    try {
      check();
    } catch (const std::invalid_argument& e) {
      maps_.back().fail(first_.back(), e.what());
    }
    maps_.pop_back();
    first_.pop_back();
  }

 protected:
  YamlMap& at(const char* key) {
    if (!first_.empty() && first_.back().empty()) first_.back() = key;
    return maps_.back();
  }
  std::vector<YamlMap> maps_;
  std::vector<std::string> first_;
};

}  // namespace rtsim::model
