// Ray generator: up to `rays_per_cycle` primary rays per cycle (the T&I engine's dispatcher issues
// one), through pixel centres in scanline or square-tile order (a path-traced frame's `spp` paths
// of a pixel one after another), dealt in turn to the TRV units' input FIFOs (`to_trv`), as long
// as the ray pool has a free slot. The phase controller drives it through the export `control`.
#pragma once

#include "kernels/camera.h"
#include "model/sim/ray_fifo.h"
#include "model/sim/unit.h"
#include "model/units/detail_window.h"
#include "model/units/model_context.h"
#include "model/units/ray_ports.h"

#include <functional>
#include <vector>

namespace rtsim::model {

enum class RayOrder { kScanline, kTiles };

// The pixels in issue order: row by row, or square tiles row by row with pixels row by row inside
// a tile (partial tiles at the edges).
std::vector<uint32_t> issue_order(int width, int height, RayOrder order, int tile);

class RayGenerator : public Unit, public PrimaryRays {
 public:
  RayDeal to_trv;
  sc_core::sc_export<PrimaryRays> control;

  RayGenerator(sc_core::sc_module_name name, const ModelContext& ctx, RayOrder order, int tile,
               uint32_t rays_per_cycle = 1);
  // The next frame's rays: `camera` at width x height, from its first pixel, those of `windows`
  // only (check_windows; whole_frame() for all): between two windows it waits until no ray is
  // in flight, then goes on at the next window's first ray.
  void begin_frame(const Camera& camera, int width, int height,
                   std::vector<DetailWindow> windows = {});

  // Per window, when each batch of kBatchRays primary rays in issue order began to issue: the
  // frame's units of work for sampling (issue 38, docs/sampling.md). A window that ends before
  // the frame's last ray issues ray `end` to time its last batch: its last start is that one.
  static constexpr uint32_t kBatchRays = model::kBatchRays;
  const std::vector<DetailWindow>& windows() const { return windows_; }
  const std::vector<std::vector<Tick>>& window_starts() const { return starts_; }
  // Called when a window but the first begins, with its first ray, before it issues (a sampled
  // frame's functional warming; Accelerator::sample).
  std::function<void(uint64_t)> on_window;

  // PrimaryRays.
  bool finished() const override { return next_ == limit_ && window_ + 1 >= windows_.size(); }
  uint64_t issued() const override { return issued_; }
  uint64_t total() const { return total_; }  // primary rays in the frame
  void slot_freed(Tick now) override { wake(now); }

 protected:
  bool cycle(Tick now) override;
  Tick next_ready(Tick from) const override;
  bool holds_work() const override { return !finished(); }

 private:
  uint32_t pixel_of(uint64_t k) const { return order_[k]; }

  const ModelContext& ctx_;
  PinholeCamera camera_{Camera{}, 1, 1};
  int width_ = 0, height_ = 0;
  RayOrder order_kind_;
  int tile_;
  RoundRobin inputs_;  // over to_trv
  uint32_t rays_per_cycle_;
  // At the current window's end: goes on at the next window when the machine is empty.
  bool next_window();

  uint64_t next_ = 0, total_ = 0;  // rays in issue order
  uint32_t paths_ = 1;             // per pixel
  uint32_t path_stride_ = 0;       // entries from one of a pixel's paths to the next
  uint64_t limit_ = 0;             // the current window's last ray to issue, plus one
  uint64_t issued_ = 0;            // this frame
  std::vector<uint32_t> order_;    // pixels in issue order
  std::vector<DetailWindow> windows_;
  size_t window_ = 0;
  std::vector<std::vector<Tick>> starts_;  // per window
};

}  // namespace rtsim::model
