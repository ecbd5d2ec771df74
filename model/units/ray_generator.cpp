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

RayGenerator::RayGenerator(sc_core::sc_module_name name, const ModelContext& ctx, RayOrder order,
                           int tile, uint32_t rays_per_cycle)
    : Unit(name, *ctx.calendar, ctx.clock),
      to_trv("to_trv", this),
      control("control"),
      ctx_(ctx),
      order_kind_(order),
      tile_(tile),
      inputs_(to_trv),
      rays_per_cycle_(rays_per_cycle) {
  control.bind(*this);
}

void RayGenerator::begin_frame(const Camera& camera, int width, int height) {
  camera_ = PinholeCamera(camera, width, height);
  width_ = width;
  height_ = height;
  next_ = 0;
  inputs_.restart();
  total_ = uint64_t(width) * uint64_t(height);
  order_ = issue_order(width, height, order_kind_, tile_);
  batch_starts_.clear();
  batch_starts_.reserve((total_ + kBatchRays - 1) / kBatchRays);
}

bool RayGenerator::cycle(Tick now) {
  uint32_t issued = 0;
  for (; issued < rays_per_cycle_ && !finished() && !ctx_.pool->full(); ++issued) {
    RayQueueIn* f = inputs_.next_free();
    if (!f) break;
    if (next_ % kBatchRays == 0) batch_starts_.push_back(now);
    RayInfo info;
    info.entry = pixel_of(next_++);  // bounce 0: the entry is the pixel
    info.ray = camera_.ray(int(info.entry % width_), int(info.entry / width_));
    f->push(ctx_.pool->create(info), now + clock().period(), now);
  }
  return issued > 0;
}

Tick RayGenerator::next_ready(Tick from) const {
  if (finished() || ctx_.pool->full()) return kUnknown;  // woken when a ray retires
  return inputs_.any_free() ? from : kUnknown;           // woken when a TRV input frees a slot
}

}  // namespace rtsim::model
