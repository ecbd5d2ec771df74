// A ray in flight in the model, in a pool of slots indexed by a 32-bit id (FIFOs and ports carry
// ids). Its state is split by who writes it: what the ray is (its creator's), and one part per
// stage on its path, each written by that stage alone (the others may read it). A stage sets up
// its own part when the ray enters it; the pool sets up a new ray's result (no hit yet).
#pragma once

#include "kernels/access_stream.h"
#include "kernels/bvh_traversal.h"
#include "kernels/shading.h"
#include "kernels/traversal.h"
#include "model/sim/time.h"

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace rtsim::model {

// A path's rays after its primary are reflections (a mirror) or bounces (diffuse); its shadow
// rays are its next-event rays.
enum class RayType : uint8_t { kPrimary, kReflection, kShadow, kBounce };
inline constexpr size_t kRayTypes = 4;
// Per ray type, a traversal unit's node fetches (<counter>_<name>: node_fetches_shadow): the split
// by which a frame's walk-driven energy is shared among its ray types (model/energy/).
using PerRayType = std::array<uint64_t, kRayTypes>;
inline const char* ray_type_name(size_t type) {
  static constexpr const char* kNames[kRayTypes] = {"primary", "reflection", "shadow", "bounce"};
  return kNames[type];
}
template <class V>
void describe_by_ray_type(V& v, const char* counter, const PerRayType& n, const char* what) {
  for (size_t t = 0; t < kRayTypes; ++t)
    v.counter(std::string(counter) + "_" + ray_type_name(t), n[t], "count",
              std::string(what) + " for " + ray_type_name(t) + " rays");
}

// What a ray is, written once by the block that makes it: the ray generator (primary rays), the
// shadow culling unit (shadow rays) or a shading unit (a reflection or bounce, in its ray's slot).
struct RayInfo {
  Ray ray;
  RayType type = RayType::kPrimary;
  // Its frame entry (model/units/frame_buffer.h): a primary, reflection or bounce ray's, its
  // pixel's at its bounce on its path; a shadow ray's, the hit it tests. (A primary ray's entry
  // is its pixel on its path.)
  uint32_t entry = 0;
  uint8_t depth = 0;     // bounces so far (a shadow ray: its hit's)
  uint8_t light = 0;     // shadow rays: which light
  uint16_t sample = 0;   // shadow rays: which of the light's samples
  Vec3 throughput{1.f};  // a path's ray: the weight of the light it brings back
  Tick born = 0;         // when it was made (its time in flight ends when it is shaded)
};

// The stages that hold a ray while it waits for memory, each with its own entry below.
enum Stage : uint8_t { kTrvStage, kListStage, kIstStage, kShadingStage, kStages };

// The stage whose units read a walk's record of kind `k` (kernels/access_stream.h): a node the
// traversal stage, a leaf's record and list LIST, a triangle IST, a hit's records the shading
// stage; and the light records, which the culling unit reads through the shading stage's L1s
// (or one beside them: culling.l1), the shading stage.
constexpr Stage stage_of(WalkRead k) {
  switch (k) {
    case WalkRead::kNode: return kTrvStage;
    case WalkRead::kLeaf:
    case WalkRead::kPrims: return kListStage;
    case WalkRead::kTriangle: return kIstStage;
    case WalkRead::kShade:
    case WalkRead::kLight: break;
  }
  return kShadingStage;
}

// A unit's hold on a ray waiting for memory: its entry in the unit's ray accumulation buffer.
// Empty again whenever the ray leaves the unit.
struct FetchState {
  uint32_t waiting_lines = 0;  // lines of a straddling record still in flight
  // The record the ray waited for has arrived: its next operation reads it without fetching
  // again (re-fetching could miss forever when the line is evicted before the ray issues again).
  bool fill_ready = false;
  bool reading = false;  // that operation reads `bytes`, not the L1
  // The entry holds the data of the (at most two) L1 lines its record lies on: a line as it
  // arrived, or, of a record on two lines, as it was when its time was known. So the ray reads
  // what the fill brought even when the L1 has evicted the line before the ray issues again.
  uint64_t lines[2] = {~uint64_t(0), ~uint64_t(0)};
  std::vector<uint8_t> bytes;  // two L1 lines
};

// The traversal stage: the walk through the kd-tree (TRV) or the BVH (the BVH unit), and which
// unit owns the ray's slot.
struct TrvState {
  uint16_t owner = 0;
  bool started = false;  // traversal_begin done
  // BVH unit only: the ray's stack slot in its unit, the stack entries held on chip (the rest
  // are spilled), and whether its next operation hands a popped leaf to LIST.
  uint16_t stack_slot = 0;
  uint16_t on_chip = 0;
  bool leaf_next = false;
  uint8_t node_chunk = 0;  // the part of a wide node its next operation fetches
  uint32_t steps = 0;      // nodes fetched by this walk: a legal one fetches each at most once
  BvhTraversalState bvh;   // its stack lives in the BVH unit
  TraversalState walk;     // last: its stack ends the ray's state
  // What the leaf's intersection tests read, whichever structure the ray walks.
  const RayWalk& leaf_walk(bool bvh_walk) const {
    return bvh_walk ? static_cast<const RayWalk&>(bvh) : walk;
  }
};

// LIST: the current leaf's record and primitive list.
struct ListState {
  uint32_t leaf_lvb = 0;  // the leaf's LVB word
  uint32_t prim_offset = 0, prim_count = 0, prims_fetched = 0;
  std::vector<uint32_t> tris;
};

// IST (with its LVB updater): the closest hit so far and the current leaf's tests.
struct IstState {
  TraversalResult result;
  uint32_t lvb = 0;  // the LVB word of the leaf holding the closest hit
  uint32_t tests_issued = 0;
  Ray leaf_ray;
  Tick leaf_done_at = 0;  // completion of the latest test issued
};

// Shading: the hit's surface, read from its triangle, then its material.
struct ShadingState {
  enum class Next : uint8_t { kTriangle, kMaterial };  // the record its next operation reads
  Next next = Next::kTriangle;
  uint32_t material = 0;
  SurfacePoint surface;
};

// Laid out for the host's caches: a 2048-ray pool outgrows them, and each step of a ray touches
// its state at a random place in the pool. What every stage reads comes first, packed into few
// lines; the traversal stack, of which a step reads only the top, comes last.
struct alignas(64) RayState {
  RayInfo info;
  // Set by the stage that found the image unreadable (model/units/image_faults.h): the ray's
  // walk is over and shading retires it as a miss.
  bool faulted = false;
  IstState ist;
  ListState list;
  ShadingState shading;
  FetchState fetch[kStages];  // by stage: each ray unit's own entry, written by that unit alone
  TrvState trv;               // last
};

class RayPool {
 public:
  explicit RayPool(uint32_t capacity) : rays_(capacity) { begin_frame(); }
  // Every slot free, in the order of the first frame (ids 0, 1, ... handed out first): a frame's
  // ray ids, and the orders that break ties by id, do not depend on the frames before it.
  void begin_frame() {
    free_.clear();
    free_.reserve(rays_.size());
    for (uint32_t i = uint32_t(rays_.size()); i-- > 0;) free_.push_back(i);
  }
  bool full() const { return free_.empty(); }
  uint32_t in_flight() const { return uint32_t(rays_.size() - free_.size()); }
  // A new ray in a free slot.
  uint32_t create(const RayInfo& info) {
    const uint32_t id = free_.back();
    free_.pop_back();
    renew(id, info);
    return id;
  }
  // From now on slot `id` holds a new ray (a reflection goes on in its ray's slot).
  void renew(uint32_t id, const RayInfo& info) {
    RayState& r = rays_[id];
    r.info = info;
    r.faulted = false;
    r.ist.result = traversal_result_begin(info.ray);
    r.ist.lvb = 0;
  }
  void release(uint32_t id) { free_.push_back(id); }
  RayState& operator[](uint32_t id) { return rays_[id]; }
  const RayState& operator[](uint32_t id) const { return rays_[id]; }
  uint32_t capacity() const { return uint32_t(rays_.size()); }

 private:
  std::vector<RayState> rays_;
  std::vector<uint32_t> free_;
};

}  // namespace rtsim::model
