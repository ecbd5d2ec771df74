#include "model/accelerator.h"

#include "model/memory/dram.h"
#include "model/memory/memory_system.h"
#include "model/memory/tlm_checker.h"
#include "model/sim/calendar.h"
#include "model/sim/periodic_probe.h"
#include "model/sim/report.h"
#include "model/sim/watchdog.h"
#include "model/units/ist_unit.h"
#include "model/units/list_unit.h"
#include "model/units/lvb_updater.h"
#include "model/units/phase_controller.h"
#include "model/units/ray_router.h"
#include "model/units/shading_unit.h"
#include "model/units/shadow_culling_unit.h"
#include "model/units/trv_unit.h"

#include <stdexcept>

namespace rtsim::model {

namespace {

template <typename T>
std::vector<const Unit*> raw(const std::vector<std::unique_ptr<T>>& units) {
  std::vector<const Unit*> v;
  for (const auto& u : units) v.push_back(u.get());
  return v;
}

std::string indexed(const char* type, uint32_t i) { return type + std::to_string(i); }

HitRecordRegion record_region(const AcceleratorConfig& cfg, const MemoryImage& image,
                              const FrameJob& job, uint32_t request_bytes) {
  HitRecordRegion records;
  records.base = (image.bytes().size() + 4095) / 4096 * 4096;
  records.stride = std::max(kHitRecordBytes, request_bytes);
  records.pixels = uint32_t(job.width) * uint32_t(job.height);
  auto pixel_at = std::make_shared<std::vector<uint32_t>>(
      issue_order(job.width, job.height, cfg.order, cfg.tile));
  auto slot_of = std::make_shared<std::vector<uint32_t>>(pixel_at->size());
  for (uint32_t k = 0; k < pixel_at->size(); ++k) (*slot_of)[(*pixel_at)[k]] = k;
  records.pixel_at = std::move(pixel_at);
  records.slot_of = std::move(slot_of);
  return records;
}

}  // namespace

// The calendar's same-time order (docs/model-design.md, "Same-time order"): among the blocks due
// at one time the memory acts first, then the units from the end of a ray's walk (IST) back to
// its start (TRV), so that a slot a unit frees is seen by its producer in the same cycle; then
// shading, the generator and the culling unit, which start rays, and the watchdog, which looks
// at what all the others did. Units of one type act in the order of their index.
enum Rank : uint32_t {
  kDramRank,
  kMemoryPortRank,
  kIstRank,
  kListRank,
  kTrvRank,
  kShadingRank,
  kRayGeneratorRank,
  kCullingRank,
  kWatchdogRank,
};

// Every block of one accelerator, built in the accelerator's scope (so each is its child) in the
// order a ray meets them, then connected: every hop of a ray is a port bound here, once.
struct Accelerator::Netlist {
  Netlist(Accelerator& top, const AcceleratorConfig& cfg, const MemoryImage& image,
          const FrameJob& job, const SimulationHooks& hooks, MemoryTarget memory_target);

  void build_memory(const MemoryImage& image, MemoryTarget memory_target);
  void build_units();
  void bind_ray_path();
  void bind_control_and_memory();
  void declare_order();
  void build_observers();

  bool pending() const {
    return pool.in_flight() > 0 || !generator->finished() || !culling->finished();
  }
  uint64_t progress_count() const;
  std::string describe_stall() const;
  void report_progress(Tick now) const;
  void register_stats();
  // The socket towards memory: the protocol checker's, when there is one.
  tlm::tlm_initiator_socket<>& memory_socket() {
    if (checker) return checker->initiator_socket;
    return memory->interconnect().port().socket;
  }

