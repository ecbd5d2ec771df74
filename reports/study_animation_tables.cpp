// An animation's frames (frames.csv, host.csv of `rtsim animate`) as the docs' tables: the medians
// over a scene's frames (animation_table) and a row per frame (animation_hd_table).
#include "reports/study_animation_tables.h"

#include "common/error.h"
#include "reports/study_files.h"

#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <limits>
#include <map>

namespace fs = std::filesystem;

namespace rtsim::report {

namespace {

// A frame's figures by column (an empty cell is absent), host.csv's joined by time, and what the
// tables derive: saved = cycles_off - cycles_on; tests = the LVB's region and pair tests; lazy =
// a lazy rebuild's dirty, region and pair tests (when the frame has them).
struct Frame {
  std::map<std::string, double> v;
  std::string file;

  bool has(const std::string& k) const { return v.count(k) != 0; }
  double at(const std::string& k) const {
    const auto it = v.find(k);
    if (it == v.end()) throw InputError(fmt::format("{}: a frame has no '{}'", file, k));
    return it->second;
  }
};

std::map<std::string, double> numbers(const CsvRow& row, const std::string& file) {
  std::map<std::string, double> out;
  for (const auto& [k, text] : row)
    if (!text.empty()) out[k] = cell_number(row, k, file);
  return out;
}

std::vector<Frame> animation_frames(const fs::path& dir) {
  const std::string host_file = (dir / "host.csv").string();
  std::map<double, std::map<std::string, double>> host;
  for (const CsvRow& r : read_csv_file(host_file)) {
    std::map<std::string, double> h = numbers(r, host_file);
    host[Frame{h, host_file}.at("time")] = h;
  }
  const std::string file = (dir / "frames.csv").string();
  std::vector<Frame> frames;
  for (const CsvRow& r : read_csv_file(file)) {
    Frame f{numbers(r, file), file};
    const auto h = host.find(f.at("time"));
    if (h != host.end())
      for (const auto& [k, x] : h->second)
        if (k != "time") f.v[k] = x;
    f.v["saved"] = f.at("cycles_off") - f.at("cycles_on");
    f.v["tests"] = f.at("lvb_region_tests") + f.at("lvb_pair_tests");
    if (f.has("lazy_region_tests"))
      f.v["lazy"] = f.at("lazy_dirty_tests") + f.at("lazy_region_tests") + f.at("lazy_pair_tests");
    frames.push_back(std::move(f));
  }
  return frames;
}

// The frames' `k` where they have it.
std::vector<double> col(const std::vector<Frame>& frames, const std::string& k) {
  std::vector<double> out;
  for (const Frame& f : frames)
    if (f.has(k)) out.push_back(f.at(k));
  return out;
}

// f(frame) of every frame that passes `keep`.
std::vector<double> each(const std::vector<Frame>& frames,
                         const std::function<double(const Frame&)>& f,
                         const std::function<bool(const Frame&)>& keep = nullptr) {
  std::vector<double> out;
  for (const Frame& r : frames)
    if (!keep || keep(r)) out.push_back(f(r));
  return out;
}

double min_of(const std::vector<double>& v, const std::string& what) {
  if (v.empty()) throw InputError(what + ": no value");
  return *std::min_element(v.begin(), v.end());
}

double max_of(const std::vector<double>& v, const std::string& what) {
  if (v.empty()) throw InputError(what + ": no value");
  return *std::max_element(v.begin(), v.end());
}

double ratio(double a, double b) {
  return b != 0 ? a / b : std::numeric_limits<double>::infinity();
}

std::string millions(double v) { return fmt::format("{:.2f} M", v / 1e6); }

// "MEDIAN (MIN-MAX)" with each number as `f` writes it.
std::string spread(const std::vector<double>& v, const std::string& what, const char* f,
                   const char* unit = "") {
  return fmt::format(fmt::runtime(std::string(f) + "{} (" + f + "-" + f + "{})"), median(v, what),
                     unit, min_of(v, what), max_of(v, what), unit);
}

// The lazy rebuild's cells: its dirty pairs, its tests and its tests per saved cycle.
std::vector<std::string> lazy_cells(const std::vector<Frame>& fr, const std::string& file) {
  const std::vector<Frame> lazy = [&] {
    std::vector<Frame> out;
    for (const Frame& r : fr)
      if (r.has("lazy")) out.push_back(r);
    return out;
  }();
  if (lazy.empty()) return {"-", "-", "-"};
  const double saved = median(col(fr, "saved"), file + ": saved");
  const double mlazy = median(col(lazy, "lazy"), file + ": lazy");
  const std::vector<double> dirty = each(
      lazy, [](const Frame& r) { return 100 * r.at("lazy_dirty_pairs") / r.at("lazy_pairs"); },
      [](const Frame& r) { return r.has("lazy_pairs") && r.at("lazy_pairs") != 0; });
  const std::vector<double> per_saved =
      each(lazy, [](const Frame& r) { return ratio(r.at("lazy"), r.at("saved")); });
  return {spread(dirty, file + ": lazy_dirty_pairs", "{:.1f}", "%"),
          fmt::format("{} ({:.0f}% of full; {} of it finding the dirty pairs)", millions(mlazy),
                      100 * mlazy / median(col(fr, "tests"), file + ": tests"),
                      millions(median(col(lazy, "lazy_dirty_tests"), file + ": lazy_dirty_tests"))),
          saved != 0 ? fmt::format("{:.1f} ({:.1f}-{:.1f})", mlazy / saved, min_of(per_saved, file),
                                   max_of(per_saved, file))
                     : "no saving"};
}

// One scene's column of the 480x270 table.
std::vector<std::string> scene_cells(const std::vector<Frame>& fr, const std::string& file) {
  const std::vector<double> saved = col(fr, "saved"), off = col(fr, "cycles_off");
  const std::vector<double> tests = col(fr, "tests");
  const std::vector<double> pct =
      each(fr, [](const Frame& r) { return 100 * r.at("saved") / r.at("cycles_off"); });
  const std::vector<double> per_saved =
      each(fr, [](const Frame& r) { return ratio(r.at("tests"), r.at("saved")); });
  std::vector<double> share = col(fr, "culled_share");
  for (double& x : share) x = 100 * x;
  const std::vector<double> checked = col(fr, "check_mismatched_pixels");
  const double msaved = median(saved, file + ": saved");
  std::string work;
  for (const char* k : {"lvb_nodes_visited", "lvb_region_tests", "lvb_pair_tests"})
    work += (work.empty() ? "" : " / ") + millions(median(col(fr, k), file + ": " + k));
  double checked_sum = 0;
  for (double x : checked) checked_sum += x;
  std::vector<std::string> out{
      fmt::format("{} ({:.2f}-{:.2f} M)", fmt_int(median(off, file + ": cycles_off")),
                  min_of(off, file) / 1e6, max_of(off, file) / 1e6),
      fmt::format("{} ({}-{}), {}", fmt_int(msaved), fmt_int(min_of(saved, file)),
                  fmt_int(max_of(saved, file)), spread(pct, file + ": saved", "{:.1f}", "%")),
      spread(share, file + ": culled_share", "{:.1f}", "%"),
      work,
      msaved != 0 ? fmt::format("{:.1f} ({:.1f}-{:.1f})", median(tests, file) / msaved,
                                min_of(per_saved, file), max_of(per_saved, file))
                  : "no saving",
      fmt::format("{:.2f} / {:.2f}", median(col(fr, "kdtree_seconds"), file + ": kdtree_seconds"),
                  median(col(fr, "lvb_seconds"), file + ": lvb_seconds"))};
  for (const std::string& c : lazy_cells(fr, file)) out.push_back(c);
  out.push_back(fmt::format("{} in {} frames x 2 runs", fmt_int(checked_sum), checked.size()));
  return out;
}

}  // namespace

std::string animation_table(const StudyTable& t, const std::string& run_dir) {
  static const char* const labels[] = {"cycles, culling off",
                                       "cycles culling saves",
                                       "shadow rays culled",
                                       "LVB work: nodes visited / region tests / pair tests",
                                       "LVB tests (region + pair) per saved cycle",
                                       "host seconds: kd-tree / LVB (1 thread)",
                                       "lazy: dirty pairs",
                                       "lazy: tests (dirty + region + pair)",
                                       "lazy tests per saved cycle",
                                       "`--check-every 5`: pixels differing from the reference"};
  std::vector<std::vector<std::string>> columns;
  for (const std::string& s : t.scenes) {
    const fs::path dir = fs::path(run_dir) / s;
    columns.push_back(scene_cells(animation_frames(dir), (dir / "frames.csv").string()));
  }
  std::vector<std::string> head{t.label};
  head.insert(head.end(), t.scenes.begin(), t.scenes.end());
  std::string out = table_row(head) + "\n" + table_rule(head.size());
  for (size_t i = 0; i < std::size(labels); ++i) {
    std::vector<std::string> cells{labels[i]};
    for (const std::vector<std::string>& c : columns) cells.push_back(c[i]);
    out += "\n" + table_row(cells);
  }
  return out;
}

std::string animation_hd_table(const StudyTable& t, const std::string& run_dir) {
  const fs::path small_dir = fs::path(run_dir).parent_path() / t.small;
  std::string out =
      table_row({"frame", "cycles off / on at " + t.label, "saved",
                 "saved, x of " + t.small_label + "'s", "LVB tests per saved cycle"}) +
      "\n" + table_rule(5);
  for (const std::string& s : t.scenes) {
    std::map<double, double> small;  // the smaller study's saving by time
    if (fs::exists(small_dir / s / "frames.csv"))
      for (const Frame& r : animation_frames(small_dir / s)) small[r.at("time")] = r.at("saved");
    for (const Frame& r : animation_frames(fs::path(run_dir) / s)) {
      const double saved = r.at("saved"), off = r.at("cycles_off");
      const auto x = small.find(r.at("time"));
      out +=
          "\n" +
          fmt::format(
              "| {} t = {:g} | {} / {} | {} ({:.1f}%) | {} | {} |", s, r.at("time"), fmt_int(off),
              fmt_int(r.at("cycles_on")), fmt_int(saved), 100 * saved / off,
              x != small.end() && x->second != 0 ? fmt::format("{:.1f}", saved / x->second) : "-",
              saved > 0 ? fmt::format("{:.1f}", r.at("tests") / saved) : "no saving");
    }
  }
  return out;
}

}  // namespace rtsim::report
