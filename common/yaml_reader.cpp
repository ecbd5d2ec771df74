#include "common/yaml_reader.h"

#include "common/utf8.h"

#include <cmath>
#include <filesystem>

namespace rtsim {

namespace {

// Every key and scalar of a document is UTF-8 text (it may reach a JSON writer); `where` names
// the file, or the --set that gave it.
void check_utf8(const YAML::Node& n, const std::string& where, bool file) {
  auto bad = [&](const YAML::Node& at) {
    if (file) throw_at_line(where, at.Mark().line + 1, "text that is not UTF-8");
    throw InputError(fmt::format("{}: text that is not UTF-8", where));
  };
  if (n.IsScalar() && !is_utf8(n.Scalar())) bad(n);
  if (n.IsSequence())
    for (const YAML::Node& e : n) check_utf8(e, where, file);
  if (n.IsMap())
    for (const auto& kv : n) {
      check_utf8(kv.first, where, file);
      check_utf8(kv.second, where, file);
    }
}

}  // namespace

ConfigOverride parse_override(const std::string& text) {
  const size_t eq = text.find('=');
  auto bad = [&](const std::string& why) -> ConfigOverride {
    throw InputError(fmt::format("--set {}: {} (expected key.path=value)", text, why));
  };
  // The text goes into config.json and reports: UTF-8 only (a value yaml-cpp stops reading
  // before its end could otherwise carry any byte through)
  if (!is_utf8(text))
    throw InputError(
        fmt::format("--set {}: not UTF-8 text (expected key.path=value)", utf8_lossy(text)));
  if (eq == std::string::npos) return bad("no '='");
  ConfigOverride o;
  o.text = "--set " + text;
  const std::string path = text.substr(0, eq);
  size_t start = 0;
  while (true) {
    const size_t dot = path.find('.', start);
    o.keys.push_back(path.substr(start, dot - start));
    if (o.keys.back().empty()) return bad("empty key in the path");
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  try {
    o.value = YAML::Load(text.substr(eq + 1));
  } catch (const YAML::Exception& e) {
    return bad("the value is not valid YAML: " + e.msg);
  }
  if (!o.value.IsDefined() || o.value.IsNull()) return bad("no value");
  if (!is_utf8(path)) throw InputError("--set: a key path that is not UTF-8 text");
  check_utf8(o.value, "--set " + path, false);
  return o;
}

YamlMap YamlMap::from_node(const YAML::Node& node, std::string file, std::string path,
                           const std::vector<ConfigOverride>& overrides) {
  if (!node.IsMap())
    throw_at_line(file, node.Mark().line + 1,
                  path.empty() ? "expected a mapping of keys"
                               : fmt::format("key '{}': expected a mapping of keys", path));
  auto origins = std::make_shared<std::map<std::string, std::string>>();
  for (const ConfigOverride& o : overrides) {
    YAML::Node at = node;
    std::string key_path = path;
    for (size_t i = 0; i < o.keys.size(); ++i) {
      key_path += (key_path.empty() ? "" : ".") + o.keys[i];
      (*origins)[key_path] = o.text;
      if (i + 1 == o.keys.size()) {
        at[o.keys[i]] = YAML::Clone(o.value);
        break;
      }
      if (!at[o.keys[i]].IsDefined() || at[o.keys[i]].IsNull())
        at[o.keys[i]] = YAML::Node(YAML::NodeType::Map);
      const YAML::Node next = at[o.keys[i]];
      if (!next.IsMap())
        throw InputError(
            fmt::format("{}: key '{}' of {} is not a mapping", o.text, key_path, file));
      at.reset(next);
    }
  }
  YamlMap m(node, std::move(file), std::move(path));
  m.overridden_ = std::move(origins);
  return m;
}

YamlMap YamlMap::load_file(const std::string& path, const std::vector<ConfigOverride>& overrides) {
  if (!std::filesystem::exists(path)) throw InputError(fmt::format("{}: file not found", path));
  if (!std::filesystem::is_regular_file(path))
    throw InputError(fmt::format("{}: not a regular file", path));
  YAML::Node root;
  try {
    root = YAML::LoadFile(path);
  } catch (const YAML::ParserException& e) {
    throw_at_line(path, e.mark.line + 1, "YAML syntax error: " + e.msg);
  } catch (const std::exception& e) {
    throw InputError(fmt::format("{}: cannot read YAML: {}", path, e.what()));
  }
  if (!root.IsMap())
    throw_at_line(path, root.Mark().line + 1, "expected a mapping of keys at the top level");
  check_utf8(root, path, true);
  return from_node(root, path, "", overrides);
}

YamlMap::YamlMap(const YAML::Node& node, std::string file, std::string path)
    : node_(node), file_(std::move(file)), path_(std::move(path)) {
  // Keys must be plain scalars, each given once: a second 'resolution' must not silently lose.
  std::set<std::string> seen;
  for (const auto& kv : node_) {
    const long line = kv.first.Mark().line + 1;
    if (!kv.first.IsScalar())
      throw_at_line(
          file_, line,
          fmt::format("in '{}': expected a plain key", path_.empty() ? "top level" : path_));
    const std::string key = kv.first.as<std::string>();
    if (!seen.insert(key).second)
      throw_at_line(file_, line, fmt::format("key '{}': given twice", key_path(key)));
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
  if (!std::isfinite(v.x) || !std::isfinite(v.y) || !std::isfinite(v.z))
    fail(key, "expected 3 finite numbers", n);
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
  return sub(n, key_path(key));
}

YamlMap YamlMap::sub(const YAML::Node& n, std::string path) const {
  YamlMap m(n, file_, std::move(path));
  m.overridden_ = overridden_;
  return m;
}

std::vector<YamlMap> YamlMap::list_of_maps(const std::string& key) {
  const YAML::Node n = child(key);
  if (!n.IsSequence()) fail(key, "expected a list", n);
  std::vector<YamlMap> out;
  for (size_t i = 0; i < n.size(); ++i) {
    const std::string p = fmt::format("{}[{}]", key_path(key), i);
    if (!n[i].IsMap())
      throw_at_line(file_, n[i].Mark().line + 1,
                    fmt::format("key '{}': expected a mapping of keys", p));
    out.push_back(sub(n[i], p));
  }
  return out;
}

void YamlMap::finish() const {
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    if (used_->count(key)) continue;
    const long line = kv.first.Mark().line + 1;
    throw_for(key, line, kv.second.IsNull() ? "has no value" : "unknown key");
  }
}

void YamlMap::fail(const std::string& key, const std::string& message, const YAML::Node& at) const {
  throw_for(key, at.IsDefined() ? at.Mark().line + 1 : node_.Mark().line + 1, message);
}

void YamlMap::throw_for(const std::string& key, long line, const std::string& message) const {
  const std::string path = key_path(key);
  if (overridden_) {
    const auto it = overridden_->find(path);
    if (it != overridden_->end())
      throw InputError(fmt::format("{}: key '{}' of {}: {}", it->second, path, file_, message));
  }
  throw_at_line(file_, line, fmt::format("key '{}': {}", path, message));
}

}  // namespace rtsim
