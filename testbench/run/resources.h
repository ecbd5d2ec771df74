// Memory before the work: what a frame's per-pixel state will take, against what this process may
// still allocate (its address-space and data limits, its cgroup's limit, the machine's free
// memory). A command checks before it allocates its frame state, so that a frame too big for the
// machine or its limits is one clear error naming the estimate and the limit (exit 2), not an
// allocation failure halfway through.
#pragma once

#include "model/accelerator_config.h"
#include "scene/scene.h"
#include "testbench/run/pipeline.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace rtsim {

struct MemoryNeed {
  std::string what;                                     // "a 16384x16384 frame"
  std::vector<std::pair<std::string, uint64_t>> parts;  // what takes it, bytes, still to allocate
  // Allocated and freed again before the parts are allocated (the LVB computation's working set).
  std::vector<std::pair<std::string, uint64_t>> transient;
  // Allocated already when the check is made (the room is what is left beside them): part of the
  // run's peak, not of the check.
  std::vector<std::pair<std::string, uint64_t>> held;
  uint64_t peak_so_far = 0;  // the process's peak resident set at the check (a build's transients)
  uint64_t total() const;    // the most allocated at once after the check: max(transient, parts)
  uint64_t peak() const;     // the run's expected peak: max(peak so far, held + total())
};

// `rtsim run`: the model's per-pixel state (frame buffer, its copy in the result, record order,
// records in simulated memory) and the host's (pixels, report planes), with the reference trace
// when `check`.
MemoryNeed run_memory_need(const model::AcceleratorConfig& hw, const Scene& scene, bool check);
// Adds what the prepared scene holds (held: its triangles, its structure's nodes, leaves and
// triangle lists, the memory image, and `program_bytes`, the resident set before the scene was
// loaded), when `lvb` the LVB computation's working set (transient), and the peak so far.
void add_scene_memory(const PreparedScene& p, bool lvb, bool exact_lvb, uint64_t program_bytes,
                      MemoryNeed& need);
// The process's resident set now (VmRSS), in bytes; 0 where /proc is missing.
uint64_t resident_bytes();
// `rtsim render`: the reference tracer's pixels and the outputs made from them.
MemoryNeed render_memory_need(const Scene& scene);

struct MemoryRoom {
  uint64_t bytes = ~uint64_t(0);
  std::string limit;  // the limit that binds ("" when none is known)
};
// The least of: the address-space limit (ulimit -v) less the mapped size, the data limit less
// the data size, the cgroup's memory.max less its memory.current, and MemAvailable + SwapFree;
// the last two divided by $RTSIM_POINTS_AT_ONCE (a sweep's points running at once share them).
MemoryRoom memory_room();
inline constexpr const char* kPointsAtOnceEnv = "RTSIM_POINTS_AT_ONCE";

// InputError when the need exceeds the room: the estimate, its biggest parts, the limit, and that
// a smaller resolution reduces it.
void check_memory(const MemoryNeed& need, const MemoryRoom& room = memory_room());

// What the process is building, for the message of an allocation that fails anyway.
class Activity {
 public:
  explicit Activity(std::string what);
  ~Activity();
  Activity(const Activity&) = delete;
  Activity& operator=(const Activity&) = delete;
  static std::string current();  // "" outside any

 private:
  std::string saved_;
};

}  // namespace rtsim
