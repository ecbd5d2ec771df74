#include "reports/animation_tables.h"

#include <fmt/format.h>

#include <algorithm>
#include <optional>

namespace rtsim::report {

namespace {

using nlohmann::json;
using ptr = json::json_pointer;

// A number at `at`, printed as fmt prints a double; empty when absent.
std::string number(const json& r, const ptr& at) {
  return r.is_null() || !r.contains(at) || r.at(at).is_null()
             ? ""
             : fmt::format("{}", r.at(at).get<double>());
}

size_t lights_of(const std::map<double, AnimationFrame>& frames) {
  size_t lights = 0;
  for (const auto& [t, f] : frames)
    for (const json* r : {&f.off, &f.on})
      if (!r->is_null()) lights = std::max(lights, (*r)["per_light"].size());
  return lights;
}

std::string header(size_t lights) {
  std::string csv =
      "time,triangles,cycles_off,cycles_on,frame_ms_off,frame_ms_on,saved_ms,shadow_rays,shadow_"
      "rays_culled,culled_share,nonempty_leaves";
  for (size_t l = 0; l < lights; ++l) csv += fmt::format(",culled_leaves_l{}", l);
  for (size_t l = 0; l < lights; ++l) csv += fmt::format(",culled_rays_l{}", l);
  return csv +
         ",lvb_nodes_visited,lvb_region_tests,lvb_pair_tests,moved_triangles,lazy_dirty_pairs,"
         "lazy_pairs,lazy_dirty_tests,lazy_nodes_visited,lazy_region_tests,lazy_pair_tests,"
         "check_mismatched_pixels\n";
}

// The culling-on run's shadow rays and culled leaves: its cells of one row.
struct Culling {
  std::string rays, culled, share, nonempty, leaves, rays_l;
};

Culling culling_of(const json& on) {
  Culling c;
  if (on.is_null()) return c;
  uint64_t all = 0, cut = 0;
  for (const auto& l : on["per_light"]) {
    all += l["shadow_rays"].get<uint64_t>();
    cut += l["culled"].get<uint64_t>();
    c.rays_l += fmt::format(",{}", l["culled"].get<uint64_t>());
  }
  c.rays = std::to_string(all);
  c.culled = std::to_string(cut);
  c.share = all ? fmt::format("{:.6f}", double(cut) / double(all)) : "";
  const json& lvb_lights = on["lvb"]["per_light"];
  if (!lvb_lights.empty())
    c.nonempty = std::to_string(lvb_lights[0]["nonempty_leaves"].get<uint64_t>());
  for (const auto& l : lvb_lights)
    c.leaves += fmt::format(",{}", l["culled_leaves"].get<uint64_t>());
  return c;
}

std::string row(double t, const AnimationFrame& f, size_t lights) {
  const json& any = f.on.is_null() ? f.off : f.on;
  const Culling c = culling_of(f.on);
  std::string saved;
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
  for (const json* r : {&f.off, &f.on})
    if (!r->is_null() && r->contains("reference_check") && !(*r)["reference_check"].is_null())
      mismatched =
          mismatched.value_or(0) + (*r)["reference_check"]["mismatched_pixels"].get<uint64_t>();
  std::string csv = fmt::format(
      "{:.9g},{},{},{},{},{},{},{},{},{},{}{}{}", t, number(any, ptr("/scene/triangles")),
      number(f.off, ptr("/cycles_total")), number(f.on, ptr("/cycles_total")),
      number(f.off, ptr("/frame_ms/all")), number(f.on, ptr("/frame_ms/all")), saved, c.rays,
      c.culled, c.share, c.nonempty, pad(c.leaves), pad(c.rays_l));
  for (const char* key :
       {"/lvb/nodes_visited", "/lvb/region_tests", "/lvb/pair_tests", "/lvb/lazy/moved_triangles",
        "/lvb/lazy/dirty_pairs", "/lvb/lazy/pairs", "/lvb/lazy/dirty_tests",
        "/lvb/lazy/nodes_visited", "/lvb/lazy/region_tests", "/lvb/lazy/pair_tests"})
    csv += "," + number(f.on, ptr(key));
  return csv + "," + (mismatched ? std::to_string(*mismatched) : std::string()) + "\n";
}

}  // namespace

// Sampled frames (rtsim animate --sample): each run's 95% half-interval of its cycles, in columns
// after the others, so that a full animation's frames.csv is as it was.
bool any_sampled(const std::map<double, AnimationFrame>& frames) {
  for (const auto& [t, f] : frames)
    for (const json* r : {&f.off, &f.on})
      if (!r->is_null() && r->value("sampled", false)) return true;
  return false;
}

std::string frames_csv(const std::map<double, AnimationFrame>& frames) {
  const size_t lights = lights_of(frames);
  const bool sampled = any_sampled(frames);
  std::string csv = header(lights);
  if (sampled) csv.insert(csv.size() - 1, ",cycles_off_ci95,cycles_on_ci95");
  for (const auto& [t, f] : frames) {
    csv += row(t, f, lights);
    if (sampled)
      csv.insert(csv.size() - 1, "," + number(f.off, ptr("/cycles_total_ci95")) + "," +
                                     number(f.on, ptr("/cycles_total_ci95")));
  }
  return csv;
}

std::string host_csv(const std::map<double, AnimationFrame>& frames) {
  std::string host = "time,kdtree_seconds,lvb_seconds,simulate_seconds_off,simulate_seconds_on\n";
  for (const auto& [t, f] : frames) {
    const json& any = f.on.is_null() ? f.off : f.on;
    host += fmt::format("{:.9g},{},{},{},{}\n", t, number(any, ptr("/host/seconds/kdtree")),
                        number(f.on, ptr("/host/seconds/lvb")),
                        number(f.off, ptr("/host/seconds/simulate")),
                        number(f.on, ptr("/host/seconds/simulate")));
  }
  return host;
}

}  // namespace rtsim::report
