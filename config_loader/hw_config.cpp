#include "config_loader/hw_config.h"

#include "common/yaml_reader.h"
#include "model/sim/config_reader.h"

#include <fmt/format.h>

#include <stdexcept>
#include <type_traits>

namespace rtsim {

namespace {

// A hardware file's reader: the description's reader, and a dram section's preset.
class HwReader : public model::ConfigReader {
 public:
  using ConfigReader::ConfigReader;
  void preset(const char* key, model::DramConfig& dram, const char*) {
    YamlMap& m = at(key);
    if (!m.has(key)) return;  // the defaults' preset stands
    try {
      dram = model::dram_preset(m.get<std::string>(key, ""));
    } catch (const std::invalid_argument& e) {
      m.fail(key, e.what());
    }
  }
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
    at()[key] = model::choice_name_of(field, choices);
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
    row(key, model::choice_name_of(field, choices), fmt::format("{}", fmt::join(names, ", ")), "",
        meaning);
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
  HwReader reader(std::move(top));
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
