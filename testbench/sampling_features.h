// The functional pass of a sampled frame (issue 38, docs/sampling.md): the frame's primary rays in
// issue order, each walked by the reference tracer with the reads the accelerator's units would
// make (kernels/access_stream.h), replayed into the machine's caches as tags
// (testbench/functional_caches.h) and counted per batch of model::RayGenerator::kBatchRays rays:
// the auxiliary variables a sampled run's estimator regresses the batches' cycles on.
//
// The replay orders the reads by a rough clock, so that the caches see the rays interleaved about
// as the machine interleaves them, and the clock itself is a feature (a batch's replay cycles):
// - the generator deals a ray a cycle, in issue order, to the next traversal unit (round robin)
//   whose input FIFO (`fifo_depth`) has room; a unit walks `capacity` rays at once;
// - a ray's steps are its reads grouped as the units make them: a node (TRV), a leaf (LIST's
//   record and list lines, then IST's tests), the shading unit's two reads; each unit issues one
//   operation a cycle (LIST a line, IST a test, shading a hit ray every `shading interval`, the
//   larger of its two reads and its hit record's write over the memory link), and a step ends a
//   pipeline latency after its last read, whose line comes from the L1, the L2 (the link there
//   and back and the L2's hit latency) or DRAM (the memory link, tRCD + CL and the burst);
// - a ray that ends frees its slot for the next ray of its unit's FIFO.
// Not modelled: MSHRs, cache banks and ports, crossbar and DRAM queues and row misses, the
// shading unit's write buffer, the ray pool (which never binds below the traversal units'
// capacity and FIFOs). A ray's LIST, IST and shading units are those model/accelerator.cpp binds
// to its traversal unit.
#pragma once

#include "kernels/camera.h"
#include "kernels/reference_tracer.h"
#include "model/accelerator_config.h"
#include "testbench/functional_caches.h"

#include <cstdint>
#include <ostream>
#include <vector>

namespace rtsim {

struct BatchFeatures {
  uint64_t first_ray = 0;  // in issue order
  uint32_t rays = 0, hits = 0;
  // The replay's cycles from the batch's first ray's deal to the next batch's (the last: to the
  // last ray's end): its own estimate of the batch's cycles in a full run.
  uint64_t replay_cycles = 0;
  CacheCounts caches;  // the batch's rays' reads (whenever the replay makes them)
};

struct FeaturePassOptions {
  // Rays a traversal unit walks at once and holds in its FIFO; 0 = the hardware's (capacity,
  // fifo_depth of the traversal units' section).
  uint32_t capacity = 0, fifo_depth = 0;
};

// The primary rays of `camera` at width x height in the issue order of `cfg`, in batches.
std::vector<BatchFeatures> primary_batch_features(const ReferenceTracer& tracer,
                                                  const Camera& camera, int width, int height,
                                                  const model::AcceleratorConfig& cfg,
                                                  const FeaturePassOptions& options = {});

// The batches as CSV: batch, first_ray, rays, hits, replay_cycles, then per unit type (trv, list,
// ist, shading) its reads, L1 lines looked up, L1 misses and DRAM lines (L2 misses).
void write_features_csv(std::ostream& out, const std::vector<BatchFeatures>& batches);

}  // namespace rtsim
