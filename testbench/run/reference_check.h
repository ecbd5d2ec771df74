// rtsim run --check: the golden model's frame with the run's settings, and the model's frame
// compared with it, pixel for pixel and (a path-traced frame) radiance and bounce for bounce.
#pragma once

#include "kernels/reference_tracer.h"
#include "testbench/run/pipeline.h"
#include "testbench/run/run_config.h"
#include "testbench/run/simulate.h"

#include <nlohmann/json.hpp>

#include <cstdint>
#include <vector>

namespace rtsim {

TraceResult reference_frame(const PreparedScene& p, const RunSettings& run);

// Every pixel the model simulated (`simulated`: those of a sampled frame's windows; empty: every
// pixel) must match the reference's bit for bit; `mismatches` counts those that do not (and one
// for an image, culled counts, radiance or bounce counts that differ). report.json's
// reference_check.
nlohmann::json reference_check(const TraceResult& ref, const SimulatedFrame& r,
                               const std::vector<bool>& simulated, uint64_t& mismatches);

// --check's lines: a sampled frame's compares the pixels its windows simulated.
void print_check(const nlohmann::json& check);

}  // namespace rtsim
