// The accelerator (rtsim::model::Accelerator), an sc_module: ray generator -> TRV -> LIST -> IST ->
// shading -> shadow culling -> TRV, with an L1 per unit, L2s per unit type, the interconnect to
// memory and one GDDR3 memory, all built from one plain config struct. It owns every block as a
// named child, and its own calendar (`calendar`, model/sim/calendar.h), so several accelerators can
// share one simulation. A block's hierarchical name below the accelerator is its statistics prefix
// and its VCD scope: `<top>.trv3` is TRV unit 3 (statistics trv3.*), `<top>.trv3.l1` its L1,
// `<top>.trv3.in` its input FIFO, `<top>.trv.l2` the TRV units' shared L2, `<top>.memory.icnt` the
// crossbar to memory, `<top>.memory.port` its TLM-2.0 initiator (model/memory/memory_port.h),
// `<top>.dram` the GDDR3 memory, a TLM-2.0 target (or, built without it, whatever target the
// platform binds to memory_socket()). `<top>.router` carries rays back to their TRV units and
// retires them, `<top>.phases` is the phase controller. Every hop of a ray is a port bound once
// in accelerator.cpp (docs/model-design.md has the table).
//
// It is a device (docs/systemc-integration.md, "The device"): a platform puts a scene image in
// memory, programs a frame through the register socket (`<top>.registers`,
// model/device/register_map.h), writes START, and gets the interrupt `irq` when the frame's hit
// records are in memory; frames run back to back, each in two phases (all primary rays, then all
// shadow rays) or in one (shadow rays as soon as their hit is shaded). It never sets the time
// resolution, never starts or stops the simulation. Errors are sc_reports of type rtsim/*
// (model/sim/report.h); memory that does not hold a readable image is the platform's to see, not
// a report: the frame ends with STATUS error regs::kBadImage (model/units/image_faults.h).
#pragma once

#include "kernels/access_stream.h"
#include "kernels/memory_image.h"
#include "model/accelerator_config.h"
#include "model/device/control_registers.h"
#include "model/memory/memory_port.h"
#include "model/sim/stats_registry.h"
#include "model/sim/vcd_trace.h"
#include "model/units/detail_window.h"
#include "model/units/frame_buffer.h"
#include "scene/scene.h"

#include <systemc>

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

