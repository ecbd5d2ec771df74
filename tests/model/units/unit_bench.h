// A bench for testing one unit of the model on its own
// (tests/model/units/test_{trv,list,ist,shading}_unit.cpp, test_lvb_updater.cpp): an sc_module
// holding what an Accelerator gives its units, built for real but small and with round timing. Its
// calendar, ray pool and ModelContext; a real MemorySystem built from the accelerator's topology
// (one unit per type, ideal links and banks, so no crossbar hop and no port wait) whose TLM-2.0
// socket is bound to a FixedLatencyMemory holding the image, and to which a test attaches each
// unit's mem_side where the accelerator would; a FrameBuffer; and fakes to bind the unit's ports
// to: the bench itself stands for the router (RayReturn: it records what the units hand back, and
// pops a ray's stack after a leaf as its TRV unit would), a FIFO `done` for the shading units'
// inputs. The unit under test is built by the test inside the bench's constructor (so the bench's
// scope names it), bound there, and fed through its input FIFO. Several benches run side by side in
// one simulation, each with its own calendar.
//
// Timing (docs/model-design.md, "Memory accesses"): a hit costs the level's hit latency, a miss
// its tag check plus the delivery time of the level below, so with these settings
//   L1 hit          = kL1Hit                     cycles
//   L1 miss, L2 hit = kL1Hit + kL2Hit            cycles
//   cold line       = kL1Hit + kL2Hit + kMemory  cycles (kMiss: the memory answers kMemory - 0.5
//                     ns later, and the port takes the response at the next edge at 1 GHz)
#pragma once

#include "examples/tlm_memory/fixed_latency_memory.h"
#include "kernels/kdtree.h"
#include "kernels/memory_image.h"
#include "model/accelerator_config.h"
#include "model/accelerator_topology.h"
#include "model/memory/memory_system.h"
#include "model/sim/calendar.h"
#include "model/sim/ray_fifo.h"
#include "model/units/frame_buffer.h"
#include "model/units/hit_record.h"
#include "model/units/model_context.h"
#include "model/units/ray_ports.h"

#include <systemc>

#include <algorithm>
#include <utility>
#include <vector>

namespace rtsim::model::bench {

constexpr Tick kCycle = 1000;  // 1 GHz, in ps
// Distinct latencies, so that a closed form using the wrong one fails.
constexpr uint64_t kL1Hit = 1, kL2Hit = 4, kMemory = 20;
constexpr uint64_t kMiss = kL1Hit + kL2Hit + kMemory;  // a line no cache holds yet
constexpr uint64_t kEndCycle = 5000;  // accounting closes here, after every scenario

inline Tick at(uint64_t cycle) { return cycle * kCycle; }
inline uint64_t cycle_of(Tick t) { return t / kCycle; }

// The paper's units, one of each, with ideal links (latency 0, unlimited width) and ideal banks.
inline AcceleratorConfig config() {
  AcceleratorConfig c;
  for (UnitTypeConfig* u : {&c.trv, &c.list, &c.ist, &c.shading}) {
    u->count = 1;
    u->l1.hit_latency = uint32_t(kL1Hit);
    u->l1.ports = 0;
    u->l2.hit_latency = uint32_t(kL2Hit);
    u->l2.ports = 0;
    u->link = {0, 0, 0};
  }
  c.memory_link = {0, 0, 0};
  return c;
}

struct WrittenLine {
  uint64_t line;
  std::vector<uint8_t> bytes;
  Tick when;
};

class Bench : public sc_core::sc_module, public RayReturn {
 public:
  // The frame buffer's records follow the image, one 64-byte line each, `frame_entries` of them.
  Bench(sc_core::sc_module_name name, const MemoryImage& image, const AcceleratorConfig& config,
        uint32_t frame_entries = 16)
      : sc_core::sc_module(name),
        cfg(config),
        calendar("calendar"),
        pool(64),
        topology(memory_topology(cfg, MemoryTarget::kApproximatelyTimed)),
        memory(topology.memory, Clock(), calendar),
        ram("ram", memory_bytes(image, frame_entries),
            sc_core::sc_time(double(kMemory) - 0.5, sc_core::SC_NS)),
        done("done", 64, nullptr) {
    cfg.validate();
    ctx.calendar = &calendar;
    ctx.pool = &pool;
    ctx.header = image.header();
    ctx.clock = Clock();
    ctx.abs_eps = 1e-6f * ctx.header.bounds.diagonal();  // the reference tracer's constants
    ctx.shadow_offset = 1e-5f * ctx.header.bounds.diagonal();
    for (uint32_t l = 0; l < ctx.header.light_count; ++l)
      ctx.light_samples.push_back(image.light(l).samples);
    memory.interconnect().port().socket.bind(ram.socket);
    frame.width = int(frame_entries);
    frame.height = 1;
    frame.allocate(ctx.light_samples);
    records.base = records_base(image);
    records.stride = kHitRecordBytes;
    SC_THREAD(feeder);
  }
  SC_HAS_PROCESS(Bench);

