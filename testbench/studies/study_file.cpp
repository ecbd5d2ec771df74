#include "testbench/studies/study_file.h"

#include "common/error.h"
#include "common/yaml_reader.h"
#include "kernels/names.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>

namespace fs = std::filesystem;

namespace rtsim {

namespace {

fs::path beside(const std::string& file, const std::string& rel) {
  const fs::path p(rel);
  return p.is_absolute() ? p : (fs::path(file).parent_path() / p).lexically_normal();
}

bool one_of(const std::vector<std::string>& v, const std::string& x) {
  return std::find(v.begin(), v.end(), x) != v.end();
}

// A file the study names, beside the study file; it must exist.
std::string existing_file(YamlMap& m, const std::string& key, const std::string& what) {
  const fs::path p = beside(m.file(), m.require<std::string>(key));
  if (!fs::exists(p)) m.fail(key, fmt::format("{} '{}' not found", what, p.string()));
  return p.string();
}

// An integer in [lo, hi] when given, else 0.
int optional_int(YamlMap& m, const std::string& key, int lo, int hi) {
  return m.has(key) ? m.get_in_range<int>(key, lo, lo, hi) : m.get<int>(key, 0);
}

std::vector<std::string> strings(YamlMap& m, const std::string& key) {
  if (!m.has(key)) return m.get<std::vector<std::string>>(key, {});
  m.raw_sequence(key);
  return m.require<std::vector<std::string>>(key);
}

// --set overrides: PATH=VALUE with PATH under hw., scene. or run. (each point checks the value).
std::vector<std::string> overrides(YamlMap& m) {
  std::vector<std::string> set = strings(m, "set");
  for (const std::string& s : set)
    if (s.find('=') == std::string::npos ||
        (s.rfind("hw.", 0) != 0 && s.rfind("scene.", 0) != 0 && s.rfind("run.", 0) != 0))
      m.fail("set",
             fmt::format("'{}': expected hw.PATH=VALUE, scene.PATH=VALUE or run.PATH=VALUE", s));
  return set;
}

void read_animate(YamlMap& m, StudyRun& r) {
  r.file = existing_file(m, "animate", "scene file");
  r.hw = existing_file(m, "hw", "hardware file");
  r.times = m.require<std::string>("times");
  r.width = optional_int(m, "width", 1, 16384);
  r.height = optional_int(m, "height", 1, 16384);
  r.check_every = optional_int(m, "check_every", 1, 100000);
  r.lvb = m.get<std::string>("lvb", "both");
  if (!one_of({"on", "off", "both"}, r.lvb)) m.fail("lvb", "expected on, off or both");
  r.sample = m.get<std::string>("sample", "");
}

StudyRun read_run(YamlMap& m) {
  StudyRun r;
  r.dir = m.get<std::string>("dir", "");
  if (r.dir == "." || r.dir == ".." ||
      r.dir.find_first_not_of(
          "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-") != std::string::npos)
    m.fail("dir", "expected a sub-directory name (letters, digits, '_', '.' or '-')");
  std::vector<std::string> kinds;
  for (const char* k : {"sweep", "reproduce", "animate", "program"})
    if (m.has(k)) kinds.push_back(k);
  if (kinds.size() != 1)
    m.fail(kinds.empty() ? "sweep" : kinds[1],
           "expected one of sweep, reproduce, animate or program in each run");
  r.kind = kinds[0];
  if (r.kind == "sweep") {
    r.file = existing_file(m, "sweep", "sweep file");
    r.plots = m.get<bool>("plots", true);
  } else if (r.kind == "reproduce") {
    r.reproduce = m.require<std::string>("reproduce");
    if (!one_of({"paper", "ablation", kBvhFamily}, r.reproduce))
      m.fail("reproduce", "expected paper, ablation or bvh");
    r.sample = m.get<std::string>("sample", "");
    if (m.has("sweep_file")) r.file = existing_file(m, "sweep_file", "sweep file");
  } else if (r.kind == "animate") {
    read_animate(m, r);
  } else {
    r.program = strings(m, "program");
    if (r.program.empty()) m.fail("program", "expected a program of the build and its arguments");
  }
  if (r.kind == "sweep" || r.kind == "reproduce") {
    r.variants = strings(m, "variants");
    r.set = overrides(m);
  }
  m.finish();
  return r;
}

void read_cache_table(YamlMap& t, report::StudyTable& out) {
  out.key = t.require<std::string>("key");
  out.label = t.require<std::string>("label");
  out.baseline = t.require<std::string>("baseline");
  for (YamlMap& c : t.list_of_maps("columns")) {
    report::StudyColumn col{c.require<std::string>("title"), c.require<std::string>("metric"),
                            c.require<std::string>("format")};
    if (!one_of(report::study_column_formats(), col.format))
      c.fail("format", "expected int (1,234), pct (12.3%) or 1 (12.3)");
    c.finish();
    out.columns.push_back(col);
  }
}

void read_sampled_sweeps(YamlMap& t, report::StudyTable& out) {
  for (YamlMap& s : t.list_of_maps("sweeps")) {
    report::SampledSweep sweep{s.require<std::string>("name"), strings(s, "keys"),
                               s.require<std::string>("label")};
    if (sweep.keys.empty()) s.fail("keys", "expected the columns that tell the points apart");
    s.finish();
    out.sweeps.push_back(sweep);
  }
}

// The run in directory `dir`, which must be of `kind`.
const StudyRun& run_named(YamlMap& m, const std::string& key, const std::string& dir,
                          const std::string& kind, const std::vector<StudyRun>& runs) {
  for (const StudyRun& r : runs)
    if (r.dir == dir && r.kind == kind) return r;
  m.fail(key, fmt::format("'{}': expected the dir of a run with {}", dir, kind));
}

// An integration table's rows, each the figures of a program run.
void read_program_rows(YamlMap& t, const std::vector<StudyRun>& runs, report::StudyTable& out) {
  for (YamlMap& r : t.list_of_maps("rows")) {
    report::ProgramFigure f{r.require<std::string>("run"), r.require<std::string>("figure"),
                            r.require<std::string>("cells"), ""};
    f.by = describe_run(run_named(r, "run", f.run, "program", runs));
    if (!one_of({"cycles", "named_cycles", "platform"}, f.cells))
      r.fail("cells", "expected cycles, named_cycles or platform");
    r.finish();
    out.rows.push_back(f);
  }
}

report::StudyTable read_table(YamlMap& top, const std::vector<StudyRun>& runs) {
  YamlMap t = top.map("table");
  report::StudyTable out;
  out.renderer = t.require<std::string>("renderer");
  if (!one_of(report::study_renderers(), out.renderer)) {
    std::string names;
    for (const std::string& n : report::study_renderers()) names += (names.empty() ? "" : ", ") + n;
    t.fail("renderer", "expected one of " + names);
  }
  if (out.renderer == "cache_table") read_cache_table(t, out);
  if (out.renderer == "copy_markdown") {
    out.file = t.require<std::string>("file");
    out.from = t.require<std::string>("from");
  }
  if (out.renderer == "sampling_table") out.sub = t.get<std::string>("sub", "");
  if (out.renderer == "sampling_sweeps_table") read_sampled_sweeps(t, out);
  if (out.renderer == "animation_table" || out.renderer == "animation_hd_table") {
    out.scenes = strings(t, "scenes");
    for (const std::string& s : out.scenes) run_named(t, "scenes", s, "animate", runs);
    out.label = t.require<std::string>("label");
  }
  if (out.renderer == "animation_hd_table") {
    out.small = t.require<std::string>("small");
    out.small_label = t.require<std::string>("small_label");
  }
  if (out.renderer == "integration_table") read_program_rows(t, runs, out);
  t.finish();
  return out;
}

}  // namespace

std::string studies_dir() { return std::string(RTSIM_CONFIGS_DIR) + "/studies"; }

std::string study_file_of(const std::string& name) {
  if (fs::path(name).extension() == ".yaml" || name.find('/') != std::string::npos) return name;
  return (fs::path(studies_dir()) / (name + ".yaml")).string();
}

std::vector<std::string> study_files() {
  std::vector<std::string> files;
  for (const auto& e : fs::directory_iterator(studies_dir()))
    if (e.path().extension() == ".yaml") files.push_back(e.path().string());
  std::sort(files.begin(), files.end(), [](const std::string& a, const std::string& b) {
    return fs::path(a).stem() < fs::path(b).stem();
  });
  return files;
}

StudySpec load_study(const std::string& path) {
  if (!fs::exists(path))
    throw InputError(fmt::format("{}: no such study file (rtsim study --list)", path));
  YamlMap top = YamlMap::load_file(path);
  StudySpec s;
  s.file = path;
  s.id = top.require<std::string>("id");
  if (s.id != fs::path(path).stem().string())
    top.fail("id", fmt::format("expected '{}', the file's name", fs::path(path).stem().string()));
  s.doc = existing_file(top, "doc", "doc");
  s.minutes = top.get_in_range<double>("minutes", 0.0, 0.0, 1e6);
  s.jobs = optional_int(top, "jobs", 1, 1024);
  for (YamlMap& r : top.list_of_maps("runs")) s.runs.push_back(read_run(r));
  if (s.runs.empty()) top.fail("runs", "expected at least one run");
  for (size_t i = 0; i < s.runs.size(); ++i)
    for (size_t j = 0; j < i; ++j)
      if (s.runs[i].dir == s.runs[j].dir)
        top.fail("runs",
                 fmt::format("runs {} and {} share the directory '{}'", j, i, s.runs[i].dir));
  s.table = read_table(top, s.runs);
  if (top.has("figure")) {
    YamlMap f = top.map("figure");
    s.figure_from = f.require<std::string>("from");
    s.figure_to = beside(path, f.require<std::string>("to")).string();
    f.finish();
  }
  top.finish();
  return s;
}

std::string source_relative(const std::string& path) {
  const fs::path rel = fs::path(path).lexically_relative(RTSIM_DEFAULT_SOURCE_DIR);
  return rel.empty() || rel.string().rfind("..", 0) == 0 ? path : rel.string();
}

namespace {

std::string joined(const std::vector<std::string>& v) {
  std::string s;
  for (const std::string& x : v) s += (s.empty() ? "" : ",") + x;
  return s;
}

}  // namespace

std::string describe_run(const StudyRun& r) {
  std::string s;
  if (r.kind == "program") {
    for (const std::string& a : r.program) s += (s.empty() ? "" : " ") + a;
    return s;
  }
  if (r.kind == "sweep") s = "rtsim sweep " + source_relative(r.file);
  if (r.kind == "reproduce")
    s = "rtsim reproduce" + (r.reproduce == "paper" ? std::string() : " --" + r.reproduce) +
        (r.file.empty() ? std::string() : " --sweep " + source_relative(r.file));
  if (r.kind == "animate")
    s = fmt::format("rtsim animate {} --hw {} --times {}", source_relative(r.file),
                    source_relative(r.hw), r.times);
  if (r.width) s += fmt::format(" --width {}", r.width);
  if (r.height) s += fmt::format(" --height {}", r.height);
  if (r.check_every) s += fmt::format(" --check-every {}", r.check_every);
  if (r.kind == "animate") s += " --lvb " + r.lvb;
  if (!r.variants.empty()) s += " --variants " + joined(r.variants);
  if (!r.sample.empty()) s += " --sample " + r.sample;
  for (const std::string& o : r.set) s += " --set " + o;
  if (r.kind == "sweep" && !r.plots) s += " --no-plots";
  return s;
}

}  // namespace rtsim
