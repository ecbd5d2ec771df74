#include "model/accelerator.h"

#include "kernels/shading.h"
#include "model/dram.h"
#include "model/ist_unit.h"
#include "model/list_unit.h"
#include "model/lvb_updater.h"
#include "model/memory_system.h"
#include "model/periodic_probe.h"
#include "model/shading_unit.h"
#include "model/shadow_culling_unit.h"
#include "model/trv_unit.h"
#include "model/watchdog.h"

#include <memory>
#include <stdexcept>

namespace rtsim::model {

namespace {

void validate_type(const UnitTypeConfig& u, const std::string& name, bool has_l2) {
  auto bad = [&](const std::string& field, const std::string& what) {
    throw std::invalid_argument(name + "." + field + ": " + what);
  };
  if (u.count < 1 || u.count > 1024) bad("count", "expected 1..1024");
  if (u.latency < 1 || u.latency > 10000) bad("latency", "expected 1..10000 cycles");
  if (u.capacity < 1 || u.capacity > 65536) bad("capacity", "expected 1..65536 rays");
  if (u.fifo_depth < 1 || u.fifo_depth > 65536) bad("fifo_depth", "expected 1..65536");
  try {
    u.l1.validate();
  } catch (const std::invalid_argument& e) {
    bad("l1", e.what());
  }
  try {
    u.link.validate();
  } catch (const std::invalid_argument& e) {
    bad("link", e.what());
  }
  if (has_l2) {
    try {
      u.l2.validate();
    } catch (const std::invalid_argument& e) {
      bad("l2", e.what());
    }
  }
}

}  // namespace

void AcceleratorConfig::validate() const {
  if (!(clock_ghz > 0.01 && clock_ghz <= 100)) throw std::invalid_argument("clock_ghz: expected (0.01, 100]");
  validate_type(trv, "trv", true);
  validate_type(list, "list", true);
  validate_type(ist, "ist", true);
  validate_type(shading, "shading", false);
  if (shading.count > 64) throw std::invalid_argument("shading.count: expected 1..64");
  if (list.l2.line_bytes != trv.l2.line_bytes || ist.l2.line_bytes != trv.l2.line_bytes)
    throw std::invalid_argument("l2.line_bytes: the three L2s share one memory; expected equal line sizes");
  for (const UnitTypeConfig* u : {&trv, &list, &ist})
    if (u->l1.line_bytes > u->l2.line_bytes) throw std::invalid_argument("l1.line_bytes: expected <= the L2's");
  if (shading.l1.line_bytes > ist.l2.line_bytes) throw std::invalid_argument("shading.l1.line_bytes: expected <= the IST L2's");
  try {
    memory_link.validate();
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("memory_link: ") + e.what());
  }
  if (ray_pool < 1 || ray_pool > (1u << 24)) throw std::invalid_argument("ray_pool: expected 1..16777216");
  if (culling.records_per_cycle > 64) throw std::invalid_argument("culling.records_per_cycle: expected 0 (unlimited) .. 64");
  if (culling.prefetch < 1 || culling.prefetch > 65536) throw std::invalid_argument("culling.prefetch: expected 1..65536");
  if (schedule == Schedule::kTwoPhase && culling.records_per_cycle > 0 && !write_records)
    throw std::invalid_argument(
        "culling.records_per_cycle: in two phases the culling unit reads the hit records from memory, which needs "
        "shading.write_records: true (or records_per_cycle: 0, the ideal unit)");
  if (raygen_rays_per_cycle < 1 || raygen_rays_per_cycle > 64)
    throw std::invalid_argument("raygen.rays_per_cycle: expected 1..64");
  if (tile < 1 || tile > 4096) throw std::invalid_argument("tile: expected 1..4096");
  if (watchdog_cycles < 1000) throw std::invalid_argument("watchdog_cycles: expected at least 1000");
  if (reflection_depth < 0 || reflection_depth > 8) throw std::invalid_argument("reflection_depth: expected 0..8");
  DramConfig d = dram;
  d.request_bytes = trv.l2.line_bytes;
  d.validate();
}