  // RayReturn: what IST and shading hand back is recorded (returned: rays that go on; retired,
  // with retirements). After a leaf, the ray's stack is popped as its TRV unit would.
  bool leaf_done(uint32_t ray, Tick when) override {
    RayState& r = pool[ray];
    if (traversal_pop(r.trv.walk, r.ist.result) != TraversalStep::kFetchNode) return false;
    returned.push_back({ray, when});
    return true;
  }
  void reflect(uint32_t ray, Tick when) override { returned.push_back({ray, when}); }
  void release_slot(uint32_t) override {}
  void retire(uint32_t ray, RayType type, Tick when) override {
    retired.push_back(ray);
    retirements.push_back({type, when});
    pool.release(ray);
  }

  // Binds a unit's mem_side to where the topology says the caches of unit `index` of the type
  // at `stage` reach.
  template <class Port>
  void attach(Port& mem_side, Stage stage, uint32_t index) {
    mem_side.bind(reach(memory, topology.units[stage][index]));
  }

  // A new ray in the pool.
  uint32_t add_ray(const Ray& ray, RayType type = RayType::kPrimary, uint32_t entry = 0) {
    RayInfo info;
    info.ray = ray;
    info.type = type;
    info.entry = entry;
    return pool.create(info);
  }

  // Pushes `ray` into `fifo` at `cycle`, from a thread, as a producer would. (A ray pushed early
  // with a later ready time would sit in the FIFO, and a unit counts a non-empty input FIFO as
  // held work: stalled, not idle, until it shows.) Call before sc_start, in time order per FIFO.
  void feed(RayFifo* fifo, uint32_t ray, uint64_t cycle) { feeds_.push_back({fifo, ray, cycle}); }

  // Empties `fifo`: (ray, the cycle it became visible), in order.
  static std::vector<std::pair<uint32_t, uint64_t>> drain(RayFifo& fifo) {
    std::vector<std::pair<uint32_t, uint64_t>> out;
    while (!fifo.empty()) {
      const uint64_t c = cycle_of(fifo.head_ready());
      out.push_back({fifo.pop(at(kEndCycle)), c});
    }
    return out;
  }

  static uint64_t records_base(const MemoryImage& image) {
    return (image.bytes().size() + 4095) / 4096 * 4096;
  }

  AcceleratorConfig cfg;
  Calendar calendar;
  RayPool pool;
  ModelContext ctx;
  MemoryTopology topology;
  MemorySystem memory;
  example::FixedLatencyMemory ram;
  RayFifo done;  // the shading unit's input, as TRV and IST see it
  FrameBuffer frame;
  HitRecordRegion records;
  std::vector<std::pair<uint32_t, Tick>> returned;
  std::vector<uint32_t> retired;
  std::vector<std::pair<RayType, Tick>> retirements;

 private:
  struct Feed {
    RayFifo* fifo;
    uint32_t ray;
    uint64_t cycle;
  };
  void feeder() {
    std::stable_sort(feeds_.begin(), feeds_.end(),
                     [](const Feed& a, const Feed& b) { return a.cycle < b.cycle; });
    for (const Feed& f : feeds_) {
      const Tick now = Tick(sc_core::sc_time_stamp().value());
      if (at(f.cycle) > now) wait(sc_core::sc_time::from_value(at(f.cycle) - now));
      f.fifo->push(f.ray, at(f.cycle), at(f.cycle));
    }
  }
  std::vector<Feed> feeds_;

  static std::vector<uint8_t> memory_bytes(const MemoryImage& image, uint32_t entries) {
    std::vector<uint8_t> b(image.bytes());
    b.resize(records_base(image) + uint64_t(entries) * kHitRecordBytes, 0);
    return b;
  }
};

// The host's walk of the ray to its first non-empty leaf over the image's nodes (what TRV would
// do): sets up a ray for LIST or IST. False if the ray reaches no leaf.
inline bool walk_to_leaf(const MemoryImage& image, RayState& r, float abs_eps,
                         bool any_hit = false) {
  TraversalState& walk = r.trv.walk;
  if (!traversal_begin(walk, r.info.ray, any_hit, image.header().bounds, abs_eps)) return false;
  r.trv.started = true;
  for (;;) {
    const TraversalStep step = traversal_node(walk, r.ist.result, image.node(walk.node));
    if (step == TraversalStep::kLeaf) return true;
    if (step == TraversalStep::kDone || step == TraversalStep::kFault) return false;
  }
}

// The leaf a point falls in, by descending the tree's splits (no ray, no traversal code).
inline uint32_t locate_leaf(const KdTree& tree, const Vec3& p, uint32_t* depth = nullptr) {
  uint32_t node = 0, d = 0;
  while (!tree.nodes[node].is_leaf()) {
    const KdNode& n = tree.nodes[node];
    node = p[n.axis()] < n.split() ? node + 1 : n.above_child();
    ++d;
  }
  if (depth) *depth = d;
  return tree.nodes[node].leaf_index();
}

// Four small triangles side by side in the plane z = -5; rays go straight down -z from z = 0.
inline Scene row_of_triangles() {
  Scene s;
  s.add_material(Material{});
  for (int k = 0; k < 4; ++k) {
    const float x = 4.f * float(k);
    s.triangles.push_back(
        {Vec3(x - 1.f, -1.f, -5.f), Vec3(x + 1.f, -1.f, -5.f), Vec3(x, 1.f, -5.f), 0});
  }
  return s;
}

inline Ray down_at(float x) { return {Vec3(x, 0.f, 0.f), Vec3(0.f, 0.f, -1.f)}; }

}  // namespace rtsim::model::bench
