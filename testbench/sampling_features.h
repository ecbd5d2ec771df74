// The functional pass of a sampled frame (issue 38, docs/sampling.md): the frame's primary rays in
// issue order, each walked by the reference tracer with the reads the accelerator's units would
// make (kernels/access_stream.h), replayed into the machine's caches as tags
// (testbench/functional_caches.h) and counted per batch of model::RayGenerator::kBatchRays rays:
// the auxiliary variables a sampled run's estimator regresses the batches' cycles on.
//
// The replay approximates how the machine interleaves its rays:
// - a ray is dealt, in issue order, to the next traversal unit (round robin, as the generator's
//   dealer) whose input FIFO has room (`fifo_depth`); the dealer keeps every FIFO full, as it does
//   when the machine, not the generator, is the bottleneck (one ray a cycle);
// - a traversal unit walks up to `capacity` rays at once; a walk starts when a slot is free;
// - in a round every walking ray makes its next read, the units in index order: the rays of a unit
//   move at one pace whatever their reads cost (no latencies, no misses' waits), and a ray's reads
//   at LIST, IST and shading come in its walk's order, from the units model/accelerator.cpp binds
//   to its traversal unit.
// The ray pool's limit (`ray_pool`) never binds below the traversal units' capacity and FIFOs,
// which hold the rays that LIST, IST and shading work on; it is not modelled.
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
  // The replay's rounds from the batch's first ray's deal to the next batch's: a clock that
  // counts every read as one step of its ray.
  uint64_t rounds = 0;
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

// The batches as CSV: batch, first_ray, rays, hits, rounds, then per unit type (trv, list, ist,
// shading) its reads, L1 lines looked up, L1 misses and DRAM lines (L2 misses).
void write_features_csv(std::ostream& out, const std::vector<BatchFeatures>& batches);

}  // namespace rtsim
