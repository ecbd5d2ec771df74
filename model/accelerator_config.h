// The accelerator's configuration: one plain struct per block, validated at the edge
// (AcceleratorConfig::validate), with the paper's and GPGPU-Sim's figures as defaults
// (configs/README.md gives each default's source).
#pragma once

#include "kernels/integrator.h"
#include "model/memory/cache.h"
#include "model/memory/client_caches.h"
#include "model/memory/crossbar.h"
#include "model/memory/dram_config.h"
#include "model/units/bvh_unit.h"
#include "model/units/phase_controller.h"
#include "model/units/ray_generator.h"
#include "model/units/ray_unit.h"
#include "model/units/shadow_culling_unit.h"

#include <cstdint>

namespace rtsim::model {

// The paper's machine, by name: the defaults of AcceleratorConfig, which configs/hw/tni-paper.yaml
// states again (a test checks the two agree). The paper's Table 2 and Section 4.1 give the units
// (24 TRV, 12 LIST, 12 IST; latencies 8, 2, 36) and the cache sizes and ways; the rest is ours,
// each figure's source in configs/README.md: single-ported L1s; L2s of 8 single-ported banks
// (GPGPU-Sim's GT200); MSHRs serving 4 requests each (GT200's L2 and texture L1); 64-byte lines;
// 32-byte flits, 8-byte headers, 2 cycles a hop, 8-flit input buffers.
namespace paper_machine {

inline CacheConfig l1(uint32_t kb, uint32_t ways) {
  CacheConfig c;
  c.size_bytes = kb * 1024;
  c.ways = ways;
  c.line_bytes = 64;
  c.hit_latency = 1;
  c.mshrs = 16;
  c.banks = 1;
  c.ports = 1;
  c.fill_port = FillPort::kShared;
  c.max_merge = 4;
  return c;
}

inline CacheConfig l2(uint32_t kb) {
  CacheConfig c = l1(kb, 2);
  c.hit_latency = 4;
  c.mshrs = 64;
  c.banks = 8;
  return c;
}

inline LinkConfig link() {
  LinkConfig l;
  l.latency = 2;
  l.bytes_per_cycle = 32;
  l.header_bytes = 8;
  l.buffer_flits = 8;
  return l;
}

// `count` units of `latency` cycles holding 16 rays, behind 16-entry FIFOs, fully pipelined.
inline UnitTypeConfig units(uint32_t count, uint32_t latency, CacheConfig l1, CacheConfig l2) {
  UnitTypeConfig u;
  u.count = count;
  u.latency = latency;
  u.capacity = 16;
  u.fifo_depth = 16;
  u.initiation_interval = 1;
  u.l1 = l1;
  u.l2 = l2;
  u.link = link();
  return u;
}

// One shading unit of 4 cycles holding 64 rays; its L1 sits on the IST L2 (no l2, link of its own).
inline UnitTypeConfig shading() {
  UnitTypeConfig u = units(1, 4, l1(16, 4), CacheConfig{});
  u.capacity = 64;
  u.fifo_depth = 64;
  u.link = LinkConfig{};
  return u;
}

}  // namespace paper_machine

struct AcceleratorConfig {
  double clock_ghz = 1.0;
  Structure structure = Structure::kKdTree;  // what the traversal units walk
  UnitTypeConfig trv = paper_machine::units(24, 8, paper_machine::l1(8, 2), paper_machine::l2(128));
  // The BVH units (structure: bvh) in the TRV units' place: their count, rays, FIFOs and caches,
  // so that a comparison changes the structure only; their latency is Vulkan-Sim's for an inner
  // node, also 8 (docs/bvh.md, "The BVH machine").
  UnitTypeConfig bvh = paper_machine::units(24, 8, paper_machine::l1(8, 2), paper_machine::l2(128));
  BvhWalkConfig bvh_walk;
  UnitTypeConfig list = paper_machine::units(12, 2, paper_machine::l1(4, 2), paper_machine::l2(32));
  UnitTypeConfig ist =
      paper_machine::units(12, 36, paper_machine::l1(16, 4), paper_machine::l2(128));
  UnitTypeConfig shading = paper_machine::shading();
  DramConfig dram = dram_preset("gddr3-gt200-1ghz");
  // The crossbar between the L2 banks and the DRAM channels
  LinkConfig memory_link = paper_machine::link();
  uint32_t ray_pool = 2048;            // rays in flight, all units together
  uint32_t raygen_rays_per_cycle = 1;  // the T&I engine's ray dispatcher: one ray per cycle
  CullingConfig culling;               // one hit record per cycle, read from memory in two phases
  bool write_records = true;           // shading units write each hit's record to the frame buffer
  // A shading unit's posted writes in flight: one per ray it holds (our choice; no source gives
  // one). 0: unbounded, the ideal.
  uint32_t write_buffer = 64;
  bool lvb_culling = true;
  // The energy file that prices the frame (model/energy/energy_config.h): an embedded node's name
  // or a path; "none": no pricing. 65 nm: GT200's node, whose memory system the machine takes.
  std::string energy = "65nm";
  RayOrder order = RayOrder::kTiles;
  Schedule schedule = Schedule::kTwoPhase;
  int tile = 8;
  uint64_t watchdog_cycles = 100000;  // stop when nothing moved for this long
  int reflection_depth = 0;           // mirror bounces for materials with reflectance > 0
  // The frame's integrator: Whitted's, or paths with `path`'s settings (kernels/integrator.h).
  Integrator integrator = Integrator::kWhitted;
  PathSettings path;

