// Reference tracer throughput on one core: primary (closest-hit) and shadow (any-hit) rays per
// second over the camera rays of a scene. Usage:
//   bench_tracer [SCENE.yaml] [--width W --height H] [--repeat N] [--scene-root DIR]
#include "kernels/reference_tracer.h"
#include "testbench/run/pipeline.h"

#include "bench/bench_util.h"

#include <fmt/format.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <vector>

using namespace rtsim;

int main(int argc, char** argv) {
  std::string scene_file = std::string(RTSIM_SOURCE_DIR) + "/configs/scenes/kitchen.yaml";
  PrepareOptions prep;
  prep.width = 480;
  prep.height = 270;
  int repeat = 5;
  for (int i = 1; i < argc; ++i) {
    auto next = [&] { return bench::option_value(argc, argv, i); };
    if (!std::strcmp(argv[i], "--width"))
      prep.width = std::atoi(next());
    else if (!std::strcmp(argv[i], "--height"))
      prep.height = std::atoi(next());
    else if (!std::strcmp(argv[i], "--repeat"))
      repeat = std::max(1, std::atoi(next()));
    else if (!std::strcmp(argv[i], "--scene-root"))
      prep.scene_root = next();
    else
      scene_file = argv[i];
  }
  const PreparedScene p = prepare_scene(scene_file, prep);
  const ReferenceTracer tracer(*p.image);
  const PinholeCamera cam(p.scene.camera, p.scene.width, p.scene.height);
  std::vector<Ray> primary;
  for (int y = 0; y < p.scene.height; ++y)
    for (int x = 0; x < p.scene.width; ++x) primary.push_back(cam.ray(x, y));

  // Shadow rays exactly as the tracer's shading builds them.
  const float offset = 1e-5f * p.image->header().bounds.diagonal();
  std::vector<Ray> shadow;
  for (const Ray& r : primary) {
    const Hit h = tracer.closest_hit(r);
    if (h.tri == kNoHit) continue;
    const Triangle& t = p.scene.triangles[h.tri];
    const SurfacePoint sp = surface_point(r, h.t, t.v0, t.v1, t.v2);
    for (const Light& l : p.scene.lights) {
      const Ray s = shadow_ray(sp, l.position, offset);
      shadow.push_back(s);
    }
  }
  std::vector<double> prim_rate, shadow_rate, seconds;
  uint64_t sink = 0;
  for (int k = 0; k < repeat; ++k) {
    auto t0 = std::chrono::steady_clock::now();
    for (const Ray& r : primary) sink += tracer.closest_hit(r).tri;
    auto t1 = std::chrono::steady_clock::now();
    for (const Ray& r : shadow) sink += tracer.occluded(r);
    auto t2 = std::chrono::steady_clock::now();
    seconds.push_back(std::chrono::duration<double>(t2 - t0).count());
    prim_rate.push_back(primary.size() / std::chrono::duration<double>(t1 - t0).count());
    shadow_rate.push_back(shadow.size() / std::chrono::duration<double>(t2 - t1).count());
    fmt::print("run {}: {:.3f} M primary rays/s, {:.3f} M shadow rays/s\n", k,
               prim_rate.back() / 1e6, shadow_rate.back() / 1e6);
  }
  fmt::print("{}: {} triangles, {}x{}, {} primary rays, {} shadow rays, one core\n", p.scene.name,
             p.scene.triangles.size(), p.scene.width, p.scene.height, primary.size(),
             shadow.size());
  fmt::print("median of {}: {:.3f} M primary rays/s, {:.3f} M shadow rays/s (checksum {})\n",
             repeat, bench::median(prim_rate) / 1e6, bench::median(shadow_rate) / 1e6, sink);
  // The frame's rays, primary and every shadow ray (bench/model_vs_tracer.py reads this line).
  fmt::print("median seconds for the frame's rays: {:.4f}\n", bench::median(seconds));
  return 0;
}