namespace rtsim::model {

// A path-traced frame's bounce (0: the primary rays): its rays shaded and their hits; the shadow
// rays from its hits decided (emitted or culled), culled, finished and blocked; and the cycles in
// flight of its rays and of its shadow rays, summed over the rays.
struct BounceFigures {
  uint64_t rays = 0, hits = 0;
  uint64_t shadow_decisions = 0, shadow_culled = 0, shadow_rays = 0, shadow_occluded = 0;
  uint64_t ray_cycles = 0, shadow_cycles = 0;
};

// The figures of a finished frame. The pixels' colours are composed on the host from `frame`.
struct AcceleratorResult {
  FrameBuffer frame;
  uint64_t cycles_total = 0, cycles_primary = 0, cycles_shadow = 0;
  double clock_ghz = 1.0;
  std::vector<uint64_t> shadow_generated, shadow_culled;  // per light
  uint64_t primary_rays = 0, primary_hits = 0, reflection_rays = 0, shadow_rays = 0;
  uint64_t bounce_rays = 0;            // a path's diffuse bounces
  std::vector<BounceFigures> bounces;  // a path-traced frame's, by bounce (else empty)
  // The primary phase by batches of RayGenerator::kBatchRays rays in issue order: from a batch's
  // first issue to the next's (the last: to the last primary retirement). They add up to
  // cycles_primary: the units a sampled frame estimates from (issue 38, docs/sampling.md).
  std::vector<uint64_t> primary_batch_cycles;
  // Two phases: the shadow phase by batches of as many entries of the culling unit's scan, from
  // the scan reaching a batch's first entry to its reaching the next's (the last: to the last
  // retirement). They add up to cycles_shadow. Empty in one phase.
  std::vector<uint64_t> shadow_batch_cycles;
  // A sampled frame (Accelerator::sample): each window's batches, in each phase (the shadow phase's
  // in two phases only). The cycles above then count the simulated time, gaps included: a sampled
  // frame's figures are estimated from these (testbench/run/sampled_frame.h).
  std::vector<WindowBatches> primary_windows, shadow_windows;
  nlohmann::json stats;  // every named statistic
  // The unit types and the caches a report lists (model/accelerator_units.h).
  nlohmann::json units, caches;
  // The frame priced (model/energy/energy_model.h, report.json's `energy`); null for a sampled
  // frame or with `energy: none`.
  nlohmann::json energy;
  std::map<std::string, StatsRegistry::Glossary> glossary;  // ... with its unit and meaning
};

// Where a running frame stands, for progress reports.
struct Progress {
  int phase = 1;  // 1: primary rays, 2: shadow rays
  uint64_t cycle = 0;
  uint64_t pixels = 0, primaries_retired = 0;
  uint64_t shadows_generated = 0, shadows_retired = 0;
  // Share of the hit pixels the culling unit has passed (phase 2)
  double culling_scanned = 0;
};

// Observers of a run; none changes a simulated figure.
struct SimulationHooks {
  // Called every progress_cycles while the frame runs
  std::function<void(const Progress&)> progress;
  uint64_t progress_cycles = 20000;
  TraceRequest trace;      // a VCD of FIFOs and unit busy signals
  TraceRequest mem_trace;  // a CSV of the memory transactions
  // A CSV of the commands the built-in memory's controllers issue (model/memory/
  // dram_command_trace.h), over the statistics' span: rtsim/trace without the built-in memory.
  TraceRequest dram_commands;
  // A TLM-2.0 base-protocol checker (model/memory/tlm_checker.h, `<top>.tlm_checker`) between the
  // memory port and the memory: a violation is rtsim/tlm.
  bool tlm_checks = false;
  // What the statistics count: each frame on its own (every counter starts at 0 at START, and the
  // time-weighted figures cover the frame's time), or every frame since elaboration, the idle
  // time between frames included.
  enum class Statistics { kPerFrame, kAllFrames };
  Statistics statistics = Statistics::kPerFrame;
};

// The frame to render: `camera` at width x height.
struct FrameJob {
  Camera camera;
  int width = 0, height = 0;
};

// Where a frame's bytes lie in memory, from the configuration, the image's size and the resolution
// alone: a platform sizes and maps its memory with it before elaboration ends. The frame buffer
// holds a record per pixel and level (a primary hit and each reflection), `record_stride` bytes
// each, in issue order (docs/systemc-integration.md, "The register map").
struct MemoryLayout {
  uint64_t image_base = 0, image_bytes = 0;
  uint64_t fb_base = 0, fb_bytes = 0;  // the frame buffer: after the image, 4 KiB aligned
  uint32_t record_stride = 0;          // RECORD_STRIDE: a whole memory line
  uint64_t end() const { return fb_base + fb_bytes; }  // the bytes from address 0 the frame uses
};
// Bytes per hit record in the frame buffer (the register RECORD_STRIDE).
uint32_t record_stride(const AcceleratorConfig& config);
// The image at `image_base` (64-byte aligned), the frame buffer at the first 4 KiB boundary after
// it, as rtsim run and DeviceDriver lay them out (frame_buffer_after, device_driver.h).
MemoryLayout memory_layout(const AcceleratorConfig& config, uint64_t image_bytes, int width,
                           int height, uint64_t image_base = 0);

// A sampled frame's functional warming (Accelerator::sample, docs/sampling.md): before a window of
// primary rays, the host tells the accelerator the records that the rays skipped before it would
// have read. Each line goes through the L1 of the unit that would have read it and, missing there,
// that unit's L2, as tags and LRU order with the line's bytes from memory: no time, no statistic.
class CacheWarmer {
 public:
  virtual ~CacheWarmer() = default;
  // A walk's record of kind `kind`, `bytes` at `addr`, read for a ray dealt to traversal unit
  // `traversal` (by the unit of its stage on that ray's path, model::stage_of).
  virtual void read(WalkRead kind, uint32_t traversal, uint64_t addr, uint32_t bytes) = 0;
  virtual uint32_t traversal_units() const = 0;
};
// Called before each window of primary rays but the first, with the window's first ray.
using WarmSource = std::function<void(uint64_t first_ray, CacheWarmer& warmer)>;

// What the memory socket is bound to (docs/systemc-integration.md).
enum class MemoryTarget {
  kBuiltin,             // the built-in GDDR3, `<top>.dram`
  kApproximatelyTimed,  // the platform's memory, nb_transport in any base-protocol style
  kLooselyTimed,        // the platform's memory, b_transport only (and maybe DMI)
};

class Accelerator : public sc_core::sc_module {
 public:
  // A target socket a platform may leave unbound.
  using TargetSocket =
      tlm::tlm_target_socket<32, tlm::tlm_base_protocol_types, 1, sc_core::SC_ZERO_OR_MORE_BOUND>;
  // The interrupt: high while a frame's end is enabled and not acknowledged (IRQ_ENABLE,
  // IRQ_STATUS). Bind it to an sc_signal<bool>, or leave it unbound and poll STATUS.
  sc_core::sc_port<sc_core::sc_signal_inout_if<bool>, 1, sc_core::SC_ZERO_OR_MORE_BOUND> irq;

