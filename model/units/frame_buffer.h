// What the shading stage keeps per pixel between the two phases: the primary hit, the surface
// point and material it fetched, the hit leaf's LVB word, and the shadow results per light.
#pragma once

#include "kernels/shading.h"
#include "kernels/traversal.h"

#include <cstdint>
#include <vector>

namespace rtsim::model {

struct PixelState {
  Hit hit;           // tri == kNoHit: the primary ray missed
  uint32_t lvb = 0;  // LVB word of the hit leaf (from the LVB updater)
  SurfacePoint surface;
  Vec3 diffuse{0.f};
  float reflectance = 0.f;
  // Bit i: the shadow ray to light i was blocked (every sample, for an area light)
  uint16_t occluded = 0;
  uint16_t culled = 0;  // bit i: the shadow rays to light i were culled (not generated)
};

// One entry per pixel, path and bounce: entry (path * levels + level) * width * height + pixel
// holds the hit of the pixel's ray after `level` bounces (level 0: the primary ray) on its path
// `path` (a Whitted frame has one path a pixel, whose bounces are mirror reflections). An entry's
// `entry / (width * height)` is the key its area lights' samples are placed by: the reflection
// depth, or path_light_key (kernels/path_sampling.h).
struct FrameBuffer {
  int width = 0, height = 0;
  int levels = 1;  // entries along a path: 1 + reflection depth, or 1 + max_depth
  int paths = 1;   // paths per pixel (spp of a path-traced frame)
  std::vector<PixelState> pixels;
  // Lights with several samples (area lights): one occlusion bit per entry, light and sample, so
  // the pixels can be composed in the reference tracer's sample order.
  std::vector<uint32_t> samples;    // per light
  std::vector<uint32_t> first_bit;  // per light: its first bit within an entry's words
  uint32_t words_per_entry = 0;
  std::vector<uint64_t> sample_bits;

  size_t pixel_count() const { return size_t(width) * height; }
  void allocate(const std::vector<uint32_t>& light_samples) {
    pixels.assign(pixel_count() * levels * paths, PixelState{});
    samples = light_samples;
    first_bit.assign(samples.size(), 0);
    uint32_t bits = 0;
    for (size_t l = 0; l < samples.size(); ++l) {
      first_bit[l] = bits;
      if (samples[l] > 1) bits += samples[l];
    }
    words_per_entry = (bits + 63) / 64;
    sample_bits.assign(pixels.size() * words_per_entry, 0);
  }
  void set_sample_occluded(uint32_t entry, uint32_t light, uint32_t k) {
    const uint32_t bit = first_bit[light] + k;
    sample_bits[size_t(entry) * words_per_entry + bit / 64] |= uint64_t(1) << (bit % 64);
  }
  bool sample_occluded(uint32_t entry, uint32_t light, uint32_t k) const {
    if (samples[light] == 1) return (pixels[entry].occluded >> light) & 1u;
    const uint32_t bit = first_bit[light] + k;
    return (sample_bits[size_t(entry) * words_per_entry + bit / 64] >> (bit % 64)) & 1u;
  }
  uint32_t occluded_samples(uint32_t entry, uint32_t light) const {
    uint32_t n = 0;
    for (uint32_t k = 0; k < samples[light]; ++k) n += sample_occluded(entry, light, k);
    return n;
  }
  // After the frame: an area light's bit in `occluded` when every one of its samples was blocked.
  void close_samples() {
    for (uint32_t e = 0; e < pixels.size(); ++e)
      for (uint32_t l = 0; l < samples.size(); ++l)
        if (samples[l] > 1 && occluded_samples(e, l) == samples[l])
          pixels[e].occluded |= uint16_t(1u << l);
  }
  uint32_t entry(uint32_t pixel, int level, int path = 0) const {
    return uint32_t((size_t(path) * levels + level) * pixel_count() + pixel);
  }
  uint32_t pixel_of(uint32_t entry) const { return uint32_t(entry % pixel_count()); }
  uint32_t key_of(uint32_t entry) const { return uint32_t(entry / pixel_count()); }
  uint32_t level_of(uint32_t entry) const { return key_of(entry) % uint32_t(levels); }
  uint32_t path_of(uint32_t entry) const { return key_of(entry) / uint32_t(levels); }
  PixelState& at(uint32_t pixel, int level, int path = 0) {
    return pixels[entry(pixel, level, path)];
  }
  const PixelState& at(uint32_t pixel, int level, int path = 0) const {
    return pixels[entry(pixel, level, path)];
  }
};

}  // namespace rtsim::model
