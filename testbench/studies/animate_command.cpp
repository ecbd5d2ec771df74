// rtsim animate: a BART scene as a frame sequence. Each frame is one point of a sweep (the sweep
// engine runs frames in parallel processes, resumes, emits Slurm scripts): the scene loaded at time
// t, the kd-tree, memory image and LVB (hierarchical) rebuilt, the frame simulated with culling on,
// off, or both. The per-frame table (frames.csv) then pairs the on and off runs of each time and
// adds what the rebuild cost: host seconds of the kd-tree and the LVB (host.csv keeps host figures
// apart, so frames.csv is deterministic), the LVB's work counts and what a lazy rebuild after the
// previous frame would redo; summary.md sets the cycles culling saves against what the rebuild
// costs; plots.py adds the figures and frames.gif.
// docs/animation.md.
#include "common/error.h"
#include "reports/animation_tables.h"
#include "reports/output_files.h"
#include "reports/plots.h"
#include "testbench/studies/slurm.h"
#include "testbench/studies/study_commands.h"
#include "testbench/studies/sweep.h"
#include "testbench/studies/sweep_results.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <map>
#include <optional>

namespace rtsim {

namespace fs = std::filesystem;

std::vector<double> parse_times(const std::string& text) {
  double a = 0, b = 0, step = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%lf:%lf:%lf%c", &a, &b, &step, &tail) != 3 || !std::isfinite(a) ||
      !std::isfinite(b) || !std::isfinite(step))
    throw InputError(fmt::format("--times {}: expected START:END:STEP", text));
  if (!(step > 0) || b < a)
    throw InputError(fmt::format(
        "--times {}: expected START <= END and STEP > 0 (an increasing, non-empty range)", text));
  const long n = long(std::floor((b - a) / step + 1e-9)) + 1;
  if (n > 100000)
    throw InputError(fmt::format("--times {}: {} frames, expected at most 100000", text, n));
  std::vector<double> times;
  for (long k = 0; k < n; ++k) times.push_back(a + double(k) * step);
  return times;
}

namespace {

const std::vector<std::string> kFrameMetrics = {"scene.triangles",    "cycles_total",
                                                "frame_ms_all",       "shadow_culled",
                                                "shadow_culled_rate", "leaves_culled_rate"};

// The sweep the frames are: one scene, one hardware file, the times (and culling) as axes.
std::string sweep_yaml(const AnimateArgs& a, const std::vector<double>& times) {
  std::string y = "# Written by rtsim animate: the frames of " + a.scene + "\nname: animate\n";
  y += fmt::format("scenes: [\"{}\"]\nhw: \"{}\"\n", fs::absolute(a.scene).string(),
                   fs::absolute(a.hw).string());
  std::vector<std::string> set;
  if (a.width > 0) set.push_back(fmt::format("run.width: {}", a.width));
  if (a.height > 0) set.push_back(fmt::format("run.height: {}", a.height));
  if (!a.accel.empty()) set.push_back(fmt::format("run.accel: {}", a.accel));
  if (!a.sample.empty()) set.push_back("run.sample: " + checked_sample_option(a.sample));
  if (!set.empty()) y += fmt::format("set: {{{}}}\n", fmt::join(set, ", "));
  y += "axes:\n  scene.time: [";
  for (size_t i = 0; i < times.size(); ++i) y += fmt::format("{}{:.9g}", i ? ", " : "", times[i]);
  y += "]\n";
  y += a.lvb == "both" ? "  run.lvb: [off, on]\n" : fmt::format("  run.lvb: [{}]\n", a.lvb);
  y += fmt::format("metrics: [{}]\n", fmt::join(kFrameMetrics, ", "));
  return y;
}

// The run.lvb axis holds on/off (YAML may read them as booleans).
bool culling_on(const SweepPoint& p) {
  const nlohmann::json& lvb = p.values["run.lvb"];
  return lvb.is_boolean() ? lvb.get<bool>() : lvb == "on";
}

// frames.csv, host.csv and summary.md (reports/animation_tables.h), one row per time, from the
// points' reports; frames/frame_NNNN.png, the culling-on runs' images in time order.
void write_frame_tables(const std::string& out, const SweepSpec& spec) {
  std::map<double, report::AnimationFrame> frames;
  std::map<double, std::string> images;  // the culling-on point's render.png when there is one
  for (const SweepPoint& p : spec.points) {
    const double t = p.values["scene.time"].get<double>();
    const bool on = culling_on(p);
    const fs::path dir = sweep_point_dir(out, p);
    (on ? frames[t].on : frames[t].off) = read_json((dir / output::kReportJson).string());
    if (on || images[t].empty()) images[t] = (dir / output::kRenderPng).string();
  }
  fs::create_directories(fs::path(out) / "frames");
  int k = 0;
  for (const auto& [t, image] : images)
    fs::copy_file(image, fs::path(out) / "frames" / fmt::format("frame_{:04d}.png", k++),
                  fs::copy_options::overwrite_existing);
  write_file_atomic((fs::path(out) / output::kFramesCsv).string(), report::frames_csv(frames));
  write_file_atomic((fs::path(out) / output::kHostCsv).string(), report::host_csv(frames));
  write_file_atomic((fs::path(out) / output::kSummaryMd).string(),
                    report::animation_summary(frames));
}

}  // namespace

int run_animate(const AnimateArgs& a) {
  const std::vector<double> times = parse_times(a.times);
  if (!fs::exists(a.scene)) throw InputError(a.scene + ": file not found");
  if (!fs::exists(a.hw)) throw InputError(a.hw + ": file not found");
  fs::create_directories(a.out);
  const std::string file = (fs::path(a.out) / "animate.yaml").string();
  write_file_atomic(file, sweep_yaml(a, times));
  SweepSpec spec = load_sweep(file);
  // Per-point settings (so the manifest, and a resumed run, knows them): the reference check on
  // every K-th frame, both runs of it; with culling, what a lazy rebuild after the previous frame
  // would redo.
  for (SweepPoint& p : spec.points) {
    const double t = p.values["scene.time"].get<double>();
    // The file holds the times to 9 digits: the frame is the nearest of ours (they increase).
    size_t k = size_t(std::lower_bound(times.begin(), times.end(), t) - times.begin());
    if (k == times.size() || (k > 0 && t - times[k - 1] <= times[k] - t)) --k;
    if (a.check_every > 0 && k % size_t(a.check_every) == 0) p.set.push_back("run.check=true");
    if (culling_on(p) && k > 0)
      p.set.push_back(fmt::format("run.lvb_lazy_since={:.9g}", times[k - 1]));
  }
  if (a.emit == "slurm") {
    const int code = emit_slurm(spec, a.out);
    if (code == 0)
      fmt::print(
          "after the job, this command again (without --emit) writes frames.csv and the figures\n");
    return code;
  }
  const int code = run_sweep_points(spec, a.out, a.jobs, false);
  if (code != 0) return code;
  write_frame_tables(a.out, spec);
  fmt::print(
      "{} frames: {}/frames.csv (cycles, culled rays, LVB work per frame), host.csv (host "
      "seconds), summary.md\n",
      times.size(), a.out);
  const std::string note = make_plots("animate", a.out);
  if (note.empty())
    fmt::print("figures in {}/plots/, the frames as {}/frames.gif\n", a.out, a.out);
  else
    fmt::print(stderr, "rtsim: warning: figures not written: {}\n", note);
  return 0;
}

}  // namespace rtsim