  // The device, idle until a platform programs it. A configuration out of range is reported as
  // rtsim/config. With the built-in memory, a platform loads it through memory_host_socket();
  // otherwise there is no `dram`, and memory_socket() is the platform's to bind.
  Accelerator(sc_core::sc_module_name name, const AcceleratorConfig& config,
              const SimulationHooks& hooks = {}, MemoryTarget memory = MemoryTarget::kBuiltin);
  // The device programmed at construction with one frame of `job` over `image`, started at time
  // 0, as a driver writing the registers then would (DeviceDriver::program): the image at
  // address 0 and the frame buffer after it. The built-in memory holds `image` without a copy
  // (it must outlive the accelerator); the platform's must hold memory_bytes() bytes, the
  // image's first.
  Accelerator(sc_core::sc_module_name name, const AcceleratorConfig& config,
              const MemoryImage& image, const FrameJob& job, const SimulationHooks& hooks = {},
              MemoryTarget memory = MemoryTarget::kBuiltin);
  ~Accelerator() override;
  const char* kind() const override { return "rtsim_accelerator"; }
  void end_of_elaboration() override;

  // After the simulation (or between frames): whether the last frame completed, and its figures
  // (rtsim/internal if it did not): its cycles, its hits and the host-side frame, and the
  // statistics: the frame's own, or every frame's (SimulationHooks::statistics). Closes the
  // statistics the first time it is called after a frame.
  bool finished() const;
  AcceleratorResult result();
  const StatsRegistry& stats() const;

  // The TLM-2.0 initiator socket towards memory (bound to the built-in GDDR3 unless told
  // otherwise): the memory port's, or the protocol checker's behind it.
  tlm::tlm_initiator_socket<>& memory_socket();
  // The register block's target socket (LT: b_transport, transport_dbg; may stay unbound).
  TargetSocket& register_socket();
  // The built-in memory's host port (Dram::host_socket); rtsim/internal without one.
  TargetSocket& memory_host_socket();
  // The bytes the memory must hold: with a frame programmed at construction, the image then
  // its frame buffer (memory_layout(...).end()); else the built-in memory's size (0 with the
  // platform's: memory_layout() tells what a frame needs).
  uint64_t memory_bytes() const;

  // Makes the frames started from now on sampled ones: only `windows` of their primary rays in
  // issue order, and of the culling unit's record slots in the same order, run in detail
  // (model/units/detail_window.h; empty: whole frames again). It needs two phases, records read
  // from memory and no reflections, and windows that fit the frame; anything else is
  // rtsim/config. A host-side control of the simulation, not a register: no hardware samples.
  // `warm` (optional) warms the caches before each window (CacheWarmer; the built-in memory only).
  void sample(std::vector<DetailWindow> windows, WarmSource warm = {});

 private:
  struct Netlist;
  SC_HAS_PROCESS(Accelerator);
  void build(const AcceleratorConfig& config, const SimulationHooks& hooks, MemoryTarget memory,
             const MemoryImage* image, const FrameJob* job);
  void start();  // at the start of the simulation: a frame programmed at construction begins

  std::unique_ptr<Netlist> net_;
};

}  // namespace rtsim::model
