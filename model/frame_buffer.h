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
  uint16_t occluded = 0;  // bit i: the shadow ray to light i was blocked
  uint16_t culled = 0;    // bit i: the shadow ray to light i was culled (not generated)
};

struct FrameBuffer {
  int width = 0, height = 0;
  std::vector<PixelState> pixels;
};

}  // namespace rtsim::model
