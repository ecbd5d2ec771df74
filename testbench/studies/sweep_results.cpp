#include "testbench/studies/sweep_results.h"

#include "common/error.h"
#include "common/utf8.h"
#include "reports/area_report.h"
#include "reports/output_files.h"
#include "reports/plots.h"
#include "reports/sweep_index.h"
#include "testbench/studies/sweep_metrics.h"

#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace rtsim {

namespace {

constexpr const char* kManifestSchema = "rtsim-sweep-manifest/1";
constexpr const char* kResultsSchema = "rtsim-sweep/1";

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

// plots/index.md, the list of the figures plots.py drew (reports/sweep_index.h); empty on
// success, else why not.
std::string write_plots_index(const std::string& dir) {
  try {
    const nlohmann::json results = read_json((fs::path(dir) / output::kResultsJson).string());
    write_file_atomic((fs::path(dir) / output::kPlotsDir / output::kPlotsIndexMd).string(),
                      report::sweep_plots_index(results));
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

}  // namespace

std::string draw_sweep_figures(const SweepSpec& s, const std::string& dir) {
  std::string note = make_plots("sweep", dir);
  if (note.empty()) note = write_plots_index(dir);
  for (const std::string& r : s.reports)
    if (note.empty()) note = make_plots(r, dir);
  return note;
}

std::string write_sweep_reports(const SweepSpec& s, const std::string& dir) {
  for (const std::string& r : s.reports) {
    if (r != "area") continue;
    try {
      const nlohmann::json res = read_json((fs::path(dir) / output::kResultsJson).string());
      std::vector<report::AreaPoint> points;
      for (const nlohmann::json& row : res.at("rows")) {
        const fs::path report =
            fs::path(dir) / output::kPointsDir / row.value("id", "") / output::kReportJson;
        points.push_back({row, fs::exists(report) ? read_json(report.string()) : nlohmann::json()});
      }
      write_file_atomic((fs::path(dir) / output::kAreaLightsMd).string(),
                        report::area_lights_markdown(s.name, points));
    } catch (const InputError& e) {
      return fmt::format("{}: {}", output::kAreaLightsMd, e.what());
    } catch (const nlohmann::json::exception& e) {
      return fmt::format("{}: malformed input: {}", output::kAreaLightsMd, e.what());
    }
  }
  return "";
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
    s.reports = m.value("reports", std::vector<std::string>());
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

std::string sweep_manifest_file(const std::string& dir) {
  return (fs::path(dir) / output::kManifestJson).string();
}

nlohmann::json sweep_manifest(const SweepSpec& s) {
  nlohmann::json points = nlohmann::json::array();
  nlohmann::json inputs = {{s.hw_file, file_digest(s.hw_file)}};
  for (const SweepPoint& p : s.points) {
    nlohmann::json q = {{"index", p.index},
                        {"id", p.id},
                        {"scene_file", p.scene_file},
                        {"values", p.values},
                        {"set", p.set}};
    if (!p.hw_file.empty()) {  // only then: manifests of sweeps without one are unchanged
      q["hw_file"] = p.hw_file;
      inputs[p.hw_file] = file_digest(p.hw_file);
    }
    points.push_back(q);
  }
  for (const std::string& scene : s.scenes) inputs[scene] = file_digest(scene);
  nlohmann::json m = {{"schema", kManifestSchema}, {"sweep_file", s.file}, {"name", s.name},
                      {"hw_file", s.hw_file},      {"scenes", s.scenes},   {"columns", s.columns},
                      {"metrics", s.metrics},      {"points", points},     {"inputs", inputs}};
  if (!s.reports.empty()) m["reports"] = s.reports;
  return m;
}

void claim_sweep_directory(const SweepSpec& s, const std::string& dir) {
  const std::string file = sweep_manifest_file(dir);
  nlohmann::json mine = sweep_manifest(s);
  if (fs::exists(file)) {
    nlohmann::json theirs = read_json(file);
    // Everything but where the sweep file lives and which reports it draws: the points, the
    // metrics and the inputs' contents.
    for (nlohmann::json* j : {&theirs, &mine})
      if (j->is_object()) {
        j->erase("sweep_file");
        j->erase("reports");
      }
    if (theirs != mine)
      throw InputError(
          fmt::format("{}: holds the manifest of another sweep (its points, metrics or input files "
                      "differ); use another --out",
                      file));
    return;
  }
  write_json(file, mine);
}

void check_sweep_inputs(const nlohmann::json& manifest, const std::string& dir) {
  const nlohmann::json inputs = manifest.value("inputs", nlohmann::json::object());
  for (const auto& [input, digest] : inputs.items())
    if (file_digest(input) != digest.get<std::string>())
      throw InputError(fmt::format(
          "{}: changed since the sweep in {} began (its points would mix inputs)", input, dir));
}

std::string sweep_point_dir(const std::string& dir, const SweepPoint& p) {
  return (fs::path(dir) / output::kPointsDir / p.id).string();
}

// A point is finished when its row is written (the last thing its run does).
std::string sweep_row_file(const std::string& dir, const SweepPoint& p) {
  return (fs::path(sweep_point_dir(dir, p)) / output::kRowJson).string();
}
std::string sweep_row_problem(const std::string& dir, const SweepPoint& p) {
  const std::string file = sweep_row_file(dir, p);
  if (!fs::exists(file)) return "no row";
  try {
    const nlohmann::json row = read_json(file);
    if (!row.is_object() || row.value("id", "") != p.id) return file + ": not this point's row";
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// A point is done when its row is there and reads as its row: a damaged one is run again.
bool sweep_point_done(const std::string& dir, const SweepPoint& p) {
  return sweep_row_problem(dir, p).empty();
}

namespace {

// A metric's value in a row: null when the report has none; counts stay integers.
nlohmann::json row_value(double v) {
  if (std::isnan(v)) return nullptr;
  if (v == std::floor(v) && std::fabs(v) < 9e15) return int64_t(v);
  return v;
}

bool is_listed(const std::vector<std::string>& names, const std::string& name) {
  return std::find(names.begin(), names.end(), name) != names.end();
}

// The sampled points' columns the sweep file did not list as metrics (kSampledSweepColumns, and
// `sampled` first); none when no row in `rows` was sampled, so a sweep of full runs keeps its
// results as they were.
std::vector<std::string> sampled_columns(const SweepSpec& s, const nlohmann::json& rows) {
  const bool any = std::any_of(rows.begin(), rows.end(), [](const nlohmann::json& r) {
    return r.is_object() && r.value("sampled", false) == true;
  });
  if (!any) return {};
  std::vector<std::string> cols{"sampled"};
  for (const std::string& c : kSampledSweepColumns)
    if (!is_listed(s.metrics, c)) cols.push_back(c);
  return cols;
}

}  // namespace

// A sampled point's row also carries each estimate's interval and the fraction, listed or not:
// a sampled figure never goes without its interval (docs/sampling.md).
nlohmann::json sweep_row(const SweepSpec& s, const SweepPoint& p, const nlohmann::json& report) {
  nlohmann::json row = {{"point", p.index}, {"id", p.id}, {"scene", report["scene"]["name"]}};
  for (const std::string& c : s.columns) row[c] = p.values[c];
  for (const std::string& m : s.metrics) row[m] = row_value(sweep_metric(m, report));
  if (report.value("sampled", false) == true) {
    row["sampled"] = true;
    for (const std::string& c : kSampledSweepColumns)
      if (!row.contains(c)) row[c] = row_value(sweep_metric(c, report));
  }
  return row;
}

std::string sweep_failure_file(const std::string& dir, const SweepPoint& p) {
  return (fs::path(sweep_point_dir(dir, p)) / "failure.json").string();
}

namespace {

// One CSV cell of a JSON value, quoted when it holds a comma, a quote or a line break.
std::string csv_cell(const nlohmann::json& v) {
  std::string cell = v.is_string() ? v.get<std::string>() : v.is_null() ? "" : v.dump();
  if (cell.find_first_of(",\"\n") == std::string::npos) return cell;
  std::string quoted = "\"";
  for (char c : cell) quoted += c == '"' ? std::string("\"\"") : std::string(1, c);
  return quoted + "\"";
}

// The reason, and the log's last line when there is one (rtsim's error names the cause).
std::string failure_cell(const nlohmann::json& f) {
  std::string cell = f.value("reason", "failed");
  std::string tail = f.contains("log_tail") && f["log_tail"].is_string() ? f["log_tail"] : "";
  while (!tail.empty() && (tail.back() == '\n' || tail.back() == '\r')) tail.pop_back();
  if (const size_t nl = tail.rfind('\n'); nl != std::string::npos) tail.erase(0, nl + 1);
  return tail.empty() ? cell : cell + ": " + tail;
}

}  // namespace

// A failed point is a row too, its metrics empty and the `failure` column holding the reason, so
// a reader of results.csv sees what is missing and why (a rerun of the command retries it).
size_t write_sweep_results(const SweepSpec& s, const std::string& dir) {
  nlohmann::json rows = nlohmann::json::array(), failed = nlohmann::json::array();
  // Each point's row, or null for a point without a usable one.
  std::vector<nlohmann::json> read(s.points.size());
  for (size_t k = 0; k < s.points.size(); ++k)
    if (sweep_row_problem(dir, s.points[k]).empty())
      read[k] = read_json(sweep_row_file(dir, s.points[k]));
  const std::vector<std::string> sampled = sampled_columns(s, nlohmann::json(read));
  std::vector<std::string> header{"point", "id", "scene"};
  header.insert(header.end(), s.columns.begin(), s.columns.end());
  header.insert(header.end(), s.metrics.begin(), s.metrics.end());
  header.insert(header.end(), sampled.begin(), sampled.end());
  header.push_back("failure");
  std::string csv;
  for (size_t i = 0; i < header.size(); ++i) csv += (i ? "," : "") + header[i];
  csv += "\n";
  for (size_t k = 0; k < s.points.size(); ++k) {
    const SweepPoint& p = s.points[k];
    nlohmann::json row;
    if (read[k].is_null()) {
      const std::string problem = sweep_row_problem(dir, p);
      if (fs::exists(sweep_failure_file(dir, p)))
        failed.push_back(read_json(sweep_failure_file(dir, p)));
      else if (problem != "no row")
        failed.push_back(
            {{"point", p.id}, {"reason", utf8_lossy("an unreadable row: " + problem)}});
      else
        continue;  // not run yet
      const nlohmann::json& f = failed.back();
      row = {{"point", p.index}, {"id", p.id}, {"failure", failure_cell(f)}};
      for (const std::string& c : s.columns) row[c] = p.values[c];
    } else {
      row = read[k];
      rows.push_back(row);
    }
    for (size_t i = 0; i < header.size(); ++i)
      csv += (i ? "," : "") + csv_cell(row.contains(header[i]) ? row[header[i]] : nullptr);
    csv += "\n";
  }
  write_file_atomic((fs::path(dir) / output::kResultsCsv).string(), csv);
  nlohmann::json results = {
      {"schema", kResultsSchema},  {"name", s.name}, {"axes", s.columns}, {"metrics", s.metrics},
      {"points", s.points.size()}, {"rows", rows},   {"failed", failed}};
  if (!sampled.empty()) results["sampled_columns"] = sampled;  // only then: full runs' unchanged
  write_json((fs::path(dir) / output::kResultsJson).string(), results);
  return rows.size();
}

}  // namespace rtsim
