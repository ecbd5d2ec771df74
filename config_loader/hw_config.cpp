#include "config_loader/hw_config.h"

#include "common/yaml_reader.h"

#include <fmt/format.h>

#include <stdexcept>
#include <type_traits>

namespace rtsim {

namespace {

template <class E>
std::string choice_names(model::Choices<E> choices) {
  std::vector<std::string> names;
  for (const auto& [name, value] : choices) names.push_back(fmt::format("'{}'", name));
  std::string s = names.back();
  if (names.size() > 1)
    s = fmt::format("{} or {}", fmt::join(names.begin(), names.end() - 1, ", "), names.back());
  return s;
}

template <class E>
const char* name_of(const E& value, model::Choices<E> choices) {
  for (const auto& [name, v] : choices)
    if (v == value) return name;
  return "?";
}

// Reads a hardware file's maps into the config the description names
// (model/sim/config_description.h); absent keys keep their defaults, unknown keys are errors
// (YamlMap::finish).
class YamlReader {
 public:
  explicit YamlReader(YamlMap top) { maps_.push_back(std::move(top)); }
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
  void choice(const char* key, E& field, model::Choices<E> choices, const char*) {
    YamlMap& m = at(key);
    const std::string v = m.get<std::string>(key, name_of(field, choices));
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
  void preset(const char* key, model::DramConfig& dram, const char*) {
    YamlMap& m = at(key);
    if (!m.has(key)) return;  // the defaults' preset stands
    try {
      dram = model::dram_preset(m.get<std::string>(key, ""));
    } catch (const std::invalid_argument& e) {
      m.fail(key, e.what());
    }
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

 private:
  YamlMap& at(const char* key) {
    if (!first_.empty() && first_.back().empty()) first_.back() = key;
    return maps_.back();
  }
  std::vector<YamlMap> maps_;
  std::vector<std::string> first_;
};

// The config as JSON, key for key (config.json).
class JsonWriter {
 public:
  nlohmann::json out = nlohmann::json::object();

  template <class T>
  void number(const char* key, const T& field, double, double, const char*, const char*) {
    at()[key] = field;
  }
  void kib(const char* key, uint32_t bytes, double, double, const char*) {
    at()[key] = bytes / 1024;
  }
  void flag(const char* key, bool field, const char*) { at()[key] = field; }
  void text(const char* key, const std::string& field, const char*) { at()[key] = field; }
  template <class E>
  void choice(const char* key, const E& field, model::Choices<E> choices, const char*) {
    at()[key] = name_of(field, choices);
  }
  void registered(const char* key, const std::string& field, const std::vector<RegisteredName>&,
                  const char*) {
    at()[key] = field;
  }
  void preset(const char* key, const model::DramConfig& dram, const char*) {
    at()[key] = dram.preset;
  }
  template <class F, class G>
  void section(const char* key, const char* meaning, F&& body, G&&) {
    section(key, meaning, body);
  }
  template <class F>
  void section(const char* key, const char*, F&& body) {
    stack_.push_back(key);
    at() = nlohmann::json::object();
    body();
    stack_.pop_back();
  }

 private:
  nlohmann::json& at() {
    nlohmann::json* j = &out;
    for (const char* k : stack_) j = &(*j)[k];
    return *j;
  }
  std::vector<const char*> stack_;
};

// One markdown row per key: path, default, range, unit, meaning.
class DocTable {
 public:
  std::string rows;

  template <class T>
  void number(const char* key, const T& field, double lo, double hi, const char* unit,
              const char* meaning) {
    row(key, fmt::format("{}", field), fmt::format("{} .. {}", lo, hi), unit, meaning);
  }
  void kib(const char* key, uint32_t bytes, double lo, double hi, const char* meaning) {
    row(key, fmt::format("{}", bytes / 1024), fmt::format("{} .. {}", lo, hi), "KB", meaning);
  }
  void flag(const char* key, bool field, const char* meaning) {
    row(key, field ? "true" : "false", "true, false", "", meaning);
  }
  void text(const char* key, const std::string& field, const char* meaning) {
    row(key, field.size() > 24 ? field.substr(0, 21) + "..." : field, "text", "", meaning);
  }
  template <class E>
  void choice(const char* key, const E& field, model::Choices<E> choices, const char* meaning) {
    std::vector<std::string> names;
    for (const auto& [name, v] : choices) names.push_back(name);
    row(key, name_of(field, choices), fmt::format("{}", fmt::join(names, ", ")), "", meaning);
  }
  // The meaning, then each name's: "meaning (a: ...; b: ...)".
  void registered(const char* key, const std::string& field,
                  const std::vector<RegisteredName>& names, const char* meaning) {
    std::vector<std::string> listed, meanings;
    for (const RegisteredName& n : names) {
      listed.push_back(n.name);
      meanings.push_back(n.name + ": " + n.description);
    }
    row(key, field, fmt::format("{}", fmt::join(listed, ", ")), "",
        fmt::format("{} ({})", meaning, fmt::join(meanings, "; ")).c_str());
  }
  void preset(const char* key, const model::DramConfig& dram, const char* meaning) {
    row(key, dram.preset, fmt::format("{}", fmt::join(model::dram_preset_names(), ", ")), "",
        meaning);
  }
  template <class F, class G>
  void section(const char* key, const char* meaning, F&& body, G&&) {
    section(key, meaning, body);
  }
  template <class F>
  void section(const char* key, const char*, F&& body) {
    prefix_.push_back(key);
    body();
    prefix_.pop_back();
  }

 private:
  void row(const char* key, const std::string& value, const std::string& range, const char* unit,
           const char* meaning) {
    std::string path;
    for (const char* p : prefix_) path += std::string(p) + ".";
    rows += fmt::format("| `{}{}` | {} | {} | {} | {} |\n", path, key,
                        value.empty() ? "\"\"" : value, range, unit, meaning);
  }
  std::vector<const char*> prefix_;
};

}  // namespace

model::AcceleratorConfig load_hw_config(const std::string& path,
                                        const std::vector<ConfigOverride>& overrides) {
  return read_hw_config(YamlMap::load_file(path, overrides));
}

model::AcceleratorConfig read_hw_config(YamlMap top) {
  const std::string file = top.file();
  model::AcceleratorConfig c;
  YamlReader reader(std::move(top));
  model::describe(reader, c);
  reader.finish();
  try {
    c.validate();
  } catch (const std::invalid_argument& e) {
    throw InputError(file + ": " + e.what());
  }
  return c;
}

nlohmann::json hw_config_json(const model::AcceleratorConfig& c) {
  JsonWriter w;
  model::describe(w, c);
  return w.out;
}

std::string hw_params_markdown() {
  DocTable t;
  const model::AcceleratorConfig defaults;
  model::describe(t, defaults);
  return "| key | default | range | unit | meaning |\n|---|---|---|---|---|\n" + t.rows;
}

}  // namespace rtsim
