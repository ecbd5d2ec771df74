#include "model/accelerator_netlist.h"

#include <stdexcept>

namespace rtsim::model {

namespace {

std::string indexed(const char* type, uint32_t i) { return type + std::to_string(i); }

}  // namespace

Accelerator::Netlist::Netlist(Accelerator& top_, const AcceleratorConfig& config,
                              const SimulationHooks& observers, MemoryTarget memory_target,
                              const MemoryImage* image, uint64_t image_memory_bytes)
    : top(top_),
      cfg(config),
      pool(config.ray_pool),
      hooks(observers),
      calendar("calendar"),
      lvb("lvb_updater"),
      router("router", ctx),
      phases("phases", config.schedule, calendar) {
  ctx.calendar = &calendar;
  ctx.pool = &pool;
  ctx.faults = &faults;
  ctx.clock = Clock(cfg.clock_ghz);
  ctx.integrator = cfg.integrator;
  ctx.path = cfg.path;
  build_memory(image, image_memory_bytes, memory_target);
  build_units();
  bind_ray_path();
  bind_control_and_memory();
  build_observers();
  declare_order();
  register_stats();
  DeviceInfo info;
  info.record_stride = record_stride(cfg);
  info.levels = cfg.entries_per_pixel();  // entries per pixel
  info.order = cfg.order == RayOrder::kTiles ? 1u : 0u;
  info.tile = uint32_t(cfg.tile);
  info.memory_bytes = dram ? dram->store_bytes() : 0;
  info.lvb_culling = cfg.lvb_culling;
  info.bvh = cfg.structure == Structure::kBvh;
  registers = std::make_unique<ControlRegisters>("registers", info, *this);
  registers->irq.bind(top.irq);
  calendar.on_settled([this] { check_frame_end(); });
  memory->interconnect().port().on_drained([this] { check_frame_end(); });
}

// The memory (the built-in GDDR3, unless the platform binds its own) and the hierarchy in front
// of it; the frame buffer of hit records follows the image (model/units/hit_record.h).
// With an image given (a frame programmed at construction), the built-in memory holds it and
// `image_memory_bytes` in all; else it is empty, of its configured capacity.
void Accelerator::Netlist::build_memory(const MemoryImage* image, uint64_t image_memory_bytes,
                                        MemoryTarget memory_target) {
  topology = memory_topology(cfg, memory_target);
  const MemorySystemConfig& mem = topology.memory;
  memory_bytes = image_memory_bytes;
  if (memory_target == MemoryTarget::kBuiltin && image)
    dram = std::make_unique<Dram>("dram", mem.dram, &image->bytes(), ctx.clock, calendar,
                                  image_memory_bytes - image->bytes().size());
  else if (memory_target == MemoryTarget::kBuiltin)
    dram = std::make_unique<Dram>("dram", mem.dram, nullptr, ctx.clock, calendar,
                                  uint64_t(mem.dram.capacity_mib) << 20);
  if (dram && !image) memory_bytes = dram->store_bytes();
  memory = std::make_unique<MemorySystem>(mem, ctx.clock, calendar);
  if (hooks.tlm_checks) {
    checker = std::make_unique<TlmChecker>("tlm_checker");
    memory->interconnect().port().socket.bind(checker->target_socket);
  }
  if (dram) memory_socket().bind(dram->socket);
  if (!hooks.mem_trace.file.empty()) memory->interconnect().port().open_trace(hooks.mem_trace);
  if (!hooks.dram_commands.file.empty()) {
    if (!dram)
      report_error(kReportTrace, hooks.dram_commands.file +
                                     ": the DRAM commands are the built-in memory's, and the "
                                     "platform binds its own");
    dram->open_command_trace(hooks.dram_commands);
  }
}

void Accelerator::Netlist::build_units() {
  generator =
      std::make_unique<RayGenerator>("raygen", ctx, cfg.order, cfg.tile, cfg.raygen_rays_per_cycle);
  const UnitBuild b{ctx, cfg, &frame, records};
  for (const RayUnitType* type : unit_types(cfg))
    for (uint32_t i = 0; i < (cfg.*type->config).count; ++i)
      units[type->stage].push_back(type->make(indexed(type->key, i).c_str(), b, i));
  // Its own L1 is a shading L1.
  const bool own_l1 = cfg.culling.l1 == CullingL1::kOwn;
  culling = std::make_unique<ShadowCullingUnit>("culling", ctx, cfg.culling,
                                                own_l1 ? &cfg.shading : nullptr, &frame, records);
  for (auto& type : units)
    for (auto& u : type) ray_units.push_back(u.get());
}

// Forward: generator -> TRV -> LIST -> IST -> shading (TRV unit i -> LIST unit i x list / trv
// -> IST unit j x ist / list); culling -> TRV. Back: IST and shading -> router -> the ray's TRV
// unit, and IST -> router -> its TRV unit's shading unit; retirement through the router.
void Accelerator::Netlist::bind_ray_path() {
  const uint32_t traversal_units = uint32_t(units[kTrvStage].size());
  for (uint32_t i = 0; i < traversal_units; ++i) {
    TraversalUnit& t = traversal(i);
    generator->to_trv.bind(t.in);
    culling->to_trv.bind(t.in);
    const std::array<uint32_t, kStages> route = ray_route(cfg, i);
    t.to_list.bind(list(route[kListStage]).in);
    t.to_shading.bind(shading(route[kShadingStage]).in);
    router.owners.bind(t.owner);
  }
  for (uint32_t j = 0; j < cfg.list.count; ++j)
    list(j).to_ist.bind(ist(fan_in(j, cfg.list.count, cfg.ist.count)).in);
  for (uint32_t k = 0; k < cfg.ist.count; ++k) {
    ist(k).back.bind(router.returns);
    ist(k).to_shading.bind(router.finished);
    ist(k).lvb.bind(lvb);
  }
  for (uint32_t s = 0; s < cfg.shading.count; ++s) {
    ShadingUnit& u = shading(s);
    u.back.bind(router.returns);
    router.shading.bind(u.in);
    if (cfg.schedule == Schedule::kOnePhase) u.hits.bind(culling->hits);
  }
  router.phases.bind(phases.retirements);
}

// The phase controller's reach; where each unit's caches reach below (the topology); the memory
// the shading and culling units use besides their caches: the frame buffer's writes and reads,
// and the L1 the culling unit reads the lights through (shading unit 0's single port unless it
// has its own).
void Accelerator::Netlist::bind_control_and_memory() {
  for (size_t t = 0; t < units.size(); ++t)
    for (size_t i = 0; i < units[t].size(); ++i)
      units[t][i]->mem_side.bind(reach(*memory, topology.units[t][i]));
  if (auto* below = culling->mem_side()) below->bind(reach(*memory, topology.culling));
  phases.primaries.bind(generator->control);
  phases.shadows.bind(culling->control);
  if (cfg.write_records)
    for (uint32_t s = 0; s < cfg.shading.count; ++s)
      shading(s).records.bind(memory->interconnect().writer(s));
  if (cfg.schedule == Schedule::kTwoPhase && cfg.culling.records_per_cycle > 0)
    culling->records.bind(memory->interconnect().record_reader());
  if (Cache* own = culling->own_l1()) {
    culling->lights.bind(*own);
  } else {
    shading(0).l1().name_requester(culling.get(), "culling");
    culling->lights.bind(shading(0).l1());
  }
}

void Accelerator::Netlist::declare_order() {
  if (dram) calendar.set_rank(*dram, kDramRank);
  calendar.set_rank(memory->interconnect().port(), kMemoryPortRank);
  for (const RayUnitType* type : unit_types(cfg))
    for (auto& u : units[type->stage]) calendar.set_rank(*u, type->rank);
  calendar.set_rank(*generator, kRayGeneratorRank);
  calendar.set_rank(*culling, kCullingRank);
  calendar.set_rank(*watchdog, kWatchdogRank);
}

// The watchdog (a run that stops moving names what is stuck), and what only observes: progress
// reports and the VCD trace.
void Accelerator::Netlist::build_observers() {
  for (RayUnit* u : ray_units) fifos.push_back(&u->in);
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
    // The shared L2s' and the memory port's counters: where a frame's memory traffic goes.
    for (const Cache* l2 : memory->shared_l2s())
      trace->add_counters(l2->name(), l2->stats(), l2->config().max_merge > 0,
                          l2->config().ports > 0);
    const MemoryPort& port = memory->interconnect().port();
    trace->add_counters(port.name(), port.stats());
  }
}

