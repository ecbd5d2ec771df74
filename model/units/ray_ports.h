// The interfaces the ray-processing blocks offer one another besides ray FIFOs
// (model/sim/ray_fifo.h). Each is implemented by one block and reached through an sc_port that
// the accelerator binds once at elaboration, so a block can be tested with fakes bound instead.
#pragma once

#include "model/sim/time.h"
#include "model/units/ray_state.h"

#include <systemc>

#include <cstdint>

namespace rtsim::model {

// A sampled frame's unit of work (issue 38, docs/sampling.md): this many primary rays in issue
// order, or hit records in the culling unit's scan order.
inline constexpr uint32_t kBatchRays = 64;

// A TRV unit as the owner of its rays' slots: rays come back to it after a leaf or as a
// reflection, and leave it when they retire. (The router, model/units/ray_router.h, passes each
// call to the ray's owner.)
class RayOwner : public virtual sc_core::sc_interface {
 public:
  // The ray's leaf is done, its last test complete at `when`. The owner pops the ray's stack:
  // true when the ray goes on traversing there (the owner has taken it back), false when its
  // traversal is over (the caller sends it to shading).
  virtual bool leaf_done(uint32_t ray, Tick when) = 0;
  // The ray goes on as its reflection, a new traversal from `when`.
  virtual void reflect(uint32_t ray, Tick when) = 0;
  // The ray retired: its slot frees.
  virtual void release_slot(uint32_t ray) = 0;
};

// Where IST and shading hand rays back: to their owner, or out of the accelerator.
class RayReturn : public RayOwner {
 public:
  // The ray is finished (its type: shadow rays end the shadow phase, the others a pixel's
  // chain of rays) at `when`: its slots free and the phase controller is told.
  virtual void retire(uint32_t ray, RayType type, Tick when) = 0;
};

// Told of every retirement (the phase controller).
class RetireListener : public virtual sc_core::sc_interface {
 public:
  virtual void retired(RayType type, Tick when) = 0;
};

// The LVB updater (the paper's Fig. 5) on the IST's closest-hit path.
class LvbUpdate : public virtual sc_core::sc_interface {
 public:
  // A closest-hit update in a leaf whose LVB word is `leaf_lvb`: the word the ray keeps.
  virtual uint32_t closest_hit(uint32_t leaf_lvb) = 0;
};

// The shadow culling unit's intake in one phase: hits as soon as they are shaded.
class ShadedHits : public virtual sc_core::sc_interface {
 public:
  // The hit at frame entry `entry` is shaded; its record is ready at `ready`.
  virtual void hit_shaded(uint32_t entry, Tick ready) = 0;
};

// The ray generator as the phase controller drives it.
class PrimaryRays : public virtual sc_core::sc_interface {
 public:
  virtual bool finished() const = 0;  // every primary ray issued
  virtual uint64_t issued() const = 0;
  virtual void slot_freed(Tick now) = 0;  // a ray slot freed: it may issue again
};

// The shadow culling unit as the phase controller drives it.
class ShadowRays : public virtual sc_core::sc_interface {
 public:
  // Two phases: every frame entry, in order, from `now`; no more will come.
  virtual void scan_all(Tick now) = 0;
  // One phase: no more hits will come.
  virtual void close(Tick now) = 0;
  virtual void slot_freed(Tick now) = 0;  // a ray slot freed: it may emit again
  // Every (hit, light) pair decided.
  virtual bool finished() const = 0;
  virtual uint64_t generated() const = 0;  // shadow rays emitted so far
};

}  // namespace rtsim::model