  // A frame's entries (model/units/frame_buffer.h): per path, one per bounce (1 + the reflection
  // depth of a Whitted frame, 1 + max_depth of a path-traced one); paths per pixel (spp, or 1);
  // and so hit records per pixel.
  int levels() const {
    return integrator == Integrator::kPath ? path.max_depth + 1 : reflection_depth + 1;
  }
  int paths_per_pixel() const { return integrator == Integrator::kPath ? path.spp : 1; }
  uint32_t entries_per_pixel() const { return uint32_t(levels() * paths_per_pixel()); }
  // Throws std::invalid_argument naming the field.
  void validate() const;
  // The memory as the accelerator uses it: `dram` with one L2 line per request.
  DramConfig memory_dram() const;
  // The traversal units' type: TRV's or the BVH units', by `structure`.
  const UnitTypeConfig& traversal() const { return structure == Structure::kBvh ? bvh : trv; }
};

// Every field of a unit type, once (model/sim/config_description.h): `has_l2` for TRV, LIST and IST
// (the shading units' L1s sit on the IST L2), `max_count` the most units of the type.
template <class V, class U>
DescribeOf<U, UnitTypeConfig> describe(V& v, U& u, bool has_l2, uint32_t max_count) {
  v.number("count", u.count, 1, max_count, "units", "units of this type");
  v.number("latency", u.latency, 1, 10000, "cycles",
           "pipeline latency; an operation issues every initiation_interval cycles");
  v.number("capacity", u.capacity, 1, 65536, "rays",
           "rays held (TRV: rays owned, its ray accumulation buffer)");
  v.number("fifo_depth", u.fifo_depth, 1, 65536, "rays", "the input FIFO");
  v.number("initiation_interval", u.initiation_interval, 1, 10000, "cycles",
           "cycles from one operation's issue to the next: 1 = pipelined, latency = one at a time");
  v.section(
      "l1", "each unit's L1", [&] { describe(v, u.l1); }, [&] { u.l1.validate(); });
  if (!has_l2) return;
  v.section(
      "l2", "the type's L2",
      [&] {
        describe(v, u.l2);
        v.choice("sharing", u.l2_sharing, {{"type", L2Sharing::kType}, {"unit", L2Sharing::kUnit}},
                 "one L2 for all units of the type, or a private L2 per unit");
      },
      [&] { u.l2.validate(); });
  v.section("link", "the crossbar between the type's L1s and its L2's banks",
            [&] { describe(v, u.link); });
}

// Every field a hardware file sets, once (model/sim/config_description.h). lvb_culling,
// reflection_depth, integrator and path come from the run settings, not from the hardware file.
template <class V, class C>
DescribeOf<C, AcceleratorConfig> describe(V& v, C& c) {
  v.number("clock_ghz", c.clock_ghz, 0.01, 100, "GHz", "the accelerator clock");
  v.number("ray_pool", c.ray_pool, 1, 1 << 24, "rays", "rays in flight in the whole accelerator");
  v.choice("order", c.order, {{"tiles", RayOrder::kTiles}, {"scanline", RayOrder::kScanline}},
           "primary ray order");
  v.number("tile", c.tile, 1, 4096, "pixels", "tile side");
  v.choice("schedule", c.schedule,
           {{"two-phase", Schedule::kTwoPhase}, {"one-phase", Schedule::kOnePhase}},
           "all primary rays, then all shadow rays (the paper's Table 6); or shadow rays as soon "
           "as their hit is shaded");
  v.text("energy", c.energy,
         "the energy file pricing the frame: a node of configs/energy/ (65nm, 45nm) or a path to "
         "one; none: no energy figures");
  v.number("watchdog_cycles", c.watchdog_cycles, 1000, double(uint64_t(1) << 40), "cycles",
           "an error naming the stuck FIFOs and units after this long without progress");
  v.choice("structure", c.structure, {{"kdtree", Structure::kKdTree}, {"bvh", Structure::kBvh}},
           "what the traversal units walk: the kd-tree (TRV units, the paper's) or a BVH (BVH "
           "units); the image must hold it");
  v.section("trv", "the kd-tree traversal units (structure: kdtree)",
            [&] { describe(v, c.trv, true, 1024); });
  v.section("bvh", "the BVH traversal units (structure: bvh)", [&] {
    describe(v, c.bvh, true, 1024);
    describe(v, c.bvh_walk);
  });
  v.section("list", "the primitive-list units", [&] { describe(v, c.list, true, 1024); });
  v.section("ist", "the intersection units", [&] { describe(v, c.ist, true, 1024); });
  v.section("shading",
            "the shading units (the rays of TRV unit i finish in shading unit i x count / trv)",
            [&] {
              describe(v, c.shading, false, 64);
              v.flag("write_records", c.write_records,
                     "every shaded hit's 64-byte record is written to the frame buffer in DRAM");
              v.number("write_buffer", c.write_buffer, 0, 1 << 20, "lines",
                       "a unit's posted writes in flight; full, the unit waits for an "
                       "acknowledgement; 0: unbounded (ideal)");
            });
  v.section("raygen", "the ray generator", [&] {
    v.number("rays_per_cycle", c.raygen_rays_per_cycle, 1, 64, "rays",
             "primary rays issued per cycle at most");
  });
  v.section("culling", "the shadow culling unit", [&] { describe(v, c.culling); });
  v.section("memory_link", "the crossbar between the L2 banks and the memory channels",
            [&] { describe(v, c.memory_link); });
  v.section("dram", "the memory: GDDR3 (the paper's), GDDR5 or GDDR6 by preset", [&] {
    v.preset("preset", c.dram, "the preset the section starts from (docs/dram.md)");
    describe(v, c.dram);
  });
}

}  // namespace rtsim::model
