#include "testbench/studies/sweep_file.h"

#include "common/yaml_reader.h"
#include "testbench/run/run_config.h"
#include "testbench/studies/sweep_metrics.h"

#include <fmt/format.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <filesystem>

namespace fs = std::filesystem;

namespace rtsim {

namespace {

constexpr size_t kMaxPoints = 100000;

std::string emit_flow(const YAML::Node& n) {
  YAML::Emitter e;
  e << YAML::Flow << n;
  return e.c_str();
}

// A scalar as JSON: integer, number, true/false (YAML's on/off too), else the string.
nlohmann::json typed(const YAML::Node& n) {
  if (!n.IsScalar()) return emit_flow(n);
  const std::string s = n.Scalar();
  if (!s.empty()) {
    char* end = nullptr;
    errno = 0;
    const long long i = std::strtoll(s.c_str(), &end, 10);
    if (*end == '\0' && errno == 0) return i;
    const double d = std::strtod(s.c_str(), &end);
    if (*end == '\0' && std::isfinite(d)) return d;
  }
  bool b = false;
  if (YAML::convert<bool>::decode(n, b)) return b;
  return s;
}

void check_key_path(YamlMap& m, const std::string& section_key, const std::string& path) {
  if (path.rfind("hw.", 0) != 0 && path.rfind("scene.", 0) != 0 && path.rfind("run.", 0) != 0)
    m.fail(section_key,
           fmt::format("'{}': expected a key path starting with 'hw.', 'scene.' or 'run.'", path));
}

// A map of dotted key paths to values -> "--set" strings, in file order. With `hw` given (a
// variant), the key `hw` names a hardware file instead (the value as written).
std::vector<std::pair<std::string, std::string>> read_overrides(YamlMap& parent,
                                                                const std::string& key,
                                                                std::string* hw = nullptr) {
  std::vector<std::pair<std::string, std::string>> out;
  const YAML::Node n = parent.raw(key);
  if (!n.IsMap()) parent.fail(key, "expected a mapping of key paths to values", n);
  for (const auto& kv : n) {
    const std::string path = kv.first.as<std::string>();
    if (hw && path == "hw") {
      if (!kv.second.IsScalar() || kv.second.Scalar().empty())
        parent.fail(key, "'hw': expected the path of a hardware file", kv.second);
      *hw = kv.second.Scalar();
      continue;
    }
    check_key_path(parent, key, path);
    if (kv.second.IsNull()) parent.fail(key, fmt::format("'{}' has no value", path), kv.second);
    out.emplace_back(path, emit_flow(kv.second));
  }
  return out;
}

fs::path beside(const std::string& file, const std::string& rel) {
  const fs::path p(rel);
  return p.is_absolute() ? p : (fs::path(file).parent_path() / p).lexically_normal();
}

struct Variant {
  std::string name, hw_file;  // hw_file: the variant's own hardware file, or empty
  std::vector<std::string> set;
};
using Axes = std::vector<std::pair<std::string, std::vector<YAML::Node>>>;

// name, scenes and hw: checked, the files found beside the sweep file.
void read_name_scenes_and_hw(YamlMap& top, const std::string& path, SweepSpec& s) {
  s.name = top.get<std::string>("name", fs::path(path).stem().string());
  if (s.name.empty() ||
      s.name.find_first_not_of(
          "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-") != std::string::npos)
    top.fail("name", "expected letters, digits, '_', '.' or '-' (it names jobs and files)");
  const YAML::Node scenes = top.raw_sequence("scenes");
  if (scenes.size() == 0) top.fail("scenes", "expected at least one scene file");
  for (const auto& n : scenes) {
    if (!n.IsScalar()) top.fail("scenes", "expected a list of scene file paths", n);
    const fs::path p = beside(path, n.Scalar());
    if (!fs::exists(p)) top.fail("scenes", fmt::format("scene file '{}' not found", p.string()), n);
    s.scenes.push_back(p.string());
  }
  s.hw_file = beside(path, top.require<std::string>("hw")).string();
  if (!fs::exists(s.hw_file))
    top.fail("hw", fmt::format("hardware file '{}' not found", s.hw_file));
}

std::vector<Variant> read_variants(YamlMap& top, const std::string& path, SweepSpec& s) {
  std::vector<Variant> variants;
  if (!top.has("variants")) return variants;
  YamlMap v = top.map("variants");
  for (const std::string& name : v.keys()) {
    Variant var{name, "", {}};
    std::string hw;
    for (const auto& [k, val] : read_overrides(v, name, &hw)) var.set.push_back(k + "=" + val);
    if (!hw.empty()) {
      var.hw_file = beside(path, hw).string();
      if (!fs::exists(var.hw_file))
        v.fail(name, fmt::format("hardware file '{}' not found", var.hw_file));
    }
    variants.push_back(std::move(var));
  }
  if (variants.empty()) top.fail("variants", "expected at least one variant");
  s.columns.push_back("variant");
  return variants;
}

// The variants named in `only` (--variants), in the file's order.
std::vector<Variant> choose_variants(std::vector<Variant> variants,
                                     const std::vector<std::string>& only,
                                     const std::string& path) {
  if (only.empty()) return variants;
  if (variants.empty()) throw InputError(fmt::format("--variants: {} has no variants", path));
  std::string names;
  for (const Variant& v : variants) names += (names.empty() ? "" : ", ") + v.name;
  for (const std::string& name : only)
    if (std::none_of(variants.begin(), variants.end(),
                     [&](const Variant& v) { return v.name == name; }))
      throw InputError(fmt::format("--variants: '{}' is not a variant of {} (expected one of: {})",
                                   name, path, names));
  variants.erase(std::remove_if(variants.begin(), variants.end(),
                                [&](const Variant& v) {
                                  return std::find(only.begin(), only.end(), v.name) == only.end();
                                }),
                 variants.end());
  return variants;
}

Axes read_axes(YamlMap& top, SweepSpec& s) {
  Axes axes;
  if (!top.has("axes")) return axes;
  YamlMap a = top.map("axes");
  for (const std::string& key : a.keys()) {
    check_key_path(a, key, key);
    const YAML::Node values = a.raw_sequence(key);
    if (values.size() == 0) a.fail(key, "expected at least one value");
    axes.emplace_back(key, std::vector<YAML::Node>(values.begin(), values.end()));
    s.columns.push_back(key);
  }
  return axes;
}

void read_metrics_and_reports(YamlMap& top, SweepSpec& s) {
  if (top.has("metrics")) {
    s.metrics = top.get<std::vector<std::string>>("metrics", {});
    if (s.metrics.empty()) top.fail("metrics", "expected at least one metric");
    for (const std::string& m : s.metrics)
      if (!is_sweep_metric(m))
        top.fail("metrics",
                 fmt::format("'{}': expected a metric name (configs/README.md) or a "
                             "dotted path into report.json (cycles_*, frame_ms.*, "
                             "rays.*, per_light.*, path.*, lvb.*, kdtree.*, scene.*, stats.*, "
                             "sample.*)",
                             m));
  } else {
    s.metrics = kDefaultSweepMetrics;
  }
  // Reports that read the whole sweep: "area" pairs culling off and on per scene and sample count.
  s.reports = top.get<std::vector<std::string>>("reports", {});
  s.point_timeout = top.get_in_range<double>("point_timeout", 0.0, 0.0, 1e7);
  for (const std::string& r : s.reports) {
    if (r != "area") top.fail("reports", fmt::format("'{}': expected 'area'", r));
    for (const char* axis : {"scene.lights.area_from_points.samples", "run.lvb"})
      if (std::find(s.columns.begin(), s.columns.end(), axis) == s.columns.end())
        top.fail("reports",
                 "'area' needs the axes scene.lights.area_from_points.samples and run.lvb");
  }
}

// The cross product, last axis fastest.
void make_points(YamlMap& top, const std::vector<std::string>& base,
                 const std::vector<Variant>& variants, const Axes& axes, SweepSpec& s) {
  size_t count = s.scenes.size() * std::max<size_t>(variants.size(), 1);
  for (const auto& [k, v] : axes) {
    count *= v.size();
    if (count > kMaxPoints) top.fail("axes", fmt::format("more than {} points", kMaxPoints));
  }
  for (size_t i = 0; i < count; ++i) {
    SweepPoint p;
    p.index = uint32_t(i);
    p.id = fmt::format("p{:04d}", i);
    p.values = nlohmann::json::object();
    p.set = base;
    std::vector<const YAML::Node*> chosen(axes.size());
    size_t rest = i;
    for (size_t a = axes.size(); a-- > 0;) {
      chosen[a] = &axes[a].second[rest % axes[a].second.size()];
      rest /= axes[a].second.size();
    }
    if (!variants.empty()) {
      const Variant& var = variants[rest % variants.size()];
      rest /= variants.size();
      p.values["variant"] = var.name;
      p.hw_file = var.hw_file;
      p.set.insert(p.set.end(), var.set.begin(), var.set.end());
    }
    p.scene_file = s.scenes[rest];
    for (size_t a = 0; a < axes.size(); ++a) {
      p.values[axes[a].first] = typed(*chosen[a]);
      p.set.push_back(axes[a].first + "=" + emit_flow(*chosen[a]));
    }
    s.points.push_back(std::move(p));
  }
}

// Every point's hardware and run settings are checked now, before anything runs.
void check_points(const SweepSpec& s, const std::string& path) {
  for (const SweepPoint& p : s.points) {
    RunSources src;
    src.scene_file = p.scene_file;
    src.hw_file = s.hw_of(p);
    for (const std::string& e : p.set)
      if (e.rfind("scene.", 0) != 0) src.set.push_back(e);
    try {
      resolve_run_config(src);
    } catch (const InputError& e) {
      throw InputError(fmt::format("{}: point {} ({}): {}", path, p.id, p.values.dump(), e.what()));
    }
  }
}

}  // namespace

SweepSpec load_sweep(const std::string& path, const std::vector<std::string>& extra_set,
                     const std::vector<std::string>& only_variants) {
  YamlMap top = YamlMap::load_file(path);
  SweepSpec s;
  s.file = path;
  read_name_scenes_and_hw(top, path, s);
  // Points skip their figures unless the sweep asks for them (the sweep draws its own).
  std::vector<std::string> base{"run.plots=false"};
  if (top.has("set"))
    for (const auto& [k, v] : read_overrides(top, "set")) base.push_back(k + "=" + v);
  for (const std::string& e : extra_set) base.push_back(e);
  const std::vector<Variant> variants =
      choose_variants(read_variants(top, path, s), only_variants, path);
  const Axes axes = read_axes(top, s);
  read_metrics_and_reports(top, s);
  top.finish();
  make_points(top, base, variants, axes, s);
  check_points(s, path);
  return s;
}

}  // namespace rtsim
