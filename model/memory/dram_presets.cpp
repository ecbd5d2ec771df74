// The DRAM presets: one YAML file per preset in configs/dram/ (compiled in, dram_preset_files.h),
// named by its file. A file sets the keys of a hardware file's dram section (configs/README.md)
// and request_bytes; `base: NAME` starts it from another preset's values. Every value's source
// is a comment in its file.
#include "model/memory/dram_config.h"
#include "model/memory/dram_preset_files.h"
#include "model/sim/config_reader.h"

#include <algorithm>
#include <map>
#include <stdexcept>

namespace rtsim::model {

namespace {

std::string name_of(const std::string& path) {
  const size_t slash = path.rfind('/') + 1, dot = path.rfind('.');
  return path.substr(slash, dot - slash);
}

const EmbeddedFile* file_of(const std::string& name) {
  for (const EmbeddedFile& f : dram_preset_files())
    if (name_of(f.path) == name) return &f;
  return nullptr;
}

[[noreturn]] void unknown(const std::string& name) {
  std::string known;
  for (const std::string& n : dram_preset_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown DRAM preset '" + name + "' (known: " + known + ")");
}

DramConfig read_file(const EmbeddedFile& file, std::vector<std::string>& chain);

// `chain`: the presets being read, outermost first (a base that names one of them is a cycle).
DramConfig read_preset(const std::string& name, std::vector<std::string>& chain) {
  const EmbeddedFile* file = file_of(name);
  if (!file) unknown(name);
  return read_file(*file, chain);
}

DramConfig read_file(const EmbeddedFile& file, std::vector<std::string>& chain) {
  const std::string name = name_of(file.path);
  YAML::Node doc;
  try {
    doc = YAML::Load(file.text);
  } catch (const YAML::Exception& e) {
    throw_at_line(file.path, e.mark.line + 1, e.msg);
  }
  YamlMap m = YamlMap::from_node(doc, file.path, "");
  DramConfig c;
  if (m.has("base")) {
    const std::string base = m.get<std::string>("base", "");
    if (std::find(chain.begin(), chain.end(), base) != chain.end())
      m.fail("base", "'" + base + "' derives from this preset (a cycle)");
    chain.push_back(name);
    try {
      c = read_preset(base, chain);
    } catch (const std::invalid_argument& e) {
      m.fail("base", e.what());
    }
    chain.pop_back();
  }
  ConfigReader reader(m);
  describe(reader, c);
  // Not a hardware-file key (there, the L2 line size): the controller's own request size.
  c.request_bytes = uint32_t(m.get_in_range<int64_t>("request_bytes", c.request_bytes, 1, 4096));
  reader.finish();
  c.preset = name;
  try {
    c.validate();
  } catch (const std::invalid_argument& e) {
    throw InputError(std::string(file.path) + ": " + e.what());
  }
  return c;
}

}  // namespace

DramConfig read_dram_preset(const EmbeddedFile& file) {
  std::vector<std::string> chain;
  return read_file(file, chain);
}

std::vector<std::string> dram_preset_names() {
  std::vector<std::string> names;
  for (const EmbeddedFile& f : dram_preset_files()) names.push_back(name_of(f.path));
  std::sort(names.begin(), names.end());
  return names;
}

DramConfig dram_preset(const std::string& name) {
  // Read once: every accelerator config starts from a preset.
  static const std::map<std::string, DramConfig> presets = [] {
    std::map<std::string, DramConfig> all;
    for (const std::string& n : dram_preset_names()) {
      std::vector<std::string> chain;
      all[n] = read_preset(n, chain);
    }
    return all;
  }();
  const auto it = presets.find(name);
  if (it == presets.end()) unknown(name);
  return it->second;
}

}  // namespace rtsim::model