AcceleratorResult simulate_frame(const AcceleratorConfig& cfg, const MemoryImage& image, const Camera& camera,
                                 int width, int height, const SimulationHooks& hooks) {
  cfg.validate();
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const image::Header& h = image.header();
  RayPool pool(cfg.ray_pool);
  ModelContext ctx;
  ctx.pool = &pool;
  ctx.header = h;
  ctx.clock = Clock(cfg.clock_ghz);
  // The reference tracer's constants (reference_tracer.cpp), computed the same way.
  ctx.abs_eps = 1e-6f * std::max(h.bounds.diagonal(), 1e-20f);
  ctx.shadow_offset = 1e-5f * h.bounds.diagonal();

  DramConfig dram_cfg = cfg.dram;
  dram_cfg.request_bytes = cfg.trv.l2.line_bytes;
  // The frame buffer of hit records follows the image (model/hit_record.h).
  const uint64_t entries = uint64_t(width) * uint64_t(height) * uint64_t(cfg.reflection_depth + 1);
  HitRecordRegion records;
  records.base = (image.bytes().size() + 4095) / 4096 * 4096;
  records.stride = std::max(kHitRecordBytes, dram_cfg.request_bytes);
  records.pixels = uint32_t(width) * uint32_t(height);
  {
    auto pixel_at = std::make_shared<std::vector<uint32_t>>(issue_order(width, height, cfg.order, cfg.tile));
    auto slot_of = std::make_shared<std::vector<uint32_t>>(pixel_at->size());
    for (uint32_t k = 0; k < pixel_at->size(); ++k) (*slot_of)[(*pixel_at)[k]] = k;
    records.pixel_at = std::move(pixel_at);
    records.slot_of = std::move(slot_of);
  }
  Dram dram("dram", dram_cfg, &image.bytes(), ctx.clock, records.base - image.bytes().size() + entries * records.stride);
  MemorySystem memory(cfg, &dram, ctx.clock);
  Cache& culling_l1 = memory.l1(MemorySystem::kShading, 0);  // the culling unit reads lights through it

  FrameBuffer frame;
  frame.width = width;
  frame.height = height;
  frame.levels = cfg.reflection_depth + 1;
  frame.pixels.assign(frame.pixel_count() * frame.levels, PixelState{});
  LvbUpdater lvb;

  auto make_fifos = [](const std::string& prefix, uint32_t n, uint32_t depth) {
    std::vector<std::unique_ptr<RayFifo>> v;
    for (uint32_t i = 0; i < n; ++i) v.push_back(std::make_unique<RayFifo>(prefix + std::to_string(i) + ".in", depth));
    return v;
  };
  auto trv_in = make_fifos("trv", cfg.trv.count, cfg.trv.fifo_depth);
  auto list_in = make_fifos("list", cfg.list.count, cfg.list.fifo_depth);
  auto ist_in = make_fifos("ist", cfg.ist.count, cfg.ist.fifo_depth);
  auto shading_in = make_fifos("shading", cfg.shading.count, cfg.shading.fifo_depth);
  // The rays of TRV unit i finish in shading unit i * shading / trv.
  std::vector<RayFifo*> done_by_trv;
  for (uint32_t i = 0; i < cfg.trv.count; ++i) done_by_trv.push_back(shading_in[i * cfg.shading.count / cfg.trv.count].get());

  std::vector<TrvUnit*> trv;
  std::vector<std::unique_ptr<TrvUnit>> trv_owned;
  std::vector<std::unique_ptr<ListUnit>> list;
  std::vector<std::unique_ptr<IstUnit>> ist;
  for (uint32_t k = 0; k < cfg.ist.count; ++k) {
    ist.push_back(std::make_unique<IstUnit>(("ist" + std::to_string(k)).c_str(), ctx, cfg.ist.latency,
                                            cfg.ist.capacity, &memory.l1(MemorySystem::kIst, k), ist_in[k].get(), &trv, &done_by_trv, &lvb));
    for (auto& f : shading_in) f->connect(ist.back().get(), nullptr);
  }
  for (uint32_t j = 0; j < cfg.list.count; ++j) {
    RayFifo* to_ist = ist_in[j * cfg.ist.count / cfg.list.count].get();
    list.push_back(std::make_unique<ListUnit>(("list" + std::to_string(j)).c_str(), ctx, cfg.list.latency,
                                              cfg.list.capacity, &memory.l1(MemorySystem::kList, j), list_in[j].get(), to_ist));
    to_ist->connect(list.back().get(), ist[j * cfg.ist.count / cfg.list.count].get());
  }
  for (uint32_t i = 0; i < cfg.trv.count; ++i) {
    const uint32_t j = i * cfg.list.count / cfg.trv.count;
    trv_owned.push_back(std::make_unique<TrvUnit>(("trv" + std::to_string(i)).c_str(), ctx, cfg.trv.latency,
                                                  cfg.trv.capacity, &memory.l1(MemorySystem::kTrv, i), trv_in[i].get(),
                                                  list_in[j].get(), done_by_trv[i]));
    trv_owned.back()->set_index(uint16_t(i));
    trv.push_back(trv_owned.back().get());
    list_in[j]->connect(trv.back(), list[j].get());
    trv_in[i]->connect(nullptr, trv.back());
    done_by_trv[i]->connect(trv.back(), nullptr);
  }
  std::vector<std::unique_ptr<ShadingUnit>> shading;
  for (uint32_t s = 0; s < cfg.shading.count; ++s) {
    shading.push_back(std::make_unique<ShadingUnit>(("shading" + std::to_string(s)).c_str(), ctx, cfg.shading.latency,
                                                    cfg.shading.capacity, &memory.l1(MemorySystem::kShading, s),
                                                    shading_in[s].get(), &trv, &frame));
    shading_in[s]->connect(nullptr, shading.back().get());
  }
  std::vector<RayFifo*> trv_inputs;
  for (auto& f : trv_in) trv_inputs.push_back(f.get());
  RayGenerator generator("raygen", ctx, camera, width, height, cfg.order, cfg.tile, trv_inputs,
                         cfg.raygen_rays_per_cycle);
  ShadowCullingUnit culling("culling", ctx, cfg.lvb_culling, cfg.culling, &culling_l1, &frame, trv_inputs);
  if (cfg.write_records)
    for (uint32_t s = 0; s < cfg.shading.count; ++s) {
      shading[s]->records = records;
      shading[s]->write_line = [&memory, s](uint64_t line, const uint8_t* data, Tick when) {
        memory.write_line(s, line, data, when);
      };
    }
  if (cfg.schedule == Schedule::kTwoPhase && cfg.culling.records_per_cycle > 0)
    culling.read_records_from(&memory.record_reader(), records);
  for (uint32_t i = 0; i < cfg.trv.count; ++i) memory.l1(MemorySystem::kTrv, i).name_requester(trv[i], "trv");
  for (uint32_t j = 0; j < cfg.list.count; ++j) memory.l1(MemorySystem::kList, j).name_requester(list[j].get(), "list");
  for (uint32_t k = 0; k < cfg.ist.count; ++k) memory.l1(MemorySystem::kIst, k).name_requester(ist[k].get(), "ist");
  for (uint32_t s = 0; s < cfg.shading.count; ++s)
    memory.l1(MemorySystem::kShading, s).name_requester(shading[s].get(), "shading");
  culling_l1.name_requester(&culling, "culling");
  for (auto& f : trv_in) {
    f->connect(&generator, nullptr);
    f->connect(&culling, nullptr);
  }

  if (cfg.schedule == Schedule::kOnePhase)
    for (auto& u : shading) u->on_hit = [&culling](uint32_t entry, Tick ready) { culling.add(entry, ready); };
  // Phase control: the shadow phase starts when the last primary ray retires (two phases); in
  // one phase the culling unit learns there that no more hits will come.
  Tick primary_end = 0, end = 0;
  bool primaries_done = false;
  uint64_t primaries_retired = 0, shadows_retired = 0;
  auto on_retire = [&](RayType type, Tick when) {
    const Tick now = Scheduler::instance().now();
    end = std::max(end, when);
    // A ray slot is free: whoever waits for one.
    if (!generator.finished()) generator.wake(now);
    if (cfg.schedule == Schedule::kOnePhase) culling.wake(now);
    if (type == RayType::kPrimary) {
      ++primaries_retired;
      primary_end = std::max(primary_end, when);
      if (generator.finished() && primaries_retired == generator.issued()) {
        primaries_done = true;
        if (cfg.schedule == Schedule::kTwoPhase) culling.scan_all(std::max(now, primary_end));
        else culling.close(now);
      }
    } else {
      ++shadows_retired;
      culling.wake(now);
    }
  };
  for (auto& u : shading) u->on_retire = on_retire;
  // The watchdog: a run that stops moving names what is stuck.
  std::vector<RayFifo*> fifos;
  for (auto* v : {&shading_in, &trv_in, &list_in, &ist_in})
    for (auto& f : *v) fifos.push_back(f.get());
  std::vector<std::pair<std::string, const RayUnit*>> ray_units;
  for (auto* t : trv) ray_units.push_back({t->name(), t});
  for (auto& u : list) ray_units.push_back({u->name(), u.get()});
  for (auto& u : ist) ray_units.push_back({u->name(), u.get()});
  for (auto& u : shading) ray_units.push_back({u->name(), u.get()});
  auto pending = [&] { return pool.in_flight() > 0 || !generator.finished() || !culling.finished(); };
  Watchdog watchdog(
      "watchdog", ctx.clock, cfg.watchdog_cycles,
      [&] {
        // A DRAM draining its queues (a backlog of posted writes) is progress too.
        uint64_t n = primaries_retired + shadows_retired + generator.unit_stats().operations +
                     culling.unit_stats().operations + dram.stats().reads + dram.stats().writes;
        for (const auto& [name, u] : ray_units) n += u->unit_stats().operations;
        return n;
      },
      pending,
      [&] {
        std::string s = std::to_string(pool.in_flight()) + " rays in flight; non-empty FIFOs:";
        for (const RayFifo* f : fifos)
          if (!f->empty()) s += " " + f->name() + " (" + std::to_string(f->size()) + ")";
        s += "; units holding rays:";
        for (const auto& [name, u] : ray_units)
          if (u->held() > 0) s += " " + name + " (" + std::to_string(u->held()) + ")";
        return s + "; " + culling.state() + "; " + dram.engine().state();
      });
  std::unique_ptr<PeriodicProbe> progress;
  if (hooks.progress) {
    progress = std::make_unique<PeriodicProbe>("progress", ctx.clock.cycles(hooks.progress_cycles), [&](Tick now) {
      Progress p;
      p.phase = primaries_done ? 2 : 1;
      p.cycle = ctx.clock.to_cycles(now);
      p.pixels = uint64_t(width) * uint64_t(height);
      p.primaries_retired = primaries_retired;
      p.shadows_generated = culling.generated();
      p.shadows_retired = shadows_retired;
      p.culling_scanned = culling.decided_fraction();
      hooks.progress(p);
      return pending();
    });
    progress->start_at(0);
  }
  std::unique_ptr<VcdTrace> trace;
  if (!hooks.trace.file.empty()) {
    trace = std::make_unique<VcdTrace>(hooks.trace, ctx.clock);
    for (const RayFifo* f : fifos) trace->add_fifo(f);
    trace->add_unit("raygen", &generator);
    for (const auto& [name, u] : ray_units) trace->add_unit(name, u);
    trace->add_unit("culling", &culling);
    trace->add_counter("rays_in_flight", [&pool] { return uint64_t(pool.in_flight()); });
    trace->start(pending);
  }
  generator.wake(0);
  watchdog.start();
  sc_core::sc_start();
  if (trace) trace->close();
  if (watchdog.fired()) throw std::runtime_error("the accelerator model stopped: " + watchdog.report());
  if (!culling.finished() || shadows_retired != culling.generated())
    throw std::logic_error("simulation ended with rays in flight");
  // The frame ends with the last retirement (the watchdog's last look may come later).

  // Statistics, by name.
  StatsRegistry reg;
  for (Unit* u : std::vector<Unit*>{&generator, &culling}) u->finish_accounting(end);
  for (auto& u : shading) u->finish_accounting(end);
  for (auto* t : trv) t->finish_accounting(end);
  for (auto& u : list) u->finish_accounting(end);
  for (auto& u : ist) u->finish_accounting(end);
  for (RayFifo* f : fifos) f->finish_accounting(end);
  for (uint32_t i = 0; i < trv.size(); ++i) trv[i]->register_stats(reg, "trv.unit" + std::to_string(i));
  for (uint32_t i = 0; i < list.size(); ++i) list[i]->register_stats(reg, "list.unit" + std::to_string(i));
  for (uint32_t i = 0; i < ist.size(); ++i) ist[i]->register_stats(reg, "ist.unit" + std::to_string(i));
  // Unit totals per type, beside the per-instance figures.
  auto add_totals = [&reg](const std::string& type, std::vector<const Unit*> units) {
    for (auto [name, field] : {std::pair{"busy_cycles", &UnitStats::busy_cycles},
                               std::pair{"stalled_cycles", &UnitStats::stalled_cycles},
                               std::pair{"idle_cycles", &UnitStats::idle_cycles},
                               std::pair{"operations", &UnitStats::operations}})
      reg.formula(type + ".total." + name, [units, field = field] {
        uint64_t n = 0;
        for (const Unit* u : units) n += u->unit_stats().*field;
        return double(n);
      }, std::string("all ") + type + " units: " + name);
  };
  add_totals("trv", std::vector<const Unit*>(trv.begin(), trv.end()));
  std::vector<const Unit*> units;
  for (auto& u : list) units.push_back(u.get());
  add_totals("list", units);
  units.clear();
  for (auto& u : ist) units.push_back(u.get());
  add_totals("ist", units);
  units.clear();
  for (auto& u : shading) units.push_back(u.get());
  add_totals("shading", units);
  memory.register_stats(reg, &end);
  for (uint32_t s = 0; s < shading.size(); ++s) shading[s]->register_stats(reg, "shading.unit" + std::to_string(s));
  generator.register_unit_stats(reg, "raygen");
  culling.register_stats(reg, "culling");
  lvb.register_stats(reg, "lvb_updater");
  dram.register_stats(reg, "dram");
  for (RayFifo* f : fifos) {
    const FifoStats& s = f->stats();
    reg.counter("fifo." + f->name() + ".pushes", &s.pushes, "rays pushed");
    reg.counter("fifo." + f->name() + ".max_occupancy", &s.max_occupancy, "largest occupancy");
    reg.counter("fifo." + f->name() + ".full_events", &s.full_events, "pushes refused while full");
    reg.formula("fifo." + f->name() + ".mean_occupancy",
                [&s, end] { return end ? double(s.occupancy_ps) / double(end) : 0.0; }, "time-weighted mean occupancy");
  }

  AcceleratorResult out;
  out.clock_ghz = cfg.clock_ghz;
  out.cycles_total = ctx.clock.to_cycles(ctx.clock.edge_at_or_after(end));
  out.cycles_primary = ctx.clock.to_cycles(ctx.clock.edge_at_or_after(primary_end));
  out.cycles_shadow = out.cycles_total - out.cycles_primary;
  for (const auto& u : shading) {
    out.primary_rays += u->stats().primary_rays;
    out.primary_hits += u->stats().primary_hits;
    out.reflection_rays += u->stats().reflection_rays;
    out.shadow_rays += u->stats().shadow_rays;
  }
  for (const LightStats& l : culling.per_light()) {
    out.shadow_generated.push_back(l.generated);
    out.shadow_culled.push_back(l.culled);
  }
  out.stats = reg.values();

  // The pixels, composed exactly as the reference tracer composes them: the local colour of each
  // hit, blended with its reflection's from the deepest bounce up.
  out.rgb.assign(frame.pixel_count() * 3, 0);
  for (uint32_t i = 0; i < frame.pixel_count(); ++i) {
    Vec3 reflected = kBackground;
    for (int level = frame.levels - 1; level >= 0; --level) {
      const PixelState& px = frame.at(i, level);
      if (px.hit.tri == kNoHit) {
        reflected = kBackground;
        continue;
      }
      Vec3 c = kAmbient * px.diffuse;
      for (uint32_t l = 0; l < h.light_count; ++l) {
        if ((px.occluded >> l) & 1u) continue;
        const image::LightRecord light = image.light(l);
        c += light_contribution(px.surface, px.diffuse, light.position, light.color);
      }
      if (px.reflectance > 0.f && level + 1 < frame.levels) c = (1.f - px.reflectance) * c + px.reflectance * reflected;
      reflected = c;
    }
    for (int k = 0; k < 3; ++k) out.rgb[3 * size_t(i) + k] = to_display(reflected[k]);
  }
  out.frame = std::move(frame);
  return out;
}

}  // namespace rtsim::model
