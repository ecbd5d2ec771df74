// Ray generator: up to `rays_per_cycle` primary rays per cycle (the T&I engine's dispatcher issues
// one), through pixel centres in scanline or square-tile order, dealt in turn to the TRV units'
// input FIFOs (`to_trv`), as long as the ray pool has a free slot. The phase controller drives it
// through the export `control`.
#pragma once

#include "kernels/camera.h"
#include "model/sim/ray_fifo.h"
#include "model/sim/unit.h"
#include "model/units/model_context.h"
#include "model/units/ray_ports.h"

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
  // The next frame's rays: `camera` at width x height, from its first pixel.
  void begin_frame(const Camera& camera, int width, int height);

  // When each batch of kBatchRays primary rays in issue order began to issue: the frame's units of
  // work for sampling (issue 38, docs/sampling.md), the last batch maybe shorter.
  static constexpr uint32_t kBatchRays = model::kBatchRays;
  const std::vector<Tick>& batch_starts() const { return batch_starts_; }

  // PrimaryRays.
  bool finished() const override { return next_ == total_; }
  uint64_t issued() const override { return next_; }
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
  uint64_t next_ = 0, total_ = 0;
  std::vector<uint32_t> order_;  // pixels in issue order
  std::vector<Tick> batch_starts_;
};

}  // namespace rtsim::model
