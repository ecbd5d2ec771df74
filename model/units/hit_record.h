// The frame buffer in simulated memory: one 64-byte hit record per frame entry (pixel and bounce),
// in a region after the memory image. A shading unit writes a hit's record (its results: the
// surface point, the hit leaf's LVB word, the hit and its material); in the two-phase schedule
// the shadow culling unit reads the records back and builds the shadow rays from the bytes it
// fetched. An entry that was never written reads as zeros: no hit.
//
// Layout (little-endian): p (3 floats) | n (3 floats) | lvb (u32) | flags (u32, bit 0: hit) |
// diffuse (3 floats) | reflectance (float) | triangle (u32) | t (float) | 8 bytes unused.
// One record per line: a DRAM request moves a whole line, so a record is one write and one read.
#pragma once

#include "kernels/memory_image.h"
#include "model/units/frame_buffer.h"

#include <cstring>
#include <memory>
#include <vector>

namespace rtsim::model {

inline constexpr uint32_t kHitRecordBytes = 64;

// One record per memory line (stride: the line size, at least a record), level by level, and
// within a level in the order primary rays are issued (tiles): the records of a tile's pixels are
// neighbours in memory, so the writes and the reads of a tile hit open DRAM rows. (Pixel-linear,
// the rows of a tile lay 123 KB apart at full HD: every write opened a DRAM row, and the write
// backlog outgrew the frame.) Without a pixel order, slot = entry.
struct HitRecordRegion {
  uint64_t base = 0;  // line-aligned, after the image
  uint32_t stride = kHitRecordBytes;
  uint32_t pixels = 0;                                    // per level
  std::shared_ptr<const std::vector<uint32_t>> pixel_at;  // slot within a level -> pixel
  std::shared_ptr<const std::vector<uint32_t>> slot_of;   // pixel -> slot within a level

  uint32_t slot(uint32_t entry) const {
    return slot_of ? entry / pixels * pixels + (*slot_of)[entry % pixels] : entry;
  }
  uint32_t entry(uint32_t slot) const {
    return pixel_at ? slot / pixels * pixels + (*pixel_at)[slot % pixels] : slot;
  }
  uint64_t slot_address(uint32_t slot) const { return base + uint64_t(slot) * stride; }
  uint64_t address(uint32_t entry) const { return slot_address(slot(entry)); }
};

struct HitRecord {
  SurfacePoint surface;
  uint32_t lvb = 0;
  bool hit = false;
};

// Writes the record into the first kHitRecordBytes at `out`.
inline void encode_hit_record(const PixelState& px, uint8_t* out) {
  std::memset(out, 0, kHitRecordBytes);
  auto put = [&out](size_t at, const void* v, size_t n) { std::memcpy(out + at, v, n); };
  const float f[] = {px.surface.p.x, px.surface.p.y, px.surface.p.z,
                     px.surface.n.x, px.surface.n.y, px.surface.n.z};
  put(0, f, sizeof f);
  put(24, &px.lvb, 4);
  const uint32_t flags = px.hit.tri != kNoHit ? 1u : 0u;
  put(28, &flags, 4);
  const float m[] = {px.diffuse.x, px.diffuse.y, px.diffuse.z, px.reflectance};
  put(32, m, sizeof m);
  put(48, &px.hit.tri, 4);
  put(52, &px.hit.t, 4);
}

inline HitRecord decode_hit_record(const uint8_t* p) {
  HitRecord r;
  r.surface.p = image::load_vec3(p);
  r.surface.n = image::load_vec3(p + 12);
  r.lvb = image::load_u32(p + 24);
  r.hit = (image::load_u32(p + 28) & 1u) != 0;
  return r;
}

}  // namespace rtsim::model
