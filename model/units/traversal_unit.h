// What a traversal unit is to the rest of the machine, whichever structure it walks (TRV: the
// kd-tree, model/units/trv_unit.h; the BVH unit, model/units/bvh_unit.h): it owns its rays' slots
// while they visit LIST and IST (the T&I engine's scheme: at most `capacity` rays owned, and a ray
// coming back after its leaf never waits for room), and it owns their stacks.
//
// Ports: `to_list` (a ray reaching a leaf), `to_shading` (a ray whose traversal is over); the
// export `owner` (RayOwner: rays coming back, slots freeing).
#pragma once

#include "model/units/ray_ports.h"
#include "model/units/ray_unit.h"

namespace rtsim::model {

class TraversalUnit : public RayUnit, public RayOwner {
 public:
  RayOut to_list;
  RayOut to_shading;
  sc_core::sc_export<RayOwner> owner;

  // RayOwner: a ray that goes on as its reflection restarts here; a retired ray frees its slot.
  void reflect(uint32_t ray, Tick when) override {
    ray_state(ray).trv.started = false;
    take_back(ray, when);
  }
  void release_slot(uint32_t ray) override {
    --owned_;
    released(ray);
    wake(now_ps());
  }

 protected:
  // Unit `index` of its type (the owner its rays come back to); `type` names its caches.
  TraversalUnit(sc_core::sc_module_name name, const ModelContext& ctx, const UnitTypeConfig& cfg,
                uint32_t index, const char* type)
      : RayUnit(name, ctx, cfg, kTrvStage, type),
        to_list("to_list", this),
        to_shading("to_shading", this),
        owner("owner"),
        index_(uint16_t(index)) {
    owner.bind(*this);
    count_slots(&owned_);
  }
  // A ray entered: this unit owns its slot from now until it retires.
  void admitted(uint32_t ray) override {
    ++owned_;
    TrvState& t = ray_state(ray).trv;
    t.owner = index_;
    t.started = false;
    owned(ray);
  }
  // The ray met memory that is not an image: its walk ends at `when`, and shading retires it as
  // a miss.
  void walk_fault(uint32_t ray, ImageFault f, Tick when, Tick now) {
    fault(ray, f);
    emit(to_shading, ray, when, now);
  }
  // Whether the ray's walk may fetch `node` next: inside the nodes section, and not more steps
  // than the tree has nodes (a legal walk fetches each node at most once; more is a cycle of
  // corrupt pointers, which would keep the ray moving for ever). Else its walk ends at `when`.
  bool fetchable(uint32_t ray, uint32_t node, Tick when, Tick now) {
    const uint32_t nodes = ctx_.header.nodes.count;
    if (node < nodes && ray_state(ray).trv.steps < nodes) return true;
    walk_fault(ray, node >= nodes ? ImageFault::kNodeIndex : ImageFault::kStepBound, when, now);
    return false;
  }
  // A subclass's part of admitting and releasing a ray.
  virtual void owned(uint32_t) {}
  virtual void released(uint32_t) {}

 private:
  uint32_t owned_ = 0;
  uint16_t index_;
};

}  // namespace rtsim::model
