#include "testbench/run/resources.h"

#include "common/error.h"
#include "kernels/lvb.h"
#include "kernels/reference_tracer.h"
#include "model/units/frame_buffer.h"

#include <sys/resource.h>

#include <fmt/format.h>

#include <algorithm>
#include <cstdlib>
#include <fstream>
#include <sstream>

namespace rtsim {

namespace {

std::string g_activity;  // Activity::current()

std::string gb(uint64_t bytes) { return fmt::format("{:.1f} GB", double(bytes) / 1e9); }

// A "Key:   123 kB" line of a /proc file, in bytes; 0 if absent.
uint64_t proc_kb(const char* file, const std::string& key) {
  std::ifstream in(file);
  for (std::string line; std::getline(in, line);)
    if (line.rfind(key + ":", 0) == 0) return std::stoull(line.substr(key.size() + 1)) * 1024;
  return 0;
}

// The first line of a cgroup file as a number; ~0 for "max" or a missing file.
uint64_t cgroup_value(const std::string& file) {
  std::ifstream in(file);
  std::string v;
  if (!(in >> v) || v == "max") return ~uint64_t(0);
  try {
    return std::stoull(v);
  } catch (const std::exception&) {
    return ~uint64_t(0);
  }
}

// The process's cgroup v2 directory ("" if none is known).
std::string cgroup_dir() {
  std::ifstream in("/proc/self/cgroup");
  for (std::string line; std::getline(in, line);)
    if (line.rfind("0::", 0) == 0) return "/sys/fs/cgroup" + line.substr(3);
  return "";
}

void tighter(MemoryRoom& room, uint64_t limit, uint64_t used, const std::string& name) {
  const uint64_t left = limit > used ? limit - used : 0;
  if (left < room.bytes)
    room = {left, used ? fmt::format("{} ({} of {} in use)", name, gb(used), gb(limit)) : name};
}

size_t sample_words(const Scene& scene) {
  uint32_t bits = 0;
  for (const Light& l : scene.lights)
    if (l.samples > 1) bits += l.samples;
  return (bits + 63) / 64;
}

uint64_t sum(const std::vector<std::pair<std::string, uint64_t>>& parts) {
  uint64_t n = 0;
  for (const auto& part : parts) n += part.second;
  return n;
}

}  // namespace

uint64_t MemoryNeed::total() const { return std::max(sum(transient), sum(parts)); }

uint64_t MemoryNeed::peak() const { return std::max(sum(held) + total(), peak_so_far); }

uint64_t resident_bytes() { return proc_kb("/proc/self/status", "VmRSS"); }

void add_scene_memory(const PreparedScene& p, bool lvb, bool exact_lvb, uint64_t program_bytes,
                      MemoryNeed& need) {
  const auto bytes = [](const auto& v) { return uint64_t(v.capacity()) * sizeof(v[0]); };
  const bool bvh = is_bvh(p.accel);
  const uint64_t triangles = bytes(p.scene.triangles);
  const uint64_t structure = bvh ? bytes(p.bvh.nodes) + bytes(p.bvh.leaves) + bytes(p.bvh.prims)
                                 : bytes(p.tree.nodes) + bytes(p.tree.leaves) + bytes(p.tree.prims);
  const uint64_t image = p.image ? bytes(p.image->bytes()) : 0;
  need.held.push_back({"the triangles", triangles});
  need.held.push_back({"the acceleration structure", structure});
  need.held.push_back({"the memory image", image});
  need.held.push_back({"the program and its libraries", program_bytes});
  need.peak_so_far = proc_kb("/proc/self/status", "VmHWM");
  if (!lvb) return;
  const size_t leaves = bvh ? p.bvh.leaves.size() : p.tree.leaves.size();
  const size_t refs = bvh ? p.bvh.prims.size() : p.tree.prims.size();
  need.transient.push_back({"the light visibility bits' computation",
                            lvb_working_bytes(p.scene.triangles.size(), leaves, refs, exact_lvb)});
}

MemoryNeed run_memory_need(const model::AcceleratorConfig& hw, const Scene& scene, bool check) {
  const uint64_t pixels = uint64_t(scene.width) * uint64_t(scene.height);
  const uint64_t entries = pixels * uint64_t(hw.entries_per_pixel());
  const uint64_t stride = std::max<uint64_t>(64, hw.memory_dram().request_bytes);
  const uint64_t entry_bytes = sizeof(model::PixelState) + 8 * sample_words(scene);
  MemoryNeed n;
  n.what = fmt::format("a {}x{} frame", scene.width, scene.height);
  // The model's frame buffer, and its copy in the result.
  n.parts.push_back({"the frame's per-pixel state", 2 * entries * entry_bytes});
  n.parts.push_back({"the hit records in simulated memory", entries * stride});
  n.parts.push_back({"the pixel order", 3 * 4 * pixels});
  n.parts.push_back({"the image and report planes", pixels * (3 + 4 + 2 * scene.lights.size())});
  if (check) n.parts.push_back({"the reference check", pixels * (sizeof(PixelRecord) + 3)});
  if (hw.integrator == Integrator::kPath)  // radiance, the model's and the reference's
    n.parts.push_back({"the radiance planes", pixels * 3 * sizeof(float) * (check ? 2 : 1)});
  return n;
}

MemoryNeed render_memory_need(const Scene& scene) {
  const uint64_t pixels = uint64_t(scene.width) * uint64_t(scene.height);
  MemoryNeed n;
  n.what = fmt::format("a {}x{} frame", scene.width, scene.height);
  n.parts.push_back({"the traced pixels", pixels * sizeof(PixelRecord)});
  n.parts.push_back({"the image and its planes", pixels * (3 + 2 + 2 * scene.lights.size())});
  return n;
}

MemoryRoom memory_room() {
  MemoryRoom room;
  rlimit rl{};
  if (getrlimit(RLIMIT_AS, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY)
    tighter(room, rl.rlim_cur, proc_kb("/proc/self/status", "VmSize"),
            "the address-space limit (ulimit -v)");
  if (getrlimit(RLIMIT_DATA, &rl) == 0 && rl.rlim_cur != RLIM_INFINITY)
    tighter(room, rl.rlim_cur, proc_kb("/proc/self/status", "VmData"),
            "the data-size limit (ulimit -d)");
  // The cgroup and the machine are shared with the sweep points running beside this one (a sweep
  // tells its points how many run at once): each may count on its share.
  uint64_t share = 1;
  std::string shared;
  if (const char* env = std::getenv(kPointsAtOnceEnv); env && std::atoi(env) > 1) {
    share = uint64_t(std::atoi(env));
    shared = fmt::format(", shared by {} sweep points at once (--jobs)", share);
  }
  if (const std::string dir = cgroup_dir(); !dir.empty()) {
    const uint64_t max = cgroup_value(dir + "/memory.max");
    const uint64_t current = cgroup_value(dir + "/memory.current");
    if (max != ~uint64_t(0))
      tighter(
          room, (max > current ? max - current : 0) / share, 0,
          fmt::format("the cgroup's memory.max ({} of {} in use){}", gb(current), gb(max), shared));
  }
  const uint64_t available =
      proc_kb("/proc/meminfo", "MemAvailable") + proc_kb("/proc/meminfo", "SwapFree");
  if (available > 0)
    tighter(room, available / share, 0, "the machine's available memory and swap" + shared);
  return room;
}

void check_memory(const MemoryNeed& need, const MemoryRoom& room) {
  const uint64_t total = need.total();
  if (total <= room.bytes) return;
  std::vector<std::pair<std::string, uint64_t>> parts =
      sum(need.transient) > sum(need.parts) ? need.transient : need.parts;
  std::sort(parts.begin(), parts.end(),
            [](const auto& a, const auto& b) { return a.second > b.second; });
  std::string list;
  for (size_t i = 0; i < std::min<size_t>(3, parts.size()); ++i)
    list += fmt::format("{}{} {}", i ? ", " : "", parts[i].first, gb(parts[i].second));
  throw InputError(fmt::format(
      "{} needs about {} ({}), but {} leaves {}: lower the resolution (--width, --height) or "
      "the reflections",
      need.what, gb(total), list, room.limit, gb(room.bytes)));
}

Activity::Activity(std::string what) : saved_(std::move(g_activity)) {
  g_activity = std::move(what);
}
Activity::~Activity() { g_activity = std::move(saved_); }
std::string Activity::current() { return g_activity; }

}  // namespace rtsim
