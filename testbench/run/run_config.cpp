#include "testbench/run/run_config.h"

#include "config_loader/hw_config.h"
#include "kernels/names.h"

#include <fmt/format.h>

#include <cmath>
#include <cstdio>

namespace rtsim {

namespace {

struct SplitOverrides {
  std::vector<ConfigOverride> hw, scene, run;
  std::vector<std::string> scene_text;
};

SplitOverrides split_overrides(const std::vector<std::string>& set) {
  SplitOverrides out;
  for (const std::string& text : set) {
    ConfigOverride o = parse_override(text);
    const std::string section = o.keys.front();
    if (o.keys.size() < 2 || (section != "hw" && section != "scene" && section != "run"))
      throw InputError(fmt::format(
          "--set {}: expected a key path starting with 'hw.', 'scene.' or 'run.'", text));
    o.keys.erase(o.keys.begin());
    if (section == "hw")
      out.hw.push_back(std::move(o));
    else if (section == "run")
      out.run.push_back(std::move(o));
    else {
      out.scene.push_back(std::move(o));
      out.scene_text.push_back(text);
    }
  }
  return out;
}

template <class Enum>
Enum read_choice(YamlMap& m, const std::string& key, Enum fallback,
                 std::initializer_list<Enum> choices) {
  const std::string v = m.get<std::string>(key, to_string(fallback));
  std::string expected;
  for (Enum c : choices) {
    if (v == to_string(c)) return c;
    expected += (expected.empty() ? "'" : " or '") + std::string(to_string(c)) + "'";
  }
  m.fail(key, "expected " + expected);
}

void read_sample_settings(YamlMap& m, SampleSettings& s) {
  if (m.has("sample")) {
    s.fraction = m.get<double>("sample", 0);
    if (!(s.fraction > 0 && s.fraction <= 1)) m.fail("sample", "expected a fraction in (0, 1]");
  }
  s.unit = m.get_in_range<uint32_t>("sample_unit", s.unit, 64, 1u << 24);
  if (s.unit % model::kBatchRays) m.fail("sample_unit", "expected a multiple of 64 rays");
  s.warmup = m.get_in_range<uint32_t>("sample_warmup", s.warmup, 0, 1u << 24);
  if (s.warmup % model::kBatchRays) m.fail("sample_warmup", "expected a multiple of 64 rays");
  s.warming_rows = m.get_in_range<double>("sample_warming", s.warming_rows, 0.0, 64.0);
  s.seed = m.get<uint64_t>("sample_seed", s.seed);
  s.target_pct = m.get_in_range<double>("sample_target_pct", s.target_pct, 0.0, 100.0);
  s.grow = m.get<bool>("sample_grow", s.grow);
  const std::string strata = m.get<std::string>("sample_strata", strata_name(s.strata));
  if (strata != "issue" && strata != "neyman")
    m.fail("sample_strata", "expected 'issue' or 'neyman'");
  s.strata = strata == "neyman" ? SampleStrata::kNeyman : SampleStrata::kIssue;
  if (s.fraction == 0 && (s.target_pct > 0 || s.grow))
    m.fail(s.grow ? "sample_grow" : "sample_target_pct", "needs a sampled frame (run.sample)");
  if (s.grow && s.target_pct == 0) m.fail("sample_grow", "needs run.sample_target_pct");
}

RunSettings read_run_settings(YamlMap m) {
  RunSettings r;
  const std::string accel = m.get<std::string>("accel", to_string(r.accel));
  try {
    r.accel = parse_accel(accel);
  } catch (const std::invalid_argument&) {
    m.fail("accel", "expected " + quoted_names(accel_names()));
  }
  r.lvb = m.get<bool>("lvb", r.lvb);
  r.lvb_params.method = read_choice(m, "lvb_method", r.lvb_params.method,
                                    {LvbMethod::kHierarchical, LvbMethod::kPaper});
  r.lvb_params.bounds =
      read_choice(m, "lvb_bounds", r.lvb_params.bounds, {LvbBounds::kCell, LvbBounds::kGeometry});
  r.lvb_params.self_occlusion = read_choice(m, "lvb_self_occlusion", r.lvb_params.self_occlusion,
                                            {LvbSelfOcclusion::kTest, LvbSelfOcclusion::kIgnore});
  r.lvb_params.frustum_test = read_choice(m, "lvb_frustum_test", r.lvb_params.frustum_test,
                                          {LvbFrustumTest::kOverlap, LvbFrustumTest::kContained});
  r.reflections = m.get_in_range("reflections", r.reflections, 0, 8);
  r.integrator =
      read_choice(m, "integrator", r.integrator, {Integrator::kWhitted, Integrator::kPath});
  r.path.spp = m.get_in_range("spp", r.path.spp, 1, 65536);
  r.path.max_depth = m.get_in_range("max_depth", r.path.max_depth, 0, 64);
  r.path.roulette_depth = m.get_in_range("roulette_depth", r.path.roulette_depth, 1, 65);
  if (r.integrator == Integrator::kPath && r.reflections > 0)
    m.fail("reflections",
           "a path-traced frame's mirrors are lobes of its paths: expected 0 with "
           "integrator: path (max_depth bounds every bounce)");
  r.width = m.get_in_range("width", r.width, 0, 16384);
  r.height = m.get_in_range("height", r.height, 0, 16384);
  r.check = m.get<bool>("check", r.check);
  r.plots = m.get<bool>("plots", r.plots);
  r.tlm_checks = m.get<bool>("tlm_checks", r.tlm_checks);
  r.time_resolution_ps =
      m.get_in_range<uint64_t>("time_resolution_ps", r.time_resolution_ps, 1, 1'000'000);
  for (uint64_t v = r.time_resolution_ps; v > 1; v /= 10)
    if (v % 10 != 0) m.fail("time_resolution_ps", "expected a power of ten (1, 10, 100, 1000 ...)");
  if (const double since = m.get<double>("lvb_lazy_since", std::nan("")); !std::isnan(since))
    r.lvb_lazy_since = since;
  read_sample_settings(m, r.sample);
  m.finish();
  return r;
}

// What a sampled frame needs of the machine (model/accelerator.h, Accelerator::sample).
void check_sampled(const RunConfig& c) {
  if (c.run.sample.fraction == 0) return;
  const char* why = nullptr;
  if (c.hw.schedule != model::Schedule::kTwoPhase) why = "hw.schedule: two-phase";
  if (c.hw.culling.records_per_cycle == 0 || !c.hw.write_records)
    why =
        "the culling unit to read the hit records from memory (hw.culling.records_per_cycle > "
        "0 and hw.shading.write_records: true)";
  if (c.hw.reflection_depth > 0) why = "no reflections (run.reflections: 0)";
  if (c.run.integrator != Integrator::kWhitted) why = "a Whitted frame (run.integrator: whitted)";
  if (why) throw InputError(fmt::format("run.sample: a sampled frame needs {}", why));
}

}  // namespace

RunConfig resolve_run_config(const RunSources& src) {
  const SplitOverrides ov = split_overrides(src.set);
  RunConfig c;
  YAML::Node run_node(YAML::NodeType::Map);
  std::string run_file = "command line";
  if (!src.config_file.empty()) {
    if (!src.scene_file.empty() || !src.hw_file.empty())
      throw InputError("give either --config FILE or a scene file and --hw, not both");
    YamlMap doc = YamlMap::load_file(src.config_file);
    c.scene_file = doc.require<std::string>("scene_file");
    for (const auto& s : doc.get<std::vector<std::string>>("scene_set", {}))
      c.scene_set.push_back(s);
    c.scene_root = doc.get<std::string>("scene_root", "");
    c.hw_file = doc.get<std::string>("hw_file", "");
    c.hw = read_hw_config(YamlMap::from_node(doc.raw("hw"), src.config_file, "hw", ov.hw));
    run_node = doc.raw("run");
    run_file = src.config_file;
    doc.finish();
  } else {
    if (src.scene_file.empty() || src.hw_file.empty())
      throw InputError("expected a scene file and --hw HW.yaml (or --config DIR/config.json)");
    c.scene_file = src.scene_file;
    c.hw_file = src.hw_file;
    c.hw = load_hw_config(src.hw_file, ov.hw);
  }
  if (!src.scene_root.empty()) c.scene_root = src.scene_root;
  c.scene_set.insert(c.scene_set.end(), ov.scene_text.begin(), ov.scene_text.end());
  // Flags given on the command line, then --set run.*: the later one wins.
  std::vector<ConfigOverride> run_ov;
  for (const auto& kv : src.run_flags)
    run_ov.push_back({{kv.first.as<std::string>()}, kv.second, "--" + kv.first.as<std::string>()});
  run_ov.insert(run_ov.end(), ov.run.begin(), ov.run.end());
  c.run = read_run_settings(
      YamlMap::from_node(run_node, run_file, src.config_file.empty() ? "" : "run", run_ov));
  c.hw.lvb_culling = c.run.lvb;
  c.hw.reflection_depth = c.run.reflections;
  c.hw.integrator = c.run.integrator;
  c.hw.path = c.run.path;
  if (is_bvh(c.run.accel) != (c.hw.structure == model::Structure::kBvh))
    throw InputError(fmt::format(
        "run.accel: {} needs a machine whose traversal units walk {} (hw.structure: {}); {} has "
        "structure: {} (configs/hw/bvh-tni.yaml walks BVHs, configs/hw/tni-paper.yaml the kd-tree)",
        to_string(c.run.accel), is_bvh(c.run.accel) ? "a BVH" : "the kd-tree",
        structure_family(is_bvh(c.run.accel)), c.hw_file.empty() ? "the hardware" : c.hw_file,
        structure_family(c.hw.structure == model::Structure::kBvh)));
  check_sampled(c);
  return c;
}

void check_writable(const char* flag, const std::string& file, const std::string& probe) {
  if (std::FILE* f = std::fopen(probe.c_str(), "w")) {
    std::fclose(f);
    std::remove(probe.c_str());
    return;
  }
  throw InputError(fmt::format("{} {}: cannot write there", flag, file));
}

void check_writable(const char* flag, const std::string& file) {
  check_writable(flag, file, file + ".part.probe");
}

TraceWindow parse_trace_window(const std::string& window) {
  TraceWindow w;
  if (window.empty()) return w;
  unsigned long long a = 0, b = 0;
  char tail = 0;
  if (std::sscanf(window.c_str(), "%llu:%llu%c", &a, &b, &tail) != 2 ||
      window.find('-') != std::string::npos || b <= a)
    throw InputError(
        fmt::format("--trace-window {}: expected START:END in cycles with START < END", window));
  return {a, b};
}

model::TraceRequest parse_trace_request(const char* flag, const std::string& file,
                                        const std::string& window) {
  // The file is written at the end of the run (a VCD: SystemC opens it only when the simulation
  // starts): check now that it can be.
  check_writable(flag, file, file + ".part.probe");
  const TraceWindow w = parse_trace_window(window);
  model::TraceRequest t;
  t.file = file;
  t.start_cycle = w.start;
  t.end_cycle = w.end;
  return t;
}

nlohmann::json run_settings_json(const RunSettings& r) {
  nlohmann::json j = {{"accel", to_string(r.accel)},
                      {"lvb", r.lvb},
                      {"lvb_method", to_string(r.lvb_params.method)},
                      {"lvb_bounds", to_string(r.lvb_params.bounds)},
                      {"lvb_self_occlusion", to_string(r.lvb_params.self_occlusion)},
                      {"lvb_frustum_test", to_string(r.lvb_params.frustum_test)},
                      {"reflections", r.reflections},
                      {"integrator", to_string(r.integrator)},
                      {"width", r.width},
                      {"height", r.height},
                      {"check", r.check},
                      {"plots", r.plots},
                      {"tlm_checks", r.tlm_checks},
                      {"time_resolution_ps", r.time_resolution_ps}};
  if (r.lvb_lazy_since) j["lvb_lazy_since"] = *r.lvb_lazy_since;
  if (r.integrator == Integrator::kPath) {
    j["spp"] = r.path.spp;
    j["max_depth"] = r.path.max_depth;
    j["roulette_depth"] = r.path.roulette_depth;
  }
  if (r.sample.fraction > 0) {
    j["sample"] = r.sample.fraction;
    j["sample_unit"] = r.sample.unit;
    j["sample_warmup"] = r.sample.warmup;
    j["sample_warming"] = r.sample.warming_rows;
    j["sample_seed"] = r.sample.seed;
    if (r.sample.target_pct > 0) j["sample_target_pct"] = r.sample.target_pct;
    if (r.sample.grow) j["sample_grow"] = true;
    j["sample_strata"] = strata_name(r.sample.strata);
  }
  return j;
}

nlohmann::json run_config_json(const RunConfig& c) {
  return {{"scene_file", c.scene_file}, {"scene_set", c.scene_set},
          {"scene_root", c.scene_root}, {"hw_file", c.hw_file},
          {"hw", hw_config_json(c.hw)}, {"run", run_settings_json(c.run)}};
}

std::vector<ConfigOverride> scene_overrides(const std::vector<std::string>& scene_set) {
  std::vector<ConfigOverride> out;
  for (const std::string& text : scene_set) {
    ConfigOverride o = parse_override(text);
    o.keys.erase(o.keys.begin());  // "scene."
    out.push_back(std::move(o));
  }
  return out;
}

}  // namespace rtsim
