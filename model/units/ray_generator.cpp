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

void RayGenerator::begin_frame(const Camera& camera, int width, int height,
                               std::vector<DetailWindow> windows) {
  camera_ = PinholeCamera(camera, width, height);
  width_ = width;
  height_ = height;
  inputs_.restart();
  paths_ = ctx_.paths() ? uint32_t(ctx_.path.spp) : 1u;
  path_stride_ = ctx_.paths() ? uint32_t(ctx_.path.max_depth + 1) * uint32_t(width * height) : 0u;
  total_ = uint64_t(width) * uint64_t(height) * paths_;
  order_ = issue_order(width, height, order_kind_, tile_);
  windows_ = std::move(windows);
  if (windows_.empty()) windows_ = whole_frame(total_);
  starts_.assign(windows_.size(), {});
  window_ = 0;
  next_ = windows_[0].begin;
  limit_ = std::min(windows_[0].end + 1, total_);
  issued_ = 0;
}

bool RayGenerator::next_window() {
  if (window_ + 1 >= windows_.size() || ctx_.pool->in_flight() > 0) return false;
  const DetailWindow& w = windows_[++window_];
  next_ = w.begin;
  limit_ = std::min(w.end + 1, total_);
  if (on_window) on_window(w.begin);
  return true;
}

bool RayGenerator::cycle(Tick now) {
  if (next_ == limit_ && !next_window()) return false;
  uint32_t issued = 0;
  for (; issued < rays_per_cycle_ && next_ < limit_ && !ctx_.pool->full(); ++issued) {
    RayQueueIn* f = inputs_.next_free();
    if (!f) break;
    if (next_ % kBatchRays == 0) starts_[window_].push_back(now);
    // A pixel's paths one after another, each from the pixel's centre (as the reference traces
    // them); its entry is the pixel's at bounce 0 of the path.
    const uint32_t pixel = pixel_of(next_ / paths_), path = uint32_t(next_ % paths_);
    ++next_;
    RayInfo info;
    info.entry = path * path_stride_ + pixel;
    info.ray = camera_.ray(int(pixel % width_), int(pixel / width_));
    info.born = now;
    f->push(ctx_.pool->create(info), now + clock().period(), now);
    ++issued_;
  }
  return issued > 0;
}

Tick RayGenerator::next_ready(Tick from) const {
  if (next_ == limit_)  // between windows: when the last ray in flight retires
    return window_ + 1 < windows_.size() && ctx_.pool->in_flight() == 0 ? from : kUnknown;
  if (ctx_.pool->full()) return kUnknown;       // woken when a ray retires
  return inputs_.any_free() ? from : kUnknown;  // woken when a TRV input frees a slot
}

}  // namespace rtsim::model
