#include "model/units/ray_generator.h"

namespace rtsim::model {

std::vector<uint32_t> issue_order(int width, int height, RayOrder order, int tile) {
  std::vector<uint32_t> pixels;
  pixels.reserve(size_t(width) * size_t(height));
  if (order == RayOrder::kScanline) {
    for (uint32_t p = 0; p < uint32_t(width * height); ++p) pixels.push_back(p);
    return pixels;
  }
  for (int ty = 0; ty < height; ty += tile)
    for (int tx = 0; tx < width; tx += tile)
      for (int y = ty; y < std::min(ty + tile, height); ++y)
        for (int x = tx; x < std::min(tx + tile, width); ++x)
          pixels.push_back(uint32_t(y * width + x));
  return pixels;
}

RayGenerator::RayGenerator(sc_core::sc_module_name name, const ModelContext& ctx,
                           const Camera& camera, int width, int height, RayOrder order, int tile,
                           std::vector<RayFifo*> trv_inputs, uint32_t rays_per_cycle)
    : Unit(name, *ctx.calendar, ctx.clock),
      ctx_(ctx),
      camera_(camera, width, height),
      width_(width),
      height_(height),
      inputs_(std::move(trv_inputs)),
      rays_per_cycle_(rays_per_cycle),
      total_(uint64_t(width) * height),
      order_(issue_order(width, height, order, tile)) {}

bool RayGenerator::cycle(Tick now) {
  uint32_t issued = 0;
  for (; issued < rays_per_cycle_ && !finished() && !ctx_.pool->full(); ++issued) {
    RayFifo* f = inputs_.next_free();
    if (!f) break;
    const uint32_t pixel = pixel_of(next_++);
    const uint32_t id = ctx_.pool->allocate();
    RayState& r = (*ctx_.pool)[id];
    r.type = RayType::kPrimary;
    r.pixel = pixel;
    r.trav.ray = camera_.ray(int(pixel % width_), int(pixel / width_));
    f->push(id, now + clock().period(), now);
  }
  return issued > 0;
}

Tick RayGenerator::next_ready(Tick from) const {
  if (finished() || ctx_.pool->full()) return kUnknown;  // woken when a ray retires
  return inputs_.any_free() ? from : kUnknown;           // woken when a TRV input frees a slot
}

}  // namespace rtsim::model
