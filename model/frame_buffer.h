// What the shading stage keeps per pixel between the two phases: the primary hit, the surface
// point and material it fetched, the hit leaf's LVB word, and the shadow results per light.
#pragma once

#include "kernels/shading.h"
#include "kernels/traversal.h"

#include <cstdint>
#include <vector>

namespace rtsim::model {

struct PixelState {
  Hit hit;                // tri == kNoHit: the primary ray missed
  uint32_t lvb = 0;       // LVB word of the hit leaf (from the LVB updater)
  SurfacePoint surface;
  Vec3 diffuse{0.f};
  float reflectance = 0.f;
  uint16_t occluded = 0;  // bit i: the shadow ray to light i was blocked
  uint16_t culled = 0;    // bit i: the shadow ray to light i was culled (not generated)
};

// One entry per pixel and bounce: entry level * width * height + pixel holds the hit of the
// pixel's ray after `level` mirror reflections (level 0: the primary ray).
struct FrameBuffer {
  int width = 0, height = 0;
  int levels = 1;
  std::vector<PixelState> pixels;
  size_t pixel_count() const { return size_t(width) * height; }
  uint32_t entry(uint32_t pixel, int level) const { return uint32_t(size_t(level) * pixel_count() + pixel); }
  PixelState& at(uint32_t pixel, int level) { return pixels[entry(pixel, level)]; }
  const PixelState& at(uint32_t pixel, int level) const { return pixels[entry(pixel, level)]; }
};

}  // namespace rtsim::model
