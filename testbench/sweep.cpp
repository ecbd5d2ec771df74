#include "testbench/sweep.h"

#include "common/yaml_reader.h"
#include "reports/output_files.h"
#include "reports/plots.h"
#include "reports/run_report.h"
#include "testbench/commands.h"
#include "testbench/run_config.h"

#include <fmt/format.h>

#include <cerrno>
#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <cmath>
#include <csignal>
#include <fcntl.h>
#include <filesystem>
#include <fstream>
#include <limits>
#include <map>
#include <sys/prctl.h>
#include <sys/wait.h>
#include <unistd.h>

namespace fs = std::filesystem;

namespace rtsim {

namespace {

constexpr const char* kManifestSchema = "rtsim-sweep-manifest/1";
constexpr const char* kResultsSchema = "rtsim-sweep/1";
constexpr size_t kMaxPoints = 100000;
constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

const std::vector<std::string> kDefaultMetrics = {
    "cycles_total",     "cycles_shadow",   "frame_ms_all",     "frame_ms_shadow",     "shadow_culled_rate",
    "trv_l1_hit_rate",  "trv_l2_hit_rate", "list_l1_hit_rate", "ist_l1_hit_rate",     "ist_l2_hit_rate",
    "trv_busy",         "dram_row_hit_rate", "dram_bandwidth_gbps"};

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
    m.fail(section_key, fmt::format("'{}': expected a key path starting with 'hw.', 'scene.' or 'run.'", path));
}

// A map of dotted key paths to values -> "--set" strings, in file order. With `hw` given (a
// variant), the key `hw` names a hardware file instead (the value as written).
std::vector<std::pair<std::string, std::string>> read_overrides(YamlMap& parent, const std::string& key,
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

// FNV-1a over a file's bytes: the manifest remembers what the inputs were.
std::string file_digest(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  uint64_t h = 1469598103934665603ull;
  char buf[65536];
  while (in.read(buf, sizeof buf) || in.gcount() > 0) {
    for (std::streamsize i = 0; i < in.gcount(); ++i) h = (h ^ uint8_t(buf[i])) * 1099511628211ull;
  }
  return fmt::format("{:016x}", h);
}

std::string point_dir(const std::string& dir, const SweepPoint& p) { return (fs::path(dir) / "points" / p.id).string(); }

// A point is finished when its row is written (the last thing its run does).
fs::path row_file(const std::string& dir, const SweepPoint& p) { return fs::path(point_dir(dir, p)) / "row.json"; }
bool point_done(const std::string& dir, const SweepPoint& p) { return fs::exists(row_file(dir, p)); }

nlohmann::json read_json(const std::string& path) {
  std::ifstream in(path);
  if (!in) throw InputError(path + ": cannot read");
  try {
    return nlohmann::json::parse(in);
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: not valid JSON: {}", path, e.what()));
  }
}

SweepSpec spec_from_manifest(const nlohmann::json& m, const std::string& path) {
  if (!m.is_object() || m.value("schema", "") != kManifestSchema)
    throw InputError(fmt::format("{}: expected a manifest with schema {}", path, kManifestSchema));
  try {
    SweepSpec s;
    s.file = m.at("sweep_file").get<std::string>();
    s.name = m.at("name").get<std::string>();
    s.hw_file = m.at("hw_file").get<std::string>();
    s.scenes = m.at("scenes").get<std::vector<std::string>>();
    s.columns = m.at("columns").get<std::vector<std::string>>();
    s.metrics = m.at("metrics").get<std::vector<std::string>>();
    for (const auto& p : m.at("points")) {
      SweepPoint q;
      q.index = p.at("index").get<uint32_t>();
      q.id = p.at("id").get<std::string>();
      q.scene_file = p.at("scene_file").get<std::string>();
      q.hw_file = p.value("hw_file", std::string());
      q.values = p.at("values");
      q.set = p.at("set").get<std::vector<std::string>>();
      s.points.push_back(std::move(q));
    }
    return s;
  } catch (const nlohmann::json::exception& e) {
    throw InputError(fmt::format("{}: malformed manifest: {}", path, e.what()));
  }
}

double metric_value(const std::string& name, const nlohmann::json& r) {
  auto share = [&](const std::string& p) {
    const double b = json_number(r, p + ".busy_cycles"), s = json_number(r, p + ".stalled_cycles"),
                 i = json_number(r, p + ".idle_cycles");
    return b + s + i > 0 ? b / (b + s + i) : kNaN;
  };
  auto sum = [&](const char* list, const char* field) {
    double n = 0;
    if (!r.contains(list) || !r[list].is_array()) return kNaN;
    for (const auto& e : r[list]) n += e.value(field, 0.0);
    return n;
  };
  if (name == "frame_ms_all") return json_number(r, "frame_ms.all");
  if (name == "frame_ms_shadow") return json_number(r, "frame_ms.shadow");
  if (name == "rays_primary") return json_number(r, "rays.primary");
  if (name == "rays_shadow") return json_number(r, "rays.shadow");
  if (name == "shadow_culled") return sum("per_light", "culled");
  if (name == "shadow_culled_rate") {
    const double all = sum("per_light", "shadow_rays");
    return all > 0 ? sum("per_light", "culled") / all : kNaN;
  }
  if (name == "leaves_culled_rate") {
    if (!r.contains("lvb") || r["lvb"].is_null()) return kNaN;
    double c = 0, n = 0;
    for (const auto& e : r["lvb"]["per_light"]) {
      c += e.value("culled_leaves", 0.0);
      n += e.value("nonempty_leaves", 0.0);
    }
    return n > 0 ? c / n : kNaN;
  }
  if (name == "dram_row_hit_rate") return json_number(r, "stats.dram.row_hit_rate");
  if (name == "dram_bandwidth_gbps") return json_number(r, "stats.dram.bandwidth_gbps");
  if (name == "dram_reads") return json_number(r, "stats.dram.reads");
  for (const char* type : {"trv", "list", "ist", "shading"}) {
    for (const char* level : {"l1", "l2"})
      if (name == fmt::format("{}_{}_hit_rate", type, level)) return json_number(r, fmt::format("stats.{}.{}.hit_rate", type, level));
    if (name == fmt::format("{}_busy", type))
      return share(std::string("stats.") + type + ".total");
  }
  return json_number(r, name);  // any numeric field of report.json by its dotted path
}

bool is_metric(const std::string& name) {
  static const std::vector<std::string> named = [] {
    std::vector<std::string> v{"frame_ms_all", "frame_ms_shadow", "rays_primary", "rays_shadow", "shadow_culled",
                               "shadow_culled_rate", "leaves_culled_rate", "dram_row_hit_rate", "dram_bandwidth_gbps",
                               "dram_reads"};
    for (const char* type : {"trv", "list", "ist", "shading"}) {
      v.push_back(fmt::format("{}_busy", type));
      for (const char* level : {"l1", "l2"}) v.push_back(fmt::format("{}_{}_hit_rate", type, level));
    }
    return v;
  }();
  if (std::find(named.begin(), named.end(), name) != named.end()) return true;
  const std::string head = name.substr(0, name.find('.'));
  for (const char* key : {"cycles_total", "cycles_primary", "cycles_shadow", "clock_ghz"})
    if (name == key) return true;
  for (const char* key : {"frame_ms", "rays", "per_light", "lvb", "kdtree", "scene", "stats"})
    if (head == key && name.size() > head.size() + 1) return true;
  return false;
}

}  // namespace

SweepSpec load_sweep(const std::string& path, const std::vector<std::string>& extra_set) {
  YamlMap top = YamlMap::load_file(path);
  SweepSpec s;
  s.file = path;
  s.name = top.get<std::string>("name", fs::path(path).stem().string());
  if (s.name.empty() || s.name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-") != std::string::npos)
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
  if (!fs::exists(s.hw_file)) top.fail("hw", fmt::format("hardware file '{}' not found", s.hw_file));

  // Points skip their figures unless the sweep asks for them (the sweep draws its own).
  std::vector<std::string> base{"run.plots=false"};
  if (top.has("set"))
    for (const auto& [k, v] : read_overrides(top, "set")) base.push_back(k + "=" + v);
  for (const std::string& e : extra_set) base.push_back(e);

  struct Variant {
    std::string name, hw_file;  // hw_file: the variant's own hardware file, or empty
    std::vector<std::string> set;
  };
  std::vector<Variant> variants;
  if (top.has("variants")) {
    YamlMap v = top.map("variants");
    for (const std::string& name : v.keys()) {
      Variant var{name, "", {}};
      std::string hw;
      for (const auto& [k, val] : read_overrides(v, name, &hw)) var.set.push_back(k + "=" + val);
      if (!hw.empty()) {
        var.hw_file = beside(path, hw).string();
        if (!fs::exists(var.hw_file)) v.fail(name, fmt::format("hardware file '{}' not found", var.hw_file));
      }
      variants.push_back(std::move(var));
    }
    if (variants.empty()) top.fail("variants", "expected at least one variant");
    s.columns.push_back("variant");
  }
  std::vector<std::pair<std::string, std::vector<YAML::Node>>> axes;
  if (top.has("axes")) {
    YamlMap a = top.map("axes");
    for (const std::string& key : a.keys()) {
      check_key_path(a, key, key);
      const YAML::Node values = a.raw_sequence(key);
      if (values.size() == 0) a.fail(key, "expected at least one value");
      std::vector<YAML::Node> list(values.begin(), values.end());
      axes.emplace_back(key, list);
      s.columns.push_back(key);
    }
  }
  if (top.has("metrics")) {
    s.metrics = top.get<std::vector<std::string>>("metrics", {});
    if (s.metrics.empty()) top.fail("metrics", "expected at least one metric");
    for (const std::string& m : s.metrics)
      if (!is_metric(m))
        top.fail("metrics", fmt::format("'{}': expected a metric name (configs/README.md) or a dotted path into "
                                        "report.json (cycles_*, frame_ms.*, rays.*, per_light.*, lvb.*, kdtree.*, "
                                        "scene.*, stats.*)", m));
  } else {
    s.metrics = kDefaultMetrics;
  }
  top.finish();

  // The cross product, last axis fastest.
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
  // Every point's hardware and run settings are checked now, before anything runs.
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
  return s;
}

nlohmann::json sweep_manifest(const SweepSpec& s) {
  nlohmann::json points = nlohmann::json::array();
  nlohmann::json inputs = {{s.hw_file, file_digest(s.hw_file)}};
  for (const SweepPoint& p : s.points) {
    nlohmann::json q = {{"index", p.index}, {"id", p.id}, {"scene_file", p.scene_file}, {"values", p.values}, {"set", p.set}};
    if (!p.hw_file.empty()) {  // only then: manifests of sweeps without one are unchanged
      q["hw_file"] = p.hw_file;
      inputs[p.hw_file] = file_digest(p.hw_file);
    }
    points.push_back(q);
  }
  for (const std::string& scene : s.scenes) inputs[scene] = file_digest(scene);
  return {{"schema", kManifestSchema}, {"sweep_file", s.file}, {"name", s.name},     {"hw_file", s.hw_file},
          {"scenes", s.scenes},        {"columns", s.columns},  {"metrics", s.metrics}, {"points", points},
          {"inputs", inputs}};
}

nlohmann::json sweep_row(const SweepSpec& s, const SweepPoint& p, const nlohmann::json& report) {
  nlohmann::json row = {{"point", p.index}, {"id", p.id}, {"scene", report["scene"]["name"]}};
  for (const std::string& c : s.columns) row[c] = p.values[c];
  for (const std::string& m : s.metrics) {
    const double v = metric_value(m, report);
    if (std::isnan(v)) row[m] = nullptr;
    else if (v == std::floor(v) && std::fabs(v) < 9e15) row[m] = int64_t(v);  // counts stay integers
    else row[m] = v;
  }
  return row;
}

size_t write_sweep_results(const SweepSpec& s, const std::string& dir) {
  nlohmann::json rows = nlohmann::json::array();
  std::vector<std::string> header{"point", "id", "scene"};
  header.insert(header.end(), s.columns.begin(), s.columns.end());
  header.insert(header.end(), s.metrics.begin(), s.metrics.end());
  std::string csv;
  for (size_t i = 0; i < header.size(); ++i) csv += (i ? "," : "") + header[i];
  csv += "\n";
  for (const SweepPoint& p : s.points) {
    if (!point_done(dir, p)) continue;
    const nlohmann::json row = read_json(row_file(dir, p).string());
    rows.push_back(row);
    for (size_t i = 0; i < header.size(); ++i) {
      const nlohmann::json& v = row.contains(header[i]) ? row[header[i]] : nlohmann::json(nullptr);
      std::string cell = v.is_string() ? v.get<std::string>() : v.is_null() ? "" : v.dump();
      if (cell.find_first_of(",\"\n") != std::string::npos) {
        std::string quoted = "\"";
        for (char c : cell) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
        cell = quoted + "\"";
      }
      csv += (i ? "," : "") + cell;
    }
    csv += "\n";
  }
  write_file_atomic((fs::path(dir) / "results.csv").string(), csv);
  write_json((fs::path(dir) / "results.json").string(),
             {{"schema", kResultsSchema}, {"name", s.name}, {"axes", s.columns}, {"metrics", s.metrics},
              {"points", s.points.size()}, {"rows", rows}});
  return rows.size();
}

namespace {

// Runs one point in this process and writes its row.
int run_point(const SweepSpec& s, const std::string& dir, const SweepPoint& p) {
  const fs::path out = point_dir(dir, p);
  if (point_done(dir, p)) {
    fmt::print("{}: already done\n", p.id);
    return 0;
  }
  RunArgs args;
  args.sources.scene_file = p.scene_file;
  args.sources.hw_file = s.hw_of(p);
  args.sources.set = p.set;
  args.out = out.string();
  args.quiet = true;
  const int code = run_model(args);
  if (code != 0) return code;
  write_json(row_file(dir, p).string(), sweep_row(s, p, read_json((out / "report.json").string())));
  return 0;
}

const SweepPoint& point_by_index(const SweepSpec& s, int index, const std::string& where) {
  if (index < 0 || size_t(index) >= s.points.size())
    throw InputError(fmt::format("{}: --point {}: expected 0..{}", where, index, s.points.size() - 1));
  return s.points[size_t(index)];
}

// The manifest in DIR must describe the same points (a resume), or be absent (a new sweep).
void claim_directory(const SweepSpec& s, const std::string& dir) {
  const fs::path file = fs::path(dir) / "manifest.json";
  nlohmann::json mine = sweep_manifest(s);
  if (fs::exists(file)) {
    nlohmann::json theirs = read_json(file.string());
    // Everything but where the sweep file lives: the points, the metrics and the inputs' contents.
    if (theirs.is_object()) theirs.erase("sweep_file");
    mine.erase("sweep_file");
    if (theirs != mine)
      throw InputError(fmt::format("{}: holds the manifest of another sweep (its points, metrics or input files "
                                   "differ); use another --out",
                                   file.string()));
    return;
  }
  write_json(file.string(), mine);
}

// Starts `rtsim sweep --out DIR --point I` as a child whose output goes to the point's log; the
// child dies with this process.
pid_t spawn_point(const std::string& dir, const SweepPoint& p) {
  const fs::path out = point_dir(dir, p);
  fs::create_directories(out);
  const std::string log = (out / "log.txt").string();
  const std::string index = std::to_string(p.index);
  const pid_t parent = getpid();
  const pid_t pid = fork();
  if (pid < 0) throw std::runtime_error("fork failed");
  if (pid == 0) {
    prctl(PR_SET_PDEATHSIG, SIGTERM);
    if (getppid() != parent) _exit(127);
    const int fd = open(log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    if (fd >= 0) {
      dup2(fd, 1);
      dup2(fd, 2);
      close(fd);
    }
    // The running binary itself, even if the file was rebuilt or removed meanwhile.
    execl("/proc/self/exe", "rtsim", "sweep", "--out", dir.c_str(), "--point", index.c_str(), (char*)nullptr);
    _exit(127);
  }
  return pid;
}

std::string describe(const SweepPoint& p) {
  std::string s = fs::path(p.scene_file).stem().string();
  for (const auto& [k, v] : p.values.items()) s += ", " + k + "=" + (v.is_string() ? v.get<std::string>() : v.dump());
  return s;
}

}  // namespace

std::string sweep_point_dir(const std::string& dir, const SweepPoint& p) { return point_dir(dir, p); }

int run_sweep_points(const SweepSpec& s, const std::string& dir, int jobs, bool plots) {
  claim_directory(s, dir);
  std::vector<const SweepPoint*> missing;
  for (const SweepPoint& p : s.points)
    if (!point_done(dir, p)) missing.push_back(&p);
  fmt::print("sweep {}: {} points, {} already done, running {} with {} job{}\n", s.name, s.points.size(),
             s.points.size() - missing.size(), missing.size(), jobs, jobs == 1 ? "" : "s");
  std::fflush(stdout);
  std::map<pid_t, std::pair<const SweepPoint*, std::chrono::steady_clock::time_point>> running;
  size_t next = 0, finished = 0, failed = 0;
  auto last_write = std::chrono::steady_clock::now();
  while (next < missing.size() || !running.empty()) {
    while (next < missing.size() && running.size() < size_t(jobs)) {
      const SweepPoint* p = missing[next++];
      running[spawn_point(dir, *p)] = {p, std::chrono::steady_clock::now()};
    }
    int status = 0;
    const pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0) break;
    const auto it = running.find(pid);
    if (it == running.end()) continue;
    const auto [p, started] = it->second;
    running.erase(it);
    ++finished;
    const double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
    if (point_done(dir, *p)) {
      fmt::print("[{}/{}] {} done in {:.1f} s ({})\n", finished, missing.size(), p->id, secs, describe(*p));
    } else {
      ++failed;
      const std::string why = WIFSIGNALED(status) ? fmt::format("killed by signal {}", WTERMSIG(status))
                                                  : fmt::format("exit code {}", WEXITSTATUS(status));
      fmt::print("[{}/{}] {} FAILED ({}; {}): see {}/log.txt\n", finished, missing.size(), p->id, why, describe(*p),
                 point_dir(dir, *p));
    }
    std::fflush(stdout);
    // Keep results current while points finish, but do not reread every row after each point.
    if (std::chrono::steady_clock::now() - last_write > std::chrono::seconds(2)) {
      write_sweep_results(s, dir);
      last_write = std::chrono::steady_clock::now();
    }
  }
  const size_t rows = write_sweep_results(s, dir);
  std::string note;
  if (plots) note = make_plots("sweep", dir);
  fmt::print("sweep {}: {} of {} points in {}/results.csv{}\n", s.name, rows, s.points.size(), dir,
             plots && note.empty() ? ", figures in plots/" : "");
  if (!note.empty()) fmt::print(stderr, "rtsim: warning: figures not written: {}\n", note);
  return failed || rows != s.points.size() ? 1 : 0;
}

namespace {

int emit_slurm(const SweepSpec& s, const std::string& dir) {
  claim_directory(s, dir);
  const fs::path abs_dir = fs::absolute(dir).lexically_normal();
  const std::string self = fs::read_symlink("/proc/self/exe").string();
  // #SBATCH lines cannot quote: keep the paths plain.
  for (const std::string& p : {abs_dir.string(), self, fs::current_path().string()})
    if (p.find_first_of(" \t\n'\"$`\\") != std::string::npos)
      throw InputError(fmt::format("--emit slurm: the path '{}' has a space, quote or shell character; use a plain path", p));
  const std::string script = fmt::format(
      "#!/bin/bash\n"
      "# rtsim sweep '{name}' as a Slurm job array: one task per point of {dir}/manifest.json.\n"
      "# Submit with: sbatch {dir}/sweep.sbatch    Then gather: rtsim sweep --merge {dir}\n"
      "#SBATCH --job-name=rtsim-{name}\n"
      "#SBATCH --array=0-{last}\n"
      "#SBATCH --cpus-per-task=1\n"
      "#SBATCH --output={dir}/points/slurm-%A_%a.out\n"
      "set -euo pipefail\n"
      "RTSIM=\"${{RTSIM:-{self}}}\"\n"
      "# Scene and hardware paths in the manifest are relative to where the sweep was emitted.\n"
      "cd '{cwd}'\n"
      "exec \"$RTSIM\" sweep --out '{dir}' --point \"$SLURM_ARRAY_TASK_ID\"\n",
      fmt::arg("name", s.name), fmt::arg("dir", abs_dir.string()), fmt::arg("last", s.points.size() - 1),
      fmt::arg("self", self), fmt::arg("cwd", fs::current_path().string()));
  fs::create_directories(abs_dir / "points");
  write_file_atomic((abs_dir / "sweep.sbatch").string(), script);
  fmt::print("wrote {0}/sweep.sbatch ({1} array tasks) and {0}/manifest.json\nsubmit: sbatch {0}/sweep.sbatch; then: "
             "rtsim sweep --merge {0}\n",
             abs_dir.string(), s.points.size());
  return 0;
}

}  // namespace

int run_sweep_command(const SweepArgs& a) {
  if (!a.merge_dir.empty()) {
    const std::string file = (fs::path(a.merge_dir) / "manifest.json").string();
    const SweepSpec s = spec_from_manifest(read_json(file), file);
    const size_t rows = write_sweep_results(s, a.merge_dir);
    std::string missing;
    for (const SweepPoint& p : s.points)
      if (!point_done(a.merge_dir, p)) missing += " " + p.id;
    if (a.plots) {
      const std::string note = make_plots("sweep", a.merge_dir);
      if (!note.empty()) fmt::print(stderr, "rtsim: warning: figures not written: {}\n", note);
    }
    fmt::print("merged {} of {} points into {}/results.csv\n", rows, s.points.size(), a.merge_dir);
    if (!missing.empty()) fmt::print(stderr, "missing points:{}\n", missing);
    return missing.empty() ? 0 : 1;
  }
  if (a.out.empty()) throw InputError("--out DIR is required");
  if (a.point >= 0) {
    if (!a.file.empty() || !a.set.empty()) throw InputError("--point runs a point of DIR/manifest.json: give only --out");
    const std::string file = (fs::path(a.out) / "manifest.json").string();
    if (!fs::exists(file)) throw InputError(file + ": file not found (emit or start the sweep first)");
    const nlohmann::json manifest = read_json(file);
    const SweepSpec s = spec_from_manifest(manifest, file);
    const nlohmann::json inputs = manifest.value("inputs", nlohmann::json::object());
    for (const auto& [input, digest] : inputs.items())
      if (file_digest(input) != digest.get<std::string>())
        throw InputError(fmt::format("{}: changed since the sweep in {} began (its points would mix inputs)", input, a.out));
    return run_point(s, a.out, point_by_index(s, a.point, file));
  }
  if (a.file.empty()) throw InputError("expected a sweep file (or --merge DIR, or --out DIR --point I)");
  const SweepSpec s = load_sweep(a.file, a.set);
  if (a.emit == "slurm") return emit_slurm(s, a.out);
  return run_sweep_points(s, a.out, a.jobs, a.plots);
}

}  // namespace rtsim
