// The study tables of sampled runs against full ones (docs/sampling.md): a reproduction's setups
// (sampling_table) and sweeps' points (sampling_sweeps_table), each sampled run's error and 95%
// interval per seed, the host-time speedup, and a summary line over every row.
#include "reports/study_sampling_tables.h"

#include "common/error.h"
#include "reports/study_files.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <regex>

namespace fs = std::filesystem;
using nlohmann::json;

namespace rtsim::report {

namespace {

json read_json_file(const fs::path& path) {
  const json j = json::parse(read_text_file(path.string()), nullptr, false);
  if (j.is_discarded()) throw InputError(path.string() + ": not JSON");
  return j;
}

// A sweep column's value as the table shows it: a switch (run.lvb) as on or off.
std::string column_value(const json& v) {
  if (v.is_boolean()) return v.get<bool>() ? "on" : "off";
  if (v.is_string()) return v.get<std::string>();
  if (v.is_null()) return "None";  // as the Python renderer wrote it
  return v.dump();
}

// A run's points' reports in point order, keyed by (scene, the values of `keys` joined by ", ");
// a later point of the same key replaces the earlier in its place.
using Keyed = std::vector<std::pair<std::pair<std::string, std::string>, json>>;

const json* find(const Keyed& k, const std::pair<std::string, std::string>& key) {
  for (const auto& [kk, r] : k)
    if (kk == key) return &r;
  return nullptr;
}

Keyed point_reports(const fs::path& dir, const std::vector<std::string>& keys) {
  std::vector<fs::path> points;
  if (!fs::is_directory(dir / "points"))
    throw InputError((dir / "points").string() + ": no such directory (has the study run?)");
  for (const auto& e : fs::directory_iterator(dir / "points")) points.push_back(e.path());
  std::sort(points.begin(), points.end());
  Keyed out;
  for (const fs::path& p : points) {
    if (!fs::exists(p / "report.json")) continue;
    json r = read_json_file(p / "report.json");
    const json row = read_json_file(p / "row.json");
    std::string value;
    for (size_t i = 0; i < keys.size(); ++i)
      value += (i ? ", " : "") + column_value(row.contains(keys[i]) ? row[keys[i]] : json(""));
    const auto key = std::make_pair(r["scene"]["name"].get<std::string>(), value);
    bool replaced = false;
    for (auto& [kk, old] : out)
      if (kk == key) old = r, replaced = true;
    if (!replaced) out.emplace_back(key, std::move(r));
  }
  return out;
}

// Sampled runs against their full ones, row by row.
struct Tally {
  std::vector<double> errors, speedups;
  std::vector<std::string> missed;
  std::map<std::string, int> held{{"total", 0}, {"primary", 0}, {"shadow", 0}};

  // The error of `s`'s cycles_PHASE against the full run's in %, its interval in %, and whether
  // the interval holds the full figure.
  static std::tuple<double, double, bool> cell(const json& full, const json& s,
                                               const std::string& key) {
    const double truth = full[key].get<double>(), est = s[key].get<double>();
    const double ci = s[key + "_ci95"].get<double>();
    return {100 * (est / truth - 1), 100 * ci / truth, std::abs(est - truth) <= ci};
  }

  std::vector<std::string> cells(const std::string& name, const json& full,
                                 const std::vector<std::pair<std::string, const json*>>& runs) {
    std::vector<std::string> out;
    std::vector<double> ups;
    for (const auto& [seed, r] : runs) {
      if (!r) {
        out.push_back("-");
        continue;
      }
      const auto [err, ci, ok] = cell(full, *r, "cycles_total");
      errors.push_back(std::abs(err));
      for (auto& [phase, n] : held) n += std::get<2>(cell(full, *r, "cycles_" + phase));
      if (!ok) missed.push_back(name + ", seed " + seed);
      out.push_back(fmt::format("{:+.2f}% / {:.2f}%", err, ci) + (ok ? "" : " (missed)"));
      ups.push_back(full["host"]["seconds"]["total"].get<double>() /
                    (*r)["host"]["seconds"]["total"].get<double>());
    }
    speedups.insert(speedups.end(), ups.begin(), ups.end());
    out.push_back(ups.empty() ? "-" : fmt::format("{:.1f}x", median(ups, "speedups")));
    return out;
  }

