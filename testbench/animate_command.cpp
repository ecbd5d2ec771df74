// rtsim animate: a BART scene as a frame sequence. Each frame is one point of a sweep (the sweep
// engine runs frames in parallel processes, resumes, emits Slurm scripts): the scene loaded at time
// t, the kd-tree, memory image and LVB (hierarchical) rebuilt, the frame simulated with culling on,
// off, or both. The per-frame table (frames.csv) then pairs the on and off runs of each time and adds
// what the rebuild cost: host seconds of the kd-tree and the LVB (host.csv keeps host figures apart,
// so frames.csv is deterministic) and the LVB's work counts.
#include "common/error.h"
#include "reports/output_files.h"
#include "testbench/commands.h"
#include "testbench/sweep.h"
#include "testbench/sweep_results.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>

namespace rtsim {

namespace fs = std::filesystem;

std::vector<double> parse_times(const std::string& text) {
  double a = 0, b = 0, step = 0;
  char tail = 0;
  if (std::sscanf(text.c_str(), "%lf:%lf:%lf%c", &a, &b, &step, &tail) != 3 || !std::isfinite(a) ||
      !std::isfinite(b) || !std::isfinite(step))
    throw InputError(fmt::format("--times {}: expected START:END:STEP", text));
  if (!(step > 0) || b < a)
    throw InputError(fmt::format("--times {}: expected START <= END and STEP > 0 (an increasing, non-empty range)", text));
  const long n = long(std::floor((b - a) / step + 1e-9)) + 1;
  if (n > 100000) throw InputError(fmt::format("--times {}: {} frames, expected at most 100000", text, n));
  std::vector<double> times;
  for (long k = 0; k < n; ++k) times.push_back(a + double(k) * step);
  return times;
}

namespace {

const std::vector<std::string> kFrameMetrics = {"scene.triangles", "cycles_total", "frame_ms_all", "shadow_culled",
                                                "shadow_culled_rate", "leaves_culled_rate"};

// The sweep the frames are: one scene, one hardware file, the times (and culling) as axes.
std::string sweep_yaml(const AnimateArgs& a, const std::vector<double>& times) {
  std::string y = "# Written by rtsim animate: the frames of " + a.scene + "\nname: animate\n";
  y += fmt::format("scenes: [\"{}\"]\nhw: \"{}\"\n", fs::absolute(a.scene).string(), fs::absolute(a.hw).string());
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

nlohmann::json read_report(const std::string& dir) {
  std::ifstream in(fs::path(dir) / "report.json");
  return nlohmann::json::parse(in);
}

// frames.csv and host.csv, one row per time, from the points' reports.
void write_frame_tables(const std::string& out, const SweepSpec& spec) {
  struct Frame {
    nlohmann::json on, off;
    std::string image;  // the culling-on point's render.png when there is one
  };
  std::map<double, Frame> frames;
  for (const SweepPoint& p : spec.points) {
    const double t = p.values["scene.time"].get<double>();
    const nlohmann::json& lvb = p.values["run.lvb"];
    const bool on = lvb.is_boolean() ? lvb.get<bool>() : lvb == "on";
    (on ? frames[t].on : frames[t].off) = read_report(sweep_point_dir(out, p));
    if (on || frames[t].image.empty()) frames[t].image = (fs::path(sweep_point_dir(out, p)) / "render.png").string();
  }
  auto number = [](const nlohmann::json& r, const nlohmann::json::json_pointer& at) -> std::string {
    return r.is_null() || !r.contains(at) ? "" : fmt::format("{}", r.at(at).get<double>());
  };
  using ptr = nlohmann::json::json_pointer;
  std::string csv = "time,triangles,cycles_off,cycles_on,frame_ms_off,frame_ms_on,shadow_rays_culled,"
                    "lvb_region_tests,lvb_pair_tests\n";
  std::string host = "time,kdtree_seconds,lvb_seconds,simulate_seconds_off,simulate_seconds_on\n";
  for (const auto& [t, f] : frames) {
    const nlohmann::json& any = f.on.is_null() ? f.off : f.on;
    uint64_t culled = 0;
    if (!f.on.is_null())
      for (const auto& l : f.on["per_light"]) culled += l["culled"].get<uint64_t>();
    csv += fmt::format("{:.9g},{},{},{},{},{},{},{},{}\n", t, number(any, ptr("/scene/triangles")),
                       number(f.off, ptr("/cycles_total")), number(f.on, ptr("/cycles_total")),
                       number(f.off, ptr("/frame_ms/all")), number(f.on, ptr("/frame_ms/all")),
                       f.on.is_null() ? "" : std::to_string(culled), number(f.on, ptr("/lvb/region_tests")),
                       number(f.on, ptr("/lvb/pair_tests")));
    host += fmt::format("{:.9g},{},{},{},{}\n", t, number(any, ptr("/host/seconds/kdtree")),
                        number(f.on, ptr("/host/seconds/lvb")), number(f.off, ptr("/host/seconds/simulate")),
                        number(f.on, ptr("/host/seconds/simulate")));
  }
  // frames/frame_NNNN.png in time order: the sequence as images.
  fs::create_directories(fs::path(out) / "frames");
  int k = 0;
  for (const auto& [t, f] : frames)
    fs::copy_file(f.image, fs::path(out) / "frames" / fmt::format("frame_{:04d}.png", k++),
                  fs::copy_options::overwrite_existing);
  write_file_atomic((fs::path(out) / "frames.csv").string(), csv);
  write_file_atomic((fs::path(out) / "host.csv").string(), host);
}

}  // namespace

int run_animate(const AnimateArgs& a) {
  const std::vector<double> times = parse_times(a.times);
  if (!fs::exists(a.scene)) throw InputError(a.scene + ": file not found");
  if (!fs::exists(a.hw)) throw InputError(a.hw + ": file not found");
  fs::create_directories(a.out);
  const std::string file = (fs::path(a.out) / "animate.yaml").string();
  write_file_atomic(file, sweep_yaml(a, times));
  SweepArgs s;
  s.file = file;
  s.out = a.out;
  s.jobs = a.jobs;
  s.emit = a.emit;
  s.plots = false;
  const int code = run_sweep_command(s);
  if (code != 0 || !a.emit.empty()) return code;
  write_frame_tables(a.out, load_sweep(file));
  fmt::print("{} frames: {}/frames.csv (cycles, culled rays, LVB work per frame), host.csv (host seconds)\n",
             times.size(), a.out);
  return 0;
}

}  // namespace rtsim
