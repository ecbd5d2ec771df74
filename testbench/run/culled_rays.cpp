#include "testbench/run/culled_rays.h"

#include "kernels/light_samples.h"
#include "reports/output_files.h"

namespace rtsim {

std::vector<CulledRay> culled_rays(const model::FrameBuffer& frame, const MemoryImage& image) {
  std::vector<CulledRay> out;
  const image::Header& h = image.header();
  // The offset the culling unit's shadow rays leave their surface by (model::ModelContext).
  const float offset = 1e-5f * h.bounds.diagonal();
  for (uint32_t pixel = 0; pixel < frame.pixel_count(); ++pixel)
    for (int path = 0; path < frame.paths; ++path)
      for (int level = 0; level < frame.levels; ++level) {
        const uint32_t entry = frame.entry(pixel, level, path);
        const model::PixelState& px = frame.pixels[entry];
        if (px.hit.tri == kNoHit || px.culled == 0) continue;
        for (uint32_t l = 0; l < h.light_count; ++l) {
          if (!((px.culled >> l) & 1u)) continue;
          const image::LightRecord light = image.light(l);
          for (uint32_t k = 0; k < light.samples; ++k) {
            CulledRay c;
            c.pixel = pixel;
            c.sample = uint32_t(path);
            c.bounce = uint16_t(level);
            c.light = uint16_t(l);
            c.light_sample = k;
            c.target = light_sample_point(light, pixel, frame.key_of(entry), l, k);
            c.origin = shadow_ray(px.surface, c.target, offset).o;
            out.push_back(c);
          }
        }
      }
  return out;
}

void write_culled_rays(const std::string& path, const std::vector<CulledRay>& rays) {
  std::string bytes;
  bytes.reserve(rays.size() * 40);
  const auto put = [&bytes](const void* p, size_t n) {  // the host is little-endian (x86-64)
    bytes.append(static_cast<const char*>(p), n);
  };
  for (const CulledRay& c : rays) {
    put(&c.pixel, 4);
    put(&c.sample, 4);
    put(&c.bounce, 2);
    put(&c.light, 2);
    put(&c.light_sample, 4);
    for (const Vec3* v : {&c.origin, &c.target})
      for (int k = 0; k < 3; ++k) put(&(*v)[k], 4);
  }
  write_npy_records(path,
                    "[('pixel', '<u4'), ('sample', '<u4'), ('bounce', '<u2'), ('light', '<u2'), "
                    "('light_sample', '<u4'), ('origin', '<f4', (3,)), ('target', '<f4', (3,))]",
                    rays.size(), bytes);
}

}  // namespace rtsim
