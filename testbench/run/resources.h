// Memory before the work: what a frame's per-pixel state will take, against what this process may
// still allocate (its address-space and data limits, its cgroup's limit, the machine's free
// memory). A command checks before it allocates its frame state, so that a frame too big for the
// machine or its limits is one clear error naming the estimate and the limit (exit 2), not an
// allocation failure halfway through.
#pragma once

#include "model/accelerator_config.h"
#include "scene/scene.h"

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

namespace rtsim {

struct MemoryNeed {
  std::string what;                                     // "a 16384x16384 frame"
  std::vector<std::pair<std::string, uint64_t>> parts;  // what takes it, bytes
  uint64_t total() const;
};

// `rtsim run`: the model's per-pixel state (frame buffer, its copy in the result, record order,
// records in simulated memory) and the host's (pixels, report planes), with the reference trace
// when `check`.
MemoryNeed run_memory_need(const model::AcceleratorConfig& hw, const Scene& scene, bool check);
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
