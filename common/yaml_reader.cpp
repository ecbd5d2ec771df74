#include "common/yaml_reader.h"

#include <cmath>
#include <filesystem>

namespace rtsim {

YamlMap YamlMap::load_file(const std::string& path) {
  if (!std::filesystem::exists(path)) throw InputError(fmt::format("{}: file not found", path));
  if (!std::filesystem::is_regular_file(path)) throw InputError(fmt::format("{}: not a regular file", path));
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw_at_line(path, e.mark.line + 1, "YAML syntax error: " + e.msg);
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{}: cannot read YAML: {}", path, e.what()));
  }
  if (!root.IsMap()) throw_at_line(path, root.Mark().line + 1, "expected a mapping of keys at the top level");
  return YamlMap(root, path, "");
}

YamlMap::YamlMap(const YAML::Node& node, std::string file, std::string path)
    : node_(node), file_(std::move(file)), path_(std::move(path)) {
  // Keys must be plain scalars, each given once: a second 'resolution' must not silently lose.
  std::set<std::string> seen;
  for (const auto& kv : node_) {
    const long line = kv.first.Mark().line + 1;
    if (!kv.first.IsScalar()) throw_at_line(file_, line, fmt::format("in '{}': expected a plain key", path_.empty() ? "top level" : path_));
    const std::string key = kv.first.as<std::string>();
    if (!seen.insert(key).second) throw_at_line(file_, line, fmt::format("key '{}': given twice", key_path(key)));
  }
}

std::vector<std::string> YamlMap::keys() const {
  std::vector<std::string> out;
  for (const auto& kv : node_) out.push_back(kv.first.as<std::string>());
  return out;
}

YAML::Node YamlMap::child(const std::string& key) {
  mark(key);
  const YAML::Node& self = node_;  // const access: a missing key must not be inserted
  const YAML::Node n = self[key];
  if (!n.IsDefined() || n.IsNull()) fail(key, "required key is missing", node_);
  return n;
}

Vec3 YamlMap::require_vec3(const std::string& key) {
  const YAML::Node n = child(key);
  if (!n.IsSequence() || n.size() != 3) fail(key, "expected a list of 3 numbers", n);
  Vec3 v;
  try {
    v = Vec3(n[0].as<float>(), n[1].as<float>(), n[2].as<float>());
  } catch (const YAML::Exception&) {
    fail(key, "expected a list of 3 numbers", n);
  }
  if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z)) fail(key, "expected 3 finite numbers", n);
  return v;
}

YAML::Node YamlMap::raw_sequence(const std::string& key) {
  const YAML::Node n = child(key);
  if (!n.IsSequence()) fail(key, "expected a list", n);
  return n;
}

YamlMap YamlMap::map(const std::string& key) {
  const YAML::Node n = child(key);
  if (!n.IsMap()) fail(key, "expected a mapping of keys", n);
  return YamlMap(n, file_, key_path(key));
}

std::vector<YamlMap> YamlMap::list_of_maps(const std::string& key) {
  const YAML::Node n = child(key);
  if (!n.IsSequence()) fail(key, "expected a list", n);
  std::vector<YamlMap> out;
  for (size_t i = 0; i < n.size(); ++i) {
    const std::string p = fmt::format("{}[{}]", key_path(key), i);
    if (!n[i].IsMap()) throw_at_line(file_, n[i].Mark().line + 1, fmt::format("key '{}': expected a mapping of keys", p));
    out.emplace_back(n[i], file_, p);
  }
  return out;
}

void YamlMap::finish() const {
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    if (used_->count(key)) continue;
    const long line = kv.first.Mark().line + 1;
    if (kv.second.IsNull()) throw_at_line(file_, line, fmt::format("key '{}': has no value", key_path(key)));
    throw_at_line(file_, line, fmt::format("key '{}': unknown key", key_path(key)));
  }
}

void YamlMap::fail(const std::string& key, const std::string& message, const YAML::Node& at) const {
  const long line = at.IsDefined() ? at.Mark().line + 1 : node_.Mark().line + 1;
  throw_at_line(file_, line, fmt::format("key '{}': {}", key_path(key), message));
}

}  // namespace rtsim