  std::string summary(const std::string& what) const {
    if (errors.empty()) throw InputError("no sampled run has a report (has the study run?)");
    std::string missed_list;
    for (const std::string& m : missed) missed_list += (missed_list.empty() ? "" : "; ") + m;
    const size_t n = errors.size();
    return fmt::format(
        "{} sampled {}: the largest error {:.2f}%, {} of {} within 2%; the 95% interval held the "
        "full run's frame in {} of {}{}, its primary phase in {}, its shadow phase in {}; host "
        "time {:.1f}x less (median; from {:.1f}x to {:.1f}x).",
        n, what, *std::max_element(errors.begin(), errors.end()),
        std::count_if(errors.begin(), errors.end(), [](double e) { return e <= 2; }), n,
        held.at("total"), n, missed.empty() ? "" : " (missed: " + missed_list + ")",
        held.at("primary"), held.at("shadow"), median(speedups, "speedups"),
        *std::min_element(speedups.begin(), speedups.end()),
        *std::max_element(speedups.begin(), speedups.end()));
  }
};

// The sub-directories of `dir` whose names match `pattern`, sorted.
std::vector<std::string> matching(const fs::path& dir, const std::regex& pattern) {
  std::vector<std::string> out;
  for (const auto& e : fs::directory_iterator(dir))
    if (std::regex_match(e.path().filename().string(), pattern))
      out.push_back(e.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

// The variant with culling off that `variant` is compared with: `off`, or `bvh8-off` for
// `bvh8-paper`.
std::string off_variant(const std::string& variant) {
  const size_t dash = variant.rfind('-');
  return (dash == std::string::npos ? "" : variant.substr(0, dash + 1)) + "off";
}

std::vector<std::string> seed_heads(const std::vector<std::string>& seeds, const char* suffix) {
  std::vector<std::string> out;
  for (const std::string& s : seeds) out.push_back("seed " + s.substr(1) + suffix);
  return out;
}

// Culling's reduction per setup, full run and each seed's error in points.
std::vector<std::string> reduction_rows(const Keyed& full, const std::vector<std::string>& seeds,
                                        const std::map<std::string, Keyed>& sampled) {
  std::vector<std::string> head{"setup", "full run"};
  for (const std::string& h : seed_heads(seeds, "")) head.push_back(h);
  std::vector<std::string> out{table_row(head), table_rule(head.size())};
  for (const auto& [key, f] : full) {
    const auto& [scene, variant] = key;
    const json* off = find(full, {scene, off_variant(variant)});
    if (variant == off_variant(variant) || !off) continue;
    const double red =
        100 * (1 - f["cycles_total"].get<double>() / (*off)["cycles_total"].get<double>());
    std::vector<std::string> cells{scene + ", " + variant, fmt::format("{:.2f}%", red)};
    for (const std::string& s : seeds) {
      const json* on_s = find(sampled.at(s), key);
      const json* off_s = find(sampled.at(s), {scene, off_variant(variant)});
      if (!on_s || !off_s) {
        cells.push_back("-");
        continue;
      }
      const double r = 100 * (1 - (*on_s)["cycles_total"].get<double>() /
                                      (*off_s)["cycles_total"].get<double>());
      cells.push_back(fmt::format("{:+.2f} pt", r - red));
    }
    out.push_back(table_row(cells));
  }
  return out;
}

std::vector<std::string> plan_rows(const fs::path& run_dir, const Keyed& full,
                                   const std::vector<std::string>& seeds, const std::string& sub) {
  std::map<std::string, Keyed> sampled;
  for (const std::string& s : seeds) sampled[s] = point_reports(run_dir / s / sub, {"variant"});
  std::vector<std::string> head{"setup", "full run (cycles)"};
  for (const std::string& h : seed_heads(seeds, ": error / interval")) head.push_back(h);
  head.push_back("speedup (median)");
  std::vector<std::string> out{table_row(head), table_rule(head.size())};
  Tally tally;
  for (const auto& [key, f] : full) {
    const std::string name = key.first + ", " + key.second;
    std::vector<std::pair<std::string, const json*>> runs;
    for (const std::string& s : seeds) runs.emplace_back(s.substr(1), find(sampled[s], key));
    std::vector<std::string> cells{name, fmt_int(f["cycles_total"].get<double>())};
    for (const std::string& c : tally.cells(name, f, runs)) cells.push_back(c);
    out.push_back(table_row(cells));
  }
  out.insert(out.end(), {"", tally.summary("frames"), "",
                         "Culling's frame-time reduction (1 - on / off), full run and each "
                         "seed's error in points:",
                         ""});
  for (const std::string& line : reduction_rows(full, seeds, sampled)) out.push_back(line);
  return out;
}

std::string joined_lines(const std::vector<std::string>& lines) {
  std::string s;
  for (size_t i = 0; i < lines.size(); ++i) s += (i ? "\n" : "") + lines[i];
  return s;
}

}  // namespace

// The sampled runs (sK: strata in issue order; nK: Neyman's, the default; K the seed) against
// the full ones (RUN/full), each plan's table with its title.
std::string sampling_table(const StudyTable& t, const std::string& run_dir) {
  const fs::path dir(run_dir);
  const Keyed full = point_reports(dir / "full" / t.sub, {"variant"});
  const std::vector<std::pair<std::string, std::string>> plans{
      {"s", "Strata in issue order (`run.sample_strata: issue`)"},
      {"n", "Neyman's strata on the walk steps (`run.sample_strata: neyman`, the default)"}};
  std::vector<std::string> out;
  for (const auto& [prefix, title] : plans) {
    const std::vector<std::string> seeds = matching(dir, std::regex(prefix + "\\d+"));
    if (seeds.empty()) continue;
    if (!out.empty()) out.push_back("");
    out.insert(out.end(), {title + ":", ""});
    for (const std::string& line : plan_rows(dir, full, seeds, t.sub)) out.push_back(line);
  }
  return joined_lines(out) + "\n";
}

// Each sampled sweep point against the full one (directories full-NAME and sK-NAME).
std::string sampling_sweeps_table(const StudyTable& t, const std::string& run_dir) {
  const fs::path dir(run_dir);
  std::vector<std::string> seeds;
  for (const std::string& d : matching(dir, std::regex("s\\d+-.+"))) {
    const std::string seed = d.substr(0, d.find('-'));
    if (std::find(seeds.begin(), seeds.end(), seed) == seeds.end()) seeds.push_back(seed);
  }
  std::sort(seeds.begin(), seeds.end());
  std::vector<std::string> head{"sweep", "scene", "point", "full run (cycles)"};
  for (const std::string& h : seed_heads(seeds, ": error / interval")) head.push_back(h);
  head.push_back("speedup");
  std::vector<std::string> out{table_row(head), table_rule(head.size())};
  Tally tally;
  for (const SampledSweep& sw : t.sweeps) {
    const Keyed full = point_reports(dir / ("full-" + sw.name), sw.keys);
    std::map<std::string, Keyed> sampled;
    for (const std::string& s : seeds)
      sampled[s] = point_reports(dir / (s + "-" + sw.name), sw.keys);
    for (const auto& [key, f] : full) {
      std::vector<std::pair<std::string, const json*>> runs;
      for (const std::string& s : seeds) runs.emplace_back(s.substr(1), find(sampled[s], key));
      std::vector<std::string> cells{sw.name, key.first, sw.label + " " + key.second,
                                     fmt_int(f["cycles_total"].get<double>())};
      const std::string name = sw.name + ", " + key.first + ", " + key.second;
      for (const std::string& c : tally.cells(name, f, runs)) cells.push_back(c);
      out.push_back(table_row(cells));
    }
  }
  out.insert(out.end(), {"", tally.summary("points")});
  return joined_lines(out) + "\n";
}

}  // namespace rtsim::report
