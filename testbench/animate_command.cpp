// rtsim animate: a BART scene as a frame sequence. Each frame is one point of a sweep (the sweep
// engine runs frames in parallel processes, resumes, emits Slurm scripts): the scene loaded at time
// t, the kd-tree, memory image and LVB (hierarchical) rebuilt, the frame simulated with culling on,
// off, or both. The per-frame table (frames.csv) then pairs the on and off runs of each time and
// adds what the rebuild cost: host seconds of the kd-tree and the LVB (host.csv keeps host figures
// apart, so frames.csv is deterministic), the LVB's work counts and what a lazy rebuild after the
// previous frame would redo; plots.py adds the figures, frames.gif and summary.md.
// docs/animation.md.
#include "common/error.h"
#include "reports/output_files.h"
#include "reports/plots.h"
#include "testbench/commands.h"
#include "testbench/slurm.h"
#include "testbench/sweep.h"
#include "testbench/sweep_results.h"

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
  if (a.width > 0 || a.height > 0) {
    y += "set: {";
    if (a.width > 0) y += fmt::format("run.width: {}", a.width);
    if (a.width > 0 && a.height > 0) y += ", ";
    if (a.height > 0) y += fmt::format("run.height: {}", a.height);
    y += "}\n";
  }
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

// frames.csv and host.csv, one row per time, from the points' reports.
void write_frame_tables(const std::string& out, const SweepSpec& spec) {
  struct Frame {
    nlohmann::json on, off;
    std::string image;  // the culling-on point's render.png when there is one
  };
  std::map<double, Frame> frames;
  size_t lights = 0;
  for (const SweepPoint& p : spec.points) {
    const double t = p.values["scene.time"].get<double>();
    const bool on = culling_on(p);
    const fs::path dir = sweep_point_dir(out, p);
    nlohmann::json& report = on ? frames[t].on : frames[t].off;
    report = read_json((dir / output::kReportJson).string());
    lights = std::max(lights, report["per_light"].size());
    if (on || frames[t].image.empty()) frames[t].image = (dir / output::kRenderPng).string();
  }
  using ptr = nlohmann::json::json_pointer;
  auto number = [](const nlohmann::json& r, const ptr& at) -> std::string {
    return r.is_null() || !r.contains(at) || r.at(at).is_null()
               ? ""
               : fmt::format("{}", r.at(at).get<double>());
  };
  std::string csv =
      "time,triangles,cycles_off,cycles_on,frame_ms_off,frame_ms_on,saved_ms,shadow_rays,shadow_"
      "rays_culled,culled_share,nonempty_leaves";
  for (size_t l = 0; l < lights; ++l) csv += fmt::format(",culled_leaves_l{}", l);
  for (size_t l = 0; l < lights; ++l) csv += fmt::format(",culled_rays_l{}", l);
  csv +=
      ",lvb_nodes_visited,lvb_region_tests,lvb_pair_tests,moved_triangles,lazy_dirty_pairs,lazy_"
      "pairs,lazy_dirty_tests,lazy_nodes_visited,lazy_region_tests,lazy_pair_tests,check_"
      "mismatched_pixels\n";
  std::string host = "time,kdtree_seconds,lvb_seconds,simulate_seconds_off,simulate_seconds_on\n";
  for (const auto& [t, f] : frames) {
    const nlohmann::json& any = f.on.is_null() ? f.off : f.on;
    std::string saved, rays, culled, share, nonempty, leaves, rays_l;
    if (!f.on.is_null()) {
      uint64_t all = 0, cut = 0;
      for (const auto& l : f.on["per_light"]) {
        all += l["shadow_rays"].get<uint64_t>();
        cut += l["culled"].get<uint64_t>();
        rays_l += fmt::format(",{}", l["culled"].get<uint64_t>());
      }
      rays = std::to_string(all);
      culled = std::to_string(cut);
      share = all ? fmt::format("{:.6f}", double(cut) / double(all)) : "";
      const nlohmann::json& lvb_lights = f.on["lvb"]["per_light"];
      if (!lvb_lights.empty())
        nonempty = std::to_string(lvb_lights[0]["nonempty_leaves"].get<uint64_t>());
      for (const auto& l : lvb_lights)
        leaves += fmt::format(",{}", l["culled_leaves"].get<uint64_t>());
    }
    if (!f.on.is_null() && !f.off.is_null())
      saved = fmt::format(
          "{:.6f}", f.off["frame_ms"]["all"].get<double>() - f.on["frame_ms"]["all"].get<double>());
    // Columns for lights this frame lacks (or a run it lacks) stay empty.
    auto pad = [&](std::string cells) {
      while (size_t(std::count(cells.begin(), cells.end(), ',')) < lights) cells += ",";
      return cells;
    };
    // A frame checked in both runs counts the mismatches of both.
    std::optional<uint64_t> mismatched;
    for (const nlohmann::json* r : {&f.off, &f.on})
      if (!r->is_null() && r->contains("reference_check") && !(*r)["reference_check"].is_null())
        mismatched =
            mismatched.value_or(0) + (*r)["reference_check"]["mismatched_pixels"].get<uint64_t>();
    csv += fmt::format("{:.9g},{},{},{},{},{},{},{},{},{},{}{}{}", t,
                       number(any, ptr("/scene/triangles")), number(f.off, ptr("/cycles_total")),
                       number(f.on, ptr("/cycles_total")), number(f.off, ptr("/frame_ms/all")),
                       number(f.on, ptr("/frame_ms/all")), saved, rays, culled, share, nonempty,
                       pad(leaves), pad(rays_l));
    for (const char* key :
         {"/lvb/nodes_visited", "/lvb/region_tests", "/lvb/pair_tests", "/lvb/lazy/moved_triangles",
          "/lvb/lazy/dirty_pairs", "/lvb/lazy/pairs", "/lvb/lazy/dirty_tests",
          "/lvb/lazy/nodes_visited", "/lvb/lazy/region_tests", "/lvb/lazy/pair_tests"})
      csv += "," + number(f.on, ptr(key));
    csv += "," + (mismatched ? std::to_string(*mismatched) : std::string()) + "\n";
    host += fmt::format("{:.9g},{},{},{},{}\n", t, number(any, ptr("/host/seconds/kdtree")),
                        number(f.on, ptr("/host/seconds/lvb")),
                        number(f.off, ptr("/host/seconds/simulate")),
                        number(f.on, ptr("/host/seconds/simulate")));
  }
  // frames/frame_NNNN.png in time order: the sequence as images.
  fs::create_directories(fs::path(out) / "frames");
  int k = 0;
  for (const auto& [t, f] : frames)
    fs::copy_file(f.image, fs::path(out) / "frames" / fmt::format("frame_{:04d}.png", k++),
                  fs::copy_options::overwrite_existing);
  write_file_atomic((fs::path(out) / output::kFramesCsv).string(), csv);
  write_file_atomic((fs::path(out) / output::kHostCsv).string(), host);
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
      "seconds)\n",
      times.size(), a.out);
  const std::string note = make_plots("animate", a.out);
  if (note.empty())
    fmt::print("figures in {}/plots/, the frames as {}/frames.gif\n", a.out, a.out);
  else
    fmt::print(stderr, "rtsim: warning: figures not written: {}\n", note);
  return 0;
}

}  // namespace rtsim