void Accelerator::Netlist::invalidate_caches() {
  memory->invalidate();
  for (RayUnit* u : ray_units) u->caches().invalidate();
  if (Cache* own = culling->own_l1()) own->invalidate();
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
  // Per unit type: each unit's figures and caches, and totals beside them (its units' cycles, its
  // L1s, its private L2s).
  for (const RayUnitType* type : unit_types(cfg)) {
    std::vector<const Cache*> l1s, l2s;
    for (const auto& u : units[type->stage]) {
      u->register_stats(stats, stat_prefix(*u, top));
      u->caches().register_stats(stats, top, &stats_span);
      l1s.push_back(&u->l1());
      if (u->caches().l2()) l2s.push_back(u->caches().l2());
    }
    register_unit_totals(type->key, units[type->stage]);
    register_cache_totals(stats, std::string(type->key) + ".l1", l1s);
    if (!l2s.empty()) register_cache_totals(stats, std::string(type->key) + ".l2", l2s);
  }
  register_work_totals();
  if (const Cache* own = culling->own_l1()) own->register_stats(stats, stat_prefix(*own, top));
  memory->register_stats(stats, top, &stats_span);
  generator->register_unit_stats(stats, stat_prefix(*generator, top));
  culling->register_stats(stats, stat_prefix(*culling, top));
  lvb.register_stats(stats, stat_prefix(lvb, top));
  StatsRegistrar fault_stats(stats, "faults");
  describe_stats(fault_stats, faults);
  if (dram) dram->register_stats(stats, stat_prefix(*dram, top));
  if (checker) checker->register_stats(stats, stat_prefix(*checker, top));
  for (RayFifo* f : fifos) f->register_stats(stats, stat_prefix(*f, top), &stats_span);
}

// The work of each unit type summed over its units, as its row lists it: what per-ray figures
// divide (nodes and leaves visited, triangles tested per ray traced).
void Accelerator::Netlist::register_work_totals() {
  for (const RayUnitType* type : unit_types(cfg))
    if (type->totals) type->totals(stats, type->key, units[type->stage], type->work);
}

// <key>.total.{busy,stalled,idle}_cycles over a type's units.
void Accelerator::Netlist::register_unit_totals(const std::string& key,
                                                const std::vector<std::unique_ptr<RayUnit>>& us) {
  std::vector<const UnitStats*> parts;
  for (const auto& u : us) parts.push_back(&u->unit_stats());
  register_totals(stats, key + ".total", "all " + key + " units: ", parts,
                  {"busy_cycles", "stalled_cycles", "idle_cycles"},
                  [](auto& v, const UnitStats& s) { describe_stats(v, s); });
}

}  // namespace rtsim::model
