// The accelerator's netlist (model/accelerator.cpp builds it, model/accelerator_frames.cpp runs
// its frames): every block of one accelerator, built in the accelerator's scope (so each is its
// child) in the order a ray meets them, then connected: every hop of a ray is a port bound once.
// Private to the accelerator: a platform needs only model/accelerator.h.
#pragma once

#include "model/accelerator.h"
#include "model/accelerator_topology.h"
#include "model/accelerator_units.h"
#include "model/device/device_driver.h"
#include "model/memory/dram.h"
#include "model/memory/memory_system.h"
#include "model/memory/tlm_checker.h"
#include "model/sim/calendar.h"
#include "model/sim/periodic_probe.h"
#include "model/sim/report.h"
#include "model/sim/watchdog.h"
#include "model/units/bvh_unit.h"
#include "model/units/ist_unit.h"
#include "model/units/list_unit.h"
#include "model/units/lvb_updater.h"
#include "model/units/phase_controller.h"
#include "model/units/ray_router.h"
#include "model/units/shading_unit.h"
#include "model/units/shadow_culling_unit.h"
#include "model/units/trv_unit.h"

#include <algorithm>

namespace rtsim::model {

struct Accelerator::Netlist : FrameEngine, CacheWarmer {
  Netlist(Accelerator& top, const AcceleratorConfig& cfg, const SimulationHooks& hooks,
          MemoryTarget memory_target, const MemoryImage* image, uint64_t image_memory_bytes);

  // FrameEngine: the registers start a frame, or reset the device.
  void begin_frame(const FrameProgram& program, Tick at) override;
  void reset() override { invalidate_caches(); }
  // Empties every cache: the units' own and the shared L2s.
  void invalidate_caches();
  // Closes the time-weighted statistics at `at` and starts every counter again from 0.
  void reset_stats(Tick at);
  // The frame is over once every ray retired and its records' writes are answered.
  void check_frame_end();
  // Writes out the VCD, the memory trace and the DRAM commands, each under its name.
  void close_traces();
  // After the frame: the traces closed, the time-weighted statistics closed at its end.
  void collect();
  // CacheWarmer (model/accelerator_warming.cpp).
  void read(WalkRead kind, uint32_t traversal, uint64_t addr, uint32_t bytes) override;
  uint32_t traversal_units() const override { return cfg.traversal().count; }
  // One line of a record into `cache` and, missing there, into `below` (may be null).
  void warm_line(Cache& cache, Cache* below, uint64_t addr);

  void build_memory(const MemoryImage* image, uint64_t image_memory_bytes,
                    MemoryTarget memory_target);

  void build_units();
  void bind_ray_path();
  void bind_control_and_memory();
  void declare_order();
  void build_observers();

  // A ray unit as its own type (the table's factory built it so).
  template <class U>
  U& unit(Stage stage, uint32_t i) const {
    return static_cast<U&>(*units[stage][i]);
  }
  TraversalUnit& traversal(uint32_t i) const { return unit<TraversalUnit>(kTrvStage, i); }
  ListUnit& list(uint32_t i) const { return unit<ListUnit>(kListStage, i); }
  IstUnit& ist(uint32_t i) const { return unit<IstUnit>(kIstStage, i); }
  ShadingUnit& shading(uint32_t i) const { return unit<ShadingUnit>(kShadingStage, i); }

  bool pending() const {
    return pool.in_flight() > 0 || !generator->finished() || !culling->finished();
  }
  uint64_t progress_count() const;
  std::string describe_stall() const;
  void report_progress(Tick now) const;
  void register_stats();
  void register_work_totals();
  void register_unit_totals(const std::string& key,
                            const std::vector<std::unique_ptr<RayUnit>>& units);
  // The socket towards memory: the protocol checker's, when there is one.
  tlm::tlm_initiator_socket<>& memory_socket() {
    if (checker) return checker->initiator_socket;
    return memory->interconnect().port().socket;
  }

  Accelerator& top;
  AcceleratorConfig cfg;
  FrameJob job;  // the frame running or last run
  RayPool pool;
  ImageFaultStats faults;      // the statistics' window's (SimulationHooks::statistics)
  uint64_t faults_before = 0;  // their total when the frame running or last run began
  ModelContext ctx;
  FrameBuffer frame;
  HitRecordRegion records;
  SimulationHooks hooks;
  Calendar calendar;
  std::unique_ptr<ControlRegisters> registers;
  std::unique_ptr<Dram> dram;
  MemoryTopology topology;
  std::unique_ptr<MemorySystem> memory;
  std::unique_ptr<TlmChecker> checker;  // between the memory port and the memory, if asked
  std::unique_ptr<RayGenerator> generator;
  // By type (stage, unit_types), then index; as their own types through the accessors below.
  std::array<std::vector<std::unique_ptr<RayUnit>>, kStages> units;
  LvbUpdater lvb;
  std::unique_ptr<ShadowCullingUnit> culling;
  RayRouter router;
  PhaseController phases;
  std::unique_ptr<Watchdog> watchdog;
  std::unique_ptr<PeriodicProbe> progress;
  std::unique_ptr<VcdTrace> trace;
  std::vector<RayUnit*> ray_units;  // every ray unit, in the table's order
  std::vector<RayFifo*> fifos;      // their inputs
  StatsRegistry stats;
  Tick end = 0;
  Tick frame_begin = 0;  // the first edge of the frame running or last run
  // The statistics' window: from elaboration, or from the last START (per-frame statistics)
  Tick stats_begin = 0;
  Tick stats_span = 0;  // end - stats_begin, the time-weighted figures' denominator
  bool frame_active = false;
  uint64_t frames = 0;  // begun
  uint64_t memory_bytes = 0;
  std::vector<RegisterWrite> preset;  // a frame programmed at construction
  std::vector<DetailWindow> windows;  // the frames' windows of detail (Accelerator::sample)
  WarmSource warm;                    // ... and their functional warming
  std::vector<uint8_t> warm_bytes;    // a line's bytes, read from memory for warming
  bool collected = false;
};

}  // namespace rtsim::model
