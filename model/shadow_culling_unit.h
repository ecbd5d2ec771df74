// Shadow culling unit (the paper's Fig. 5): in the shadow phase, for every hit pixel and every
// light, it emits the shadow ray only when the hit leaf's LVB bit for that light is 1; a culled
// ray counts as unoccluded. One shadow ray per cycle; the LVB test is a bitwise check on the
// hit's whole word, so culled lights are skipped within the cycle. Light records are read
// through its L1.
#pragma once

#include "model/cache.h"
#include "model/frame_buffer.h"
#include "model/model_context.h"
#include "model/ray_fifo.h"
#include "model/unit.h"

#include <vector>

namespace rtsim::model {

struct LightStats {
  uint64_t decisions = 0;  // hit pixels considered for this light
  uint64_t generated = 0;  // shadow rays emitted
  uint64_t culled = 0;     // shadow rays culled by the LVB
};

class ShadowCullingUnit : public Unit, public FillListener {
 public:
  ShadowCullingUnit(sc_core::sc_module_name name, const ModelContext& ctx, bool culling, Cache* l1,
                    FrameBuffer* frame, std::vector<RayFifo*> trv_inputs);
  void start(Tick now);
  bool started() const { return started_; }
  bool finished() const { return started_ && pixel_ >= frame_->pixels.size(); }
  double scanned_fraction() const { return frame_->pixels.empty() ? 1.0 : double(pixel_) / double(frame_->pixels.size()); }
  uint64_t generated() const;
  void on_fill(uint64_t, uint64_t, Tick when) override {
    waiting_ = false;
    wake(when);
  }
  const std::vector<LightStats>& per_light() const { return lights_; }
  void register_stats(StatsRegistry& r, const std::string& prefix) const;

 protected:
  bool cycle(Tick now) override;
  Tick next_ready(Tick from) const override;
  bool holds_work() const override { return started_ && !finished(); }

 private:
  void advance();

  const ModelContext& ctx_;
  bool culling_;
  Cache* l1_;
  FrameBuffer* frame_;
  RoundRobin inputs_;  // the TRV units' input FIFOs
  bool started_ = false, waiting_ = false;
  size_t pixel_ = 0;
  uint32_t light_ = 0;
  std::vector<LightStats> lights_;
};

}  // namespace rtsim::model
