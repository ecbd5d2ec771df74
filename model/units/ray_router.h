// The router: the way back from IST and shading to the TRV unit that owns a ray's slot (the T&I
// engine's scheme: a ray keeps its TRV slot while it visits LIST and IST), and a finished ray's
// way to the shading unit that serves its TRV unit (the rays of TRV unit i finish in shading unit
// i x shading / trv). It owns retirement: it frees the ray's TRV slot and its pool slot, and tells
// the phase controller. It adds no time: a ray reaches its owner at the time it was handed over.
//
// Exports: `returns` (RayReturn, for IST and shading), `finished` (RaySink, for IST). Ports:
// `owners` (every TRV unit, in order), `shading` (every shading unit's input, in order),
// `phases` (the phase controller).
#pragma once

#include "model/sim/ray_fifo.h"
#include "model/units/model_context.h"
#include "model/units/ray_ports.h"

#include <systemc>

namespace rtsim::model {

class RayRouter : public sc_core::sc_module, public RayReturn, public RaySink {
 public:
  sc_core::sc_export<RayReturn> returns;
  sc_core::sc_export<RaySink> finished;
  sc_core::sc_port<RayOwner, 0> owners;
  sc_core::sc_port<RaySink, 0> shading;
  sc_core::sc_port<RetireListener> phases;

  RayRouter(sc_core::sc_module_name name, const ModelContext& ctx);
  const char* kind() const override { return "rtsim_ray_router"; }

  // RayReturn: to the ray's owner.
  bool leaf_done(uint32_t ray, Tick when) override { return owner(ray)->leaf_done(ray, when); }
  void reflect(uint32_t ray, Tick when) override { owner(ray)->reflect(ray, when); }
  void release_slot(uint32_t ray) override { owner(ray)->release_slot(ray); }
  void retire(uint32_t ray, RayType type, Tick when) override;

  // RaySink: a finished ray to its owner's shading unit.
  bool push(uint32_t ray, Tick ready, Tick now) override {
    return shading_of(ray)->push(ray, ready, now);
  }
  // A producer is woken by every shading unit's input.
  void add_producer(Unit* producer) override;

 private:
  void end_of_elaboration() override;  // takes what the ports are bound to
  RayOwner* owner(uint32_t ray) const { return owners_[(*ctx_.pool)[ray].trv.owner]; }
  RaySink* shading_of(uint32_t ray) const { return shading_of_[(*ctx_.pool)[ray].trv.owner]; }

  const ModelContext& ctx_;
  std::vector<RayOwner*> owners_;     // by TRV unit
  std::vector<RaySink*> shading_of_;  // by TRV unit
};

}  // namespace rtsim::model
