#include "model/accelerator_netlist.h"
#include "model/energy/energy_model.h"

#include "kernels/bvh_format.h"

namespace rtsim::model {

// A whole memory line, so that a record is one write and no two pixels share a line.
uint32_t record_stride(const AcceleratorConfig& config) {
  return std::max(kHitRecordBytes, config.memory_dram().request_bytes);
}

MemoryLayout memory_layout(const AcceleratorConfig& config, uint64_t image_bytes, int width,
                           int height, uint64_t image_base) {
  MemoryLayout l;
  l.image_base = image_base;
  l.image_bytes = image_bytes;
  l.fb_base = frame_buffer_after(image_base, image_bytes);
  l.record_stride = record_stride(config);
  l.fb_bytes = regs::frame_buffer_bytes(uint32_t(std::max(width, 0)), uint32_t(std::max(height, 0)),
                                        config.entries_per_pixel(), l.record_stride);
  return l;
}

namespace {

HitRecordRegion record_region(const AcceleratorConfig& cfg, const FrameProgram& p) {
  HitRecordRegion records;
  records.base = p.fb_base;
  records.stride = record_stride(cfg);
  records.pixels = uint32_t(p.width) * uint32_t(p.height);
  auto pixel_at =
      std::make_shared<std::vector<uint32_t>>(issue_order(p.width, p.height, cfg.order, cfg.tile));
  auto slot_of = std::make_shared<std::vector<uint32_t>>(pixel_at->size());
  for (uint32_t k = 0; k < pixel_at->size(); ++k) (*slot_of)[(*pixel_at)[k]] = k;
  records.pixel_at = std::move(pixel_at);
  records.slot_of = std::move(slot_of);
  return records;
}

// Each window's batches.
std::vector<WindowBatches> windows_of(const Clock& clock, const std::vector<DetailWindow>& windows,
                                      uint64_t total, const std::vector<std::vector<Tick>>& starts,
                                      Tick end) {
  std::vector<WindowBatches> out;
  for (size_t w = 0; w < windows.size(); ++w)
    out.push_back(window_batches(clock, windows[w], total, starts[w], end));
  return out;
}

// The header as the units use it: section addresses in memory.
image::Header placed(image::Header h, uint64_t image_base) {
  for (image::Section* s : {&h.nodes, &h.leaves, &h.prims, &h.triangles, &h.materials, &h.lights})
    s->base += uint32_t(image_base);
  return h;
}

}  // namespace

// A frame: the context's scene layout and constants, the frame buffer and its region in memory,
// the units' frame state; empty caches (the platform may have changed memory since the last
// frame); then the first ray at the first edge at or after `at`.
void Accelerator::Netlist::begin_frame(const FrameProgram& p, Tick at) {
  const Tick begin = ctx.clock.edge_at_or_after(at);
  const image::Header& h = p.header;
  ctx.header = placed(h, p.image_base);
  ctx.bvh = is_bvh(h.accel);
  ctx.bvh_format = ctx.bvh ? bvh_formats().find(h.accel) : nullptr;
  // The reference tracer's constants (reference_tracer.cpp), computed the same way.
  ctx.abs_eps = 1e-6f * std::max(h.bounds.diagonal(), 1e-20f);
  ctx.shadow_offset = 1e-5f * h.bounds.diagonal();
  ctx.light_samples = p.light_samples;
  job = FrameJob{p.camera, p.width, p.height};
  frame = FrameBuffer{};
  frame.width = p.width;
  frame.height = p.height;
  frame.levels = cfg.levels();
  frame.paths = cfg.paths_per_pixel();
  frame.allocate(ctx.light_samples);
  records = record_region(cfg, p);
  if (hooks.statistics == SimulationHooks::Statistics::kPerFrame) reset_stats(begin);
  invalidate_caches();
  faults_before = faults.total();
  pool.begin_frame();
  if (!windows.empty())
    if (const std::string why = check_windows(windows, uint64_t(p.width) * uint64_t(p.height));
        !why.empty())
      report_error(kReportConfig, std::string(top.name()) + ": sampling: " + why);
  generator->begin_frame(p.camera, p.width, p.height, windows);
  culling->begin_frame(p.lvb_culling, windows);
  phases.begin_frame(begin);
  frame_begin = begin;
  frame_active = true;
  collected = false;
  generator->wake(begin);
  watchdog->start();
  if (progress) progress->start_at(begin);
  if (trace && frames == 0) trace->start();
  ++frames;
}

void Accelerator::Netlist::reset_stats(Tick at) {
  // The time before `at` (the idle time since the last frame) goes to the window that ends.
  generator->finish_accounting(at);
  culling->finish_accounting(at);
  for (RayUnit* u : ray_units) u->finish_accounting(at);
  for (RayFifo* f : fifos) f->finish_accounting(at);
  if (dram) dram->settle_active(at);
  if (dram) dram->restart_command_trace();  // its rows are what the counters count
  stats.reset();
  stats_begin = at;
}

void Accelerator::Netlist::close_traces() {
  if (trace) trace->close();
  memory->interconnect().port().close_trace();
  if (dram) dram->close_command_trace();
}

void Accelerator::Netlist::collect() {
  close_traces();
  // The frame ends with the last retirement (the watchdog's last look may come later).
  end = phases.end();
  generator->finish_accounting(end);
  culling->finish_accounting(end);
  for (RayUnit* u : ray_units) u->finish_accounting(end);
  for (RayFifo* f : fifos) f->finish_accounting(end);
  if (dram) dram->settle_active(end);
  frame.close_samples();
  stats_span = end > stats_begin ? end - stats_begin : 0;
  collected = true;
}

void Accelerator::Netlist::check_frame_end() {
  if (!frame_active || !phases.finished() || memory->interconnect().port().in_flight() > 0) return;
  frame_active = false;
  const Tick end_edge = ctx.clock.edge_at_or_after(phases.end());
  const uint64_t cycles = ctx.clock.to_cycles(end_edge) - ctx.clock.to_cycles(frame_begin);
  // A frame whose rays met memory that is not an image ends as any other (they retired as
  // misses), with the error latched in STATUS.
  const uint32_t error = faults.total() > faults_before ? regs::kBadImage : regs::kNoError;
  registers->frame_ended(cycles, std::max(calendar.now(), end_edge), error);
}

void Accelerator::sample(std::vector<DetailWindow> windows, WarmSource warm) {
  const AcceleratorConfig& config = net_->cfg;
  std::string why;
  if (config.schedule != Schedule::kTwoPhase) why = "a sampled frame runs in two phases";
  if (config.culling.records_per_cycle == 0 || !config.write_records)
    why =
        "a sampled frame's culling unit reads the records from memory (records_per_cycle > 0, "
        "write_records)";
  if (config.reflection_depth > 0) why = "a sampled frame has no reflections";
  if (config.integrator != Integrator::kWhitted) why = "a sampled frame is a Whitted frame";
  if (warm && !net_->dram) why = "functional warming reads the built-in memory";
  if (!why.empty()) report_error(kReportConfig, std::string(name()) + ": sampling: " + why);
  net_->windows = std::move(windows);
  net_->warm = std::move(warm);
  Netlist& n = *net_;
  n.generator->on_window = [&n](uint64_t first_ray) {
    if (n.warm) n.warm(first_ray, n);
  };
}

Accelerator::Accelerator(sc_core::sc_module_name name, const AcceleratorConfig& config,
                         const SimulationHooks& hooks, MemoryTarget memory)
    : sc_core::sc_module(name), irq("irq") {
  build(config, hooks, memory, nullptr, nullptr);
}

Accelerator::Accelerator(sc_core::sc_module_name name, const AcceleratorConfig& config,
                         const MemoryImage& image, const FrameJob& job,
                         const SimulationHooks& hooks, MemoryTarget memory)
    : sc_core::sc_module(name), irq("irq") {
  build(config, hooks, memory, &image, &job);
}

void Accelerator::build(const AcceleratorConfig& config, const SimulationHooks& hooks,
                        MemoryTarget memory, const MemoryImage* image, const FrameJob* job) {
  try {
    config.validate();
  } catch (const std::invalid_argument& e) {
    report_error(kReportConfig, std::string(this->name()) + ": " + e.what());
  }
  FrameSetup setup;
  uint64_t image_memory_bytes = 0;
  if (image) {
    setup = frame_after_image(*image, job->camera, job->width, job->height, config.lvb_culling);
    image_memory_bytes =
        memory_layout(config, image->bytes().size(), job->width, job->height).end();
  }
  net_ = std::make_unique<Netlist>(*this, config, hooks, memory, image, image_memory_bytes);
  if (image) {
    net_->preset = program_writes(*image, setup);
    SC_METHOD(start);  // runs once, when the simulation starts
  }
}

Accelerator::~Accelerator() = default;

void Accelerator::end_of_elaboration() {
  if (net_->trace) net_->trace->end_of_elaboration();
}

void Accelerator::start() {
  ControlRegisters& r = *net_->registers;
  for (const RegisterWrite& w : net_->preset) r.write(w.offset, w.value, 0);
  r.write(regs::kControl, regs::kStart, 0);
  if (const uint32_t error = r.read(regs::kStatus) >> regs::kErrorShift)
    report_error(kReportDevice, std::string(name()) + ": the frame given at construction was " +
                                    "refused (STATUS error " + std::to_string(error) + ")");
}

bool Accelerator::finished() const { return net_->phases.finished(); }

const StatsRegistry& Accelerator::stats() const { return net_->stats; }

tlm::tlm_initiator_socket<>& Accelerator::memory_socket() { return net_->memory_socket(); }

Accelerator::TargetSocket& Accelerator::register_socket() { return net_->registers->socket; }

Accelerator::TargetSocket& Accelerator::memory_host_socket() {
  if (!net_->dram)
    report_error(kReportInternal, std::string(name()) + ": no built-in memory to load");
  return net_->dram->host_socket;
}

uint64_t Accelerator::memory_bytes() const { return net_->memory_bytes; }

namespace {

// report.json's `energy` for a frame's result (model/energy/energy_model.h).
nlohmann::json priced(const AcceleratorConfig& cfg, const AcceleratorResult& out, double frame_ns) {
  PerRayType rays{};
  rays[size_t(RayType::kPrimary)] = out.primary_rays;
  rays[size_t(RayType::kReflection)] = out.reflection_rays;
  rays[size_t(RayType::kShadow)] = out.shadow_rays;
  rays[size_t(RayType::kBounce)] = out.bounce_rays;
  const FrameEnergy e = price_frame(cfg, energy_config(cfg.energy), out.stats, frame_ns, rays);
  return energy_json(e, cfg.dram, cfg.integrator);
}

}  // namespace

AcceleratorResult Accelerator::result() {
  Netlist& n = *net_;
  if (!finished())
    report_error(kReportInternal,
                 std::string(name()) + ": the simulation ended with rays in flight");
  if (n.checker && n.checker->open_transactions() > 0)
    report_error(kReportTlm, std::string(n.checker->name()) + ": " +
                                 std::to_string(n.checker->open_transactions()) +
                                 " transactions never ended");
  if (!n.collected) n.collect();
  AcceleratorResult out;
  out.clock_ghz = n.cfg.clock_ghz;
  const uint64_t first = n.ctx.clock.to_cycles(n.frame_begin);
  out.cycles_total = n.ctx.clock.to_cycles(n.ctx.clock.edge_at_or_after(n.end)) - first;
  out.cycles_primary =
      n.ctx.clock.to_cycles(n.ctx.clock.edge_at_or_after(n.phases.primary_end())) - first;
  out.cycles_shadow = out.cycles_total - out.cycles_primary;
  out.primary_windows = windows_of(n.ctx.clock, n.generator->windows(), n.generator->total(),
                                   n.generator->window_starts(), n.phases.primary_end());
  out.shadow_windows = windows_of(n.ctx.clock, n.culling->windows(), n.frame.pixels.size(),
                                  n.culling->window_starts(), n.end);
  if (n.windows.empty()) {  // a whole frame: one window each
    out.primary_batch_cycles = std::move(out.primary_windows[0].cycles);
    if (!out.shadow_windows.empty())
      out.shadow_batch_cycles = std::move(out.shadow_windows[0].cycles);
    out.primary_windows.clear();
    out.shadow_windows.clear();
  }
  out.bounces.resize(n.culling->per_bounce().size());
  for (uint32_t s = 0; s < n.cfg.shading.count; ++s) {
    const ShadingStats& u = n.shading(s).stats();
    out.primary_rays += u.primary_rays;
    out.primary_hits += u.primary_hits;
    out.reflection_rays += u.reflection_rays;
    out.bounce_rays += u.bounce_rays;
    out.shadow_rays += u.shadow_rays;
    for (size_t b = 0; b < out.bounces.size(); ++b) {
      const BounceStats& from = n.shading(s).bounces()[b];
      BounceFigures& to = out.bounces[b];
      to.rays += from.rays;
      to.hits += from.hits;
      to.ray_cycles += from.ray_cycles;
      to.shadow_rays += from.shadow_rays;
      to.shadow_occluded += from.shadow_occluded;
      to.shadow_cycles += from.shadow_cycles;
    }
  }
  for (size_t b = 0; b < out.bounces.size(); ++b) {
    out.bounces[b].shadow_decisions = n.culling->per_bounce()[b].decisions;
    out.bounces[b].shadow_culled = n.culling->per_bounce()[b].culled;
  }
  for (const LightStats& l : n.culling->per_light()) {
    out.shadow_generated.push_back(l.generated);
    out.shadow_culled.push_back(l.culled);
  }
  out.stats = n.stats.values();
  out.units = report_units(n.cfg);
  out.caches = report_caches(n.cfg);
  // Priced over the time the statistics span (a sampled frame's windows are not a frame's work).
  if (n.cfg.energy != "none" && n.windows.empty())
    out.energy = priced(n.cfg, out, double(n.stats_span) / 1000.0);
  out.glossary = n.stats.glossary();
  out.frame = n.frame;
  return out;
}

}  // namespace rtsim::model