  Accelerator& top;
  AcceleratorConfig cfg;
  FrameJob job;
  RayPool pool;
  ModelContext ctx;
  FrameBuffer frame;
  HitRecordRegion records;
  SimulationHooks hooks;
  Calendar calendar;
  std::unique_ptr<Dram> dram;
  std::unique_ptr<MemorySystem> memory;
  std::unique_ptr<TlmChecker> checker;  // between the memory port and the memory, if asked
  std::unique_ptr<RayGenerator> generator;
  std::vector<std::unique_ptr<TrvUnit>> trv;
  std::vector<std::unique_ptr<ListUnit>> list;
  std::vector<std::unique_ptr<IstUnit>> ist;
  LvbUpdater lvb;
  std::vector<std::unique_ptr<ShadingUnit>> shading;
  std::unique_ptr<ShadowCullingUnit> culling;
  RayRouter router;
  PhaseController phases;
  std::unique_ptr<Watchdog> watchdog;
  std::unique_ptr<PeriodicProbe> progress;
  std::unique_ptr<VcdTrace> trace;
  std::vector<RayUnit*> ray_units;  // TRV, LIST, IST, shading
  std::vector<RayFifo*> fifos;      // shading, TRV, LIST, IST inputs
  StatsRegistry stats;
  Tick end = 0;
  uint64_t memory_bytes = 0;
  bool collected = false;
};

Accelerator::Netlist::Netlist(Accelerator& top_, const AcceleratorConfig& config,
                              const MemoryImage& image, const FrameJob& frame_job,
                              const SimulationHooks& observers, MemoryTarget memory_target)
    : top(top_),
      cfg(config),
      job(frame_job),
      pool(config.ray_pool),
      hooks(observers),
      calendar("calendar"),
      lvb("lvb_updater"),
      router("router", ctx),
      phases("phases", config.schedule, calendar) {
  const image::Header& h = image.header();
  ctx.calendar = &calendar;
  ctx.pool = &pool;
  ctx.header = h;
  ctx.clock = Clock(cfg.clock_ghz);
  // The reference tracer's constants (reference_tracer.cpp), computed the same way.
  ctx.abs_eps = 1e-6f * std::max(h.bounds.diagonal(), 1e-20f);
  ctx.shadow_offset = 1e-5f * h.bounds.diagonal();
  for (uint32_t l = 0; l < h.light_count; ++l) ctx.light_samples.push_back(image.light(l).samples);
  frame.width = job.width;
  frame.height = job.height;
  frame.levels = cfg.reflection_depth + 1;
  frame.allocate(ctx.light_samples);

  build_memory(image, memory_target);
  build_units();
  bind_ray_path();
  bind_control_and_memory();
  build_observers();
  declare_order();
  register_stats();
}

// The memory (the built-in GDDR3, unless the platform binds its own) and the hierarchy in front
// of it; the frame buffer of hit records follows the image (model/units/hit_record.h).
void Accelerator::Netlist::build_memory(const MemoryImage& image, MemoryTarget memory_target) {
  MemorySystemConfig mem = cfg.memory_system();
  mem.loosely_timed_memory = memory_target == MemoryTarget::kLooselyTimed;
  const uint64_t entries =
      uint64_t(job.width) * uint64_t(job.height) * uint64_t(cfg.reflection_depth + 1);
  records = record_region(cfg, image, job, mem.dram.request_bytes);
  memory_bytes = records.base + entries * records.stride;
  if (memory_target == MemoryTarget::kBuiltin)
    dram = std::make_unique<Dram>("dram", mem.dram, &image.bytes(), ctx.clock, calendar,
                                  memory_bytes - image.bytes().size());
  memory = std::make_unique<MemorySystem>(mem, ctx.clock, calendar);
  if (hooks.tlm_checks) {
    checker = std::make_unique<TlmChecker>("tlm_checker");
    memory->interconnect().port().socket.bind(checker->target_socket);
  }
  if (dram) memory_socket().bind(dram->socket);
  if (!hooks.mem_trace.file.empty()) memory->interconnect().port().open_trace(hooks.mem_trace);
}

void Accelerator::Netlist::build_units() {
  generator = std::make_unique<RayGenerator>("raygen", ctx, job.camera, job.width, job.height,
                                             cfg.order, cfg.tile, cfg.raygen_rays_per_cycle);
  for (uint32_t i = 0; i < cfg.trv.count; ++i)
    trv.push_back(std::make_unique<TrvUnit>(indexed("trv", i).c_str(), ctx, cfg.trv, *memory, i));
  for (uint32_t j = 0; j < cfg.list.count; ++j)
    list.push_back(
        std::make_unique<ListUnit>(indexed("list", j).c_str(), ctx, cfg.list, *memory, j));
  for (uint32_t k = 0; k < cfg.ist.count; ++k)
    ist.push_back(std::make_unique<IstUnit>(indexed("ist", k).c_str(), ctx, cfg.ist, *memory, k));
  for (uint32_t s = 0; s < cfg.shading.count; ++s)
    shading.push_back(std::make_unique<ShadingUnit>(indexed("shading", s).c_str(), ctx, cfg.shading,
                                                    *memory, s, &frame, records));
  culling = std::make_unique<ShadowCullingUnit>("culling", ctx, cfg.lvb_culling, cfg.culling,
                                                memory.get(), &frame, records);
}

// Forward: generator -> TRV -> LIST -> IST -> shading (TRV unit i -> LIST unit i x list / trv
// -> IST unit j x ist / list); culling -> TRV. Back: IST and shading -> router -> the ray's TRV
// unit, and IST -> router -> its TRV unit's shading unit; retirement through the router.
void Accelerator::Netlist::bind_ray_path() {
  for (uint32_t i = 0; i < cfg.trv.count; ++i) {
    TrvUnit& t = *trv[i];
    generator->to_trv.bind(t.in);
    culling->to_trv.bind(t.in);
    t.to_list.bind(list[i * cfg.list.count / cfg.trv.count]->in);
    t.to_shading.bind(shading[i * cfg.shading.count / cfg.trv.count]->in);
    router.owners.bind(t.owner);
  }
  for (uint32_t j = 0; j < cfg.list.count; ++j)
    list[j]->to_ist.bind(ist[j * cfg.ist.count / cfg.list.count]->in);
  for (auto& u : ist) {
    u->back.bind(router.returns);
    u->to_shading.bind(router.finished);
    u->lvb.bind(lvb);
  }
  for (auto& u : shading) {
    u->back.bind(router.returns);
    router.shading.bind(u->in);
    if (cfg.schedule == Schedule::kOnePhase) u->hits.bind(culling->hits);
  }
  router.phases.bind(phases.retirements);
}

// The phase controller's reach, and the memory the shading and culling units use besides their
// caches: the frame buffer's writes and reads, and the L1 the culling unit reads the lights
// through (shading unit 0's single port unless it has its own).
void Accelerator::Netlist::bind_control_and_memory() {
  phases.primaries.bind(generator->control);
  phases.shadows.bind(culling->control);
  if (cfg.write_records)
    for (uint32_t s = 0; s < cfg.shading.count; ++s)
      shading[s]->records.bind(memory->interconnect().writer(s));
  if (cfg.schedule == Schedule::kTwoPhase && cfg.culling.records_per_cycle > 0)
    culling->records.bind(memory->interconnect().record_reader());
  if (Cache* own = culling->own_l1()) {
    culling->lights.bind(*own);
  } else {
    shading[0]->l1().name_requester(culling.get(), "culling");
    culling->lights.bind(shading[0]->l1());
  }
}

void Accelerator::Netlist::declare_order() {
  if (dram) calendar.set_rank(*dram, kDramRank);
  calendar.set_rank(memory->interconnect().port(), kMemoryPortRank);
  for (auto& u : ist) calendar.set_rank(*u, kIstRank);
  for (auto& u : list) calendar.set_rank(*u, kListRank);
  for (auto& u : trv) calendar.set_rank(*u, kTrvRank);
  for (auto& u : shading) calendar.set_rank(*u, kShadingRank);
  calendar.set_rank(*generator, kRayGeneratorRank);
  calendar.set_rank(*culling, kCullingRank);
  calendar.set_rank(*watchdog, kWatchdogRank);
}

// The watchdog (a run that stops moving names what is stuck), and what only observes: progress
// reports and the VCD trace.
void Accelerator::Netlist::build_observers() {
  for (auto& u : shading) fifos.push_back(&u->in);
  for (auto& u : trv) fifos.push_back(&u->in);
  for (auto& u : list) fifos.push_back(&u->in);
  for (auto& u : ist) fifos.push_back(&u->in);
  for (auto& u : trv) ray_units.push_back(u.get());
  for (auto& u : list) ray_units.push_back(u.get());
  for (auto& u : ist) ray_units.push_back(u.get());
  for (auto& u : shading) ray_units.push_back(u.get());
  watchdog = std::make_unique<Watchdog>(
      "watchdog", calendar, ctx.clock, cfg.watchdog_cycles, [this] { return progress_count(); },
      [this] { return pending(); }, [this] { return describe_stall(); });
  if (hooks.progress)
    progress = std::make_unique<PeriodicProbe>("progress", ctx.clock.cycles(hooks.progress_cycles),
                                               [this](Tick now) {
                                                 report_progress(now);
                                                 return pending();
                                               });
  if (!hooks.trace.file.empty()) {
    trace = std::make_unique<VcdTrace>(hooks.trace, ctx.clock, [this] { return pending(); });
    for (const RayFifo* f : fifos) trace->add_fifo(f);
    trace->add_unit(generator.get());
    for (const RayUnit* u : ray_units) trace->add_unit(u);
    trace->add_unit(culling.get());
    trace->add_counter(std::string(top.name()) + ".rays_in_flight",
                       [this] { return uint64_t(pool.in_flight()); });
  }
}

uint64_t Accelerator::Netlist::progress_count() const {
  // A DRAM draining its queues (a backlog of posted writes) is progress too.
  const MemoryPortStats& port = memory->interconnect().port().stats();
  uint64_t n = phases.primaries_retired() + phases.shadows_retired() +
               generator->unit_stats().busy_cycles + culling->unit_stats().busy_cycles +
               (dram ? dram->stats().reads + dram->stats().writes : port.responses);
  for (const RayUnit* u : ray_units) n += u->unit_stats().busy_cycles;
  return n;
}

std::string Accelerator::Netlist::describe_stall() const {
  std::string s = std::to_string(pool.in_flight()) + " rays in flight; non-empty FIFOs:";
  for (const RayFifo* f : fifos)
    if (!f->empty()) s += " " + stat_prefix(*f, top) + " (" + std::to_string(f->size()) + ")";
  s += "; units holding rays:";
  for (const RayUnit* u : ray_units)
    if (u->held() > 0) s += " " + stat_prefix(*u, top) + " (" + std::to_string(u->held()) + ")";
  return s + "; " + culling->state() + (dram ? "; " + dram->engine().state() : "");
}

void Accelerator::Netlist::report_progress(Tick now) const {
  Progress p;
  p.phase = phases.primaries_done() ? 2 : 1;
  p.cycle = ctx.clock.to_cycles(now);
  p.pixels = uint64_t(job.width) * uint64_t(job.height);
  p.primaries_retired = phases.primaries_retired();
  p.shadows_generated = culling->generated();
  p.shadows_retired = phases.shadows_retired();
  p.culling_scanned = culling->decided_fraction();
  hooks.progress(p);
}

void Accelerator::Netlist::register_stats() {
  for (auto& u : trv) u->register_stats(stats, stat_prefix(*u, top));
  for (auto& u : list) u->register_stats(stats, stat_prefix(*u, top));
  for (auto& u : ist) u->register_stats(stats, stat_prefix(*u, top));
  for (auto& u : shading) u->register_stats(stats, stat_prefix(*u, top));
  // Unit totals per type, beside the per-instance figures.
  auto add_totals = [this](const std::string& type, std::vector<const Unit*> units) {
    for (auto [name, field] : {std::pair{"busy_cycles", &UnitStats::busy_cycles},
                               std::pair{"stalled_cycles", &UnitStats::stalled_cycles},
                               std::pair{"idle_cycles", &UnitStats::idle_cycles}})
      stats.formula(
          type + ".total." + name,
          [units, field = field] {
            uint64_t n = 0;
            for (const Unit* u : units) n += u->unit_stats().*field;
            return double(n);
          },
          "cycles", std::string("all ") + type + " units: " + name);
  };
  add_totals("trv", raw(trv));
  add_totals("list", raw(list));
  add_totals("ist", raw(ist));
  add_totals("shading", raw(shading));
  memory->register_stats(stats, top, &end);
  generator->register_unit_stats(stats, stat_prefix(*generator, top));
  culling->register_stats(stats, stat_prefix(*culling, top));
  lvb.register_stats(stats, stat_prefix(lvb, top));
  if (dram) dram->register_stats(stats, stat_prefix(*dram, top));
  if (checker) checker->register_stats(stats, stat_prefix(*checker, top));
  for (RayFifo* f : fifos) f->register_stats(stats, stat_prefix(*f, top), &end);
}

Accelerator::Accelerator(sc_core::sc_module_name name, const AcceleratorConfig& config,
                         const MemoryImage& image, const FrameJob& job,
                         const SimulationHooks& hooks, MemoryTarget memory)
    : sc_core::sc_module(name) {
  try {
    config.validate();
  } catch (const std::invalid_argument& e) {
    report_error(kReportConfig, std::string(this->name()) + ": " + e.what());
  }
  net_ = std::make_unique<Netlist>(*this, config, image, job, hooks, memory);
  SC_METHOD(start);  // runs once, when the simulation starts
}

Accelerator::~Accelerator() = default;

void Accelerator::end_of_elaboration() {
  if (net_->trace) net_->trace->end_of_elaboration();
}

void Accelerator::start() {
  Netlist& n = *net_;
  n.generator->wake(0);
  n.watchdog->start();
  if (n.progress) n.progress->start_at(0);
  if (n.trace) n.trace->start();
}

bool Accelerator::finished() const { return net_->phases.finished(); }

const StatsRegistry& Accelerator::stats() const { return net_->stats; }

tlm::tlm_initiator_socket<>& Accelerator::memory_socket() { return net_->memory_socket(); }

uint64_t Accelerator::memory_bytes() const { return net_->memory_bytes; }

AcceleratorResult Accelerator::result() {
  Netlist& n = *net_;
  if (!finished())
    report_error(kReportInternal,
                 std::string(name()) + ": the simulation ended with rays in flight");
  if (n.checker && n.checker->open_transactions() > 0)
    report_error(kReportTlm, std::string(n.checker->name()) + ": " +
                                 std::to_string(n.checker->open_transactions()) +
                                 " transactions never ended");
  if (!n.collected) {
    if (n.trace) n.trace->close();
    n.memory->interconnect().port().close_trace();
    // The frame ends with the last retirement (the watchdog's last look may come later).
    n.end = n.phases.end();
    n.generator->finish_accounting(n.end);
    n.culling->finish_accounting(n.end);
    for (RayUnit* u : n.ray_units) u->finish_accounting(n.end);
    for (RayFifo* f : n.fifos) f->finish_accounting(n.end);
    n.frame.close_samples();
    n.collected = true;
  }
  AcceleratorResult out;
  out.clock_ghz = n.cfg.clock_ghz;
  out.cycles_total = n.ctx.clock.to_cycles(n.ctx.clock.edge_at_or_after(n.end));
  out.cycles_primary = n.ctx.clock.to_cycles(n.ctx.clock.edge_at_or_after(n.phases.primary_end()));
  out.cycles_shadow = out.cycles_total - out.cycles_primary;
  for (const auto& u : n.shading) {
    out.primary_rays += u->stats().primary_rays;
    out.primary_hits += u->stats().primary_hits;
    out.reflection_rays += u->stats().reflection_rays;
    out.shadow_rays += u->stats().shadow_rays;
  }
  for (const LightStats& l : n.culling->per_light()) {
    out.shadow_generated.push_back(l.generated);
    out.shadow_culled.push_back(l.culled);
  }
  out.stats = n.stats.values();
  out.glossary = n.stats.glossary();
  out.frame = n.frame;
  return out;
}

}  // namespace rtsim::model
