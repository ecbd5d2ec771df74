// The functional pass of a sampled frame (docs/sampling.md), the accelerator's functional mode: the
// frame's primary rays in issue order, each walked by the reference tracer with the records it
// reads (kernels/access_stream.h), replayed into the machine's caches as tags
// (model/functional/functional_machine.h) and counted per batch of model::RayGenerator::kBatchRays
// rays; then, in two phases, the shadow phase: the culling unit's scan over the record slots
// (primary issue order) and the shadow rays it emits, through the same caches from where the
// primary phase left them, counted per batch of kBatchRays record slots (the model's shadow
// batches). These are the auxiliary variables a sampled run's estimator regresses the batches'
// cycles on.
//
// The replay orders the reads by a rough clock, so that the caches see the rays interleaved about
// as the machine interleaves them, and the clock itself is a feature (a batch's replay cycles):
// - the generator deals a ray a cycle, in issue order, to the next traversal unit (round robin)
//   whose input FIFO (`fifo_depth`) has room; a unit walks `capacity` rays at once;
// - a ray's steps are its reads grouped as the units make them: a node (TRV), a leaf (LIST's
//   record and list lines, then IST's tests), the shading unit's two reads; each unit issues one
//   operation a cycle (a traversal unit a node's line, LIST a line, IST a test, shading a hit
//   ray every `shading interval`, the larger of its two reads and its hit record's write over
//   the memory link), and a step ends a pipeline latency after its last read, whose line comes
//   from the L1, the L2 (the link there and back and the L2's hit latency) or DRAM (the memory
//   link, tRCD + CL and the burst); a line from the L2 takes its bank's port of the link back to
//   the L1s for its flits, a line from DRAM its bank's port of the memory link first, so lines
//   queue at a busy bank (a BVH's wide nodes make these ports the shadow phase's bottleneck);
// - a ray that ends frees its slot for the next ray of its unit's FIFO;
// - the shadow phase begins when the last primary ray ends. The culling unit requests the record
//   slots in order, one a cycle, at most `culling.prefetch` ahead of the slot it decides; a
//   record comes a DRAM read later, and the records come no faster than its port takes a line
//   (the memory link's flits). It takes a record a cycle; a hit's lights whose LVB bit is 0 are
//   culled within the cycle, every other light's samples are emitted one a cycle, each to the
//   next traversal unit with room, after the light's record (read once per hit and light through
//   shading unit 0's L1 or the culling unit's own, held for its samples) is in; a shadow ray walks
//   TRV, LIST and IST (any hit) and retires through its shading unit in one issue slot, reading
//   nothing.
// Not modelled: MSHRs, the L1s' banks, the L2s' lookup ports, the crossbars' other ports and
// flow control, DRAM queues and row misses, the shading unit's write buffer, the ray pool (which
// never binds below the traversal units' capacity and FIFOs), the culling unit's and shading unit
// 0's shared L1 port. A ray's LIST, IST and shading units are those model::ray_route gives, the
// path model/accelerator.cpp binds. Mirror bounces (run.reflections) are not followed: the pass
// covers the primary rays and their shadow rays.
#pragma once

#include "kernels/camera.h"
#include "kernels/memory_image.h"
#include "model/accelerator.h"
#include "model/accelerator_config.h"
#include "model/functional/functional_machine.h"

#include <atomic>
#include <cstdint>
#include <ostream>
#include <vector>

namespace rtsim::model {

struct BatchFeatures {
  uint64_t first_ray = 0;  // in issue order (shadow: the first record slot)
  // Primary: the batch's rays and their hits. Shadow: the shadow rays emitted for the batch's
  // record slots, the slots that hold a hit, the shadow rays culled (each sample of a culled
  // light) and those found occluded.
  uint32_t rays = 0, hits = 0, culled = 0, occluded = 0;
  // The replay's cycles from the batch's first ray's deal to the next batch's (the last: to the
  // last ray's end): its own estimate of the batch's cycles in a full run.
  uint64_t replay_cycles = 0;
  CacheCounts caches;  // the batch's rays' reads (whenever the replay makes them)
};

struct FeaturePassOptions {
  // Rays a traversal unit walks at once and holds in its FIFO; 0 = the hardware's (capacity,
  // fifo_depth of the traversal units' section).
  uint32_t capacity = 0, fifo_depth = 0;
  bool culling = true;  // the shadow phase's LVB culling (run.lvb)
  // The shadow phase on one batch of record slots in `shadow_stride` alone (the others' records
  // are passed over in no time and emit nothing): a cheaper, sparser auxiliary. 1: every batch.
  uint32_t shadow_stride = 1;
  // The walks traced ahead on a thread of their own (the same features, less wall time): from
  // the first walk, or from when `trace_ahead_from` turns true (a sampled run's second core
  // comes free).
  bool trace_ahead = false;
  const std::atomic<bool>* trace_ahead_from = nullptr;
};

// Both phases' batches, and the pass's host seconds in each.
struct FrameFeatures {
  std::vector<BatchFeatures> primary, shadow;  // shadow: empty without lights or a shadow pass
  double primary_seconds = 0, shadow_seconds = 0;
};

// The primary rays of `camera` at width x height in the issue order of `cfg`, in batches.
std::vector<BatchFeatures> primary_batch_features(const MemoryImage& image, const Camera& camera,
                                                  int width, int height,
                                                  const AcceleratorConfig& cfg,
                                                  const FeaturePassOptions& options = {});

// The frame's primary batches and, when `shadows` (a two-phase frame with lights), its shadow
// batches: the image as the run has it (its leaves' LVB words set when culling).
FrameFeatures frame_batch_features(const MemoryImage& image, const Camera& camera, int width,
                                   int height, const AcceleratorConfig& cfg,
                                   const FeaturePassOptions& options = {}, bool shadows = true);

// The strata's auxiliary (docs/sampling.md): per batch of kBatchRays primary rays in the issue
// order of `cfg`, the reference tracer's walk steps (inner nodes, leaves and triangle tests:
// TraversalCounters) of one ray in `stride` and of every shadow ray of its hit, as if culling
// were off. Counted in a fraction of the pass's time (no caches, no clock), the same for every
// culling setting of a frame: Neyman's strata are cut on it before the simulation, and a frame's
// runs with culling on and off share their plan.
std::vector<double> batch_walk_steps(const MemoryImage& image, const Camera& camera, int width,
                                     int height, const AcceleratorConfig& cfg, uint32_t stride = 1);

// The batches as CSV: phase (primary, shadow), batch, first_ray, rays, hits, culled, occluded,
// replay_cycles, then per stage (traversal, list, ist, shading: the report's stage names) its
// reads, L1 lines looked up, L1 misses and DRAM lines (L2 misses); a shadow batch's shading reads
// are the culling unit's light reads.
void write_features_csv(std::ostream& out, const FrameFeatures& features);

// The functional warming of a sampled frame (WarmSource, model/accelerator.h): before a window,
// the reads of the `rays` primary rays issued before it, walked by the reference tracer in issue
// order, each for the traversal unit the generator deals it to in turn. `image` must outlive the
// source.
WarmSource primary_warming(const MemoryImage& image, const Camera& camera, int width, int height,
                           const AcceleratorConfig& cfg, uint64_t rays);

}  // namespace rtsim::model
