#include "model/energy/energy_model.h"

#include "model/accelerator_units.h"
#include "model/sim/report.h"

#include <string>

namespace rtsim::model {

namespace {

// The frame's statistics by dotted name.
class Stats {
 public:
  explicit Stats(const nlohmann::json& j) : j_(j) {}
  double get(const std::string& name) const {
    const nlohmann::json* n = find(name);
    if (!n) report_error(kReportInternal, "energy: no statistic '" + name + "' to price");
    return n->get<double>();
  }
  bool has(const std::string& name) const { return find(name) != nullptr; }
  double get_or(const std::string& name, double fallback) const {
    const nlohmann::json* n = find(name);
    return n ? n->get<double>() : fallback;
  }
  // name_0 + ... while `<prefix><i><suffix>` exists (per light: culling.light<i>.decisions).
  double sum(const std::string& prefix, const std::string& suffix) const {
    double s = 0;
    for (int i = 0;; ++i) {
      const nlohmann::json* n = find(prefix + std::to_string(i) + suffix);
      if (!n) return s;
      s += n->get<double>();
    }
  }

 private:
  const nlohmann::json* find(const std::string& name) const {
    const nlohmann::json* n = &j_;
    size_t from = 0;
    while (from <= name.size()) {
      const size_t dot = std::min(name.find('.', from), name.size());
      const auto it = n->find(name.substr(from, dot - from));
      if (it == n->end()) return nullptr;
      n = &*it;
      from = dot + 1;
    }
    return n->is_number() ? n : nullptr;
  }
  const nlohmann::json& j_;
};

// The DRAM command cycles of a frame of `frame_ns`, per channel: the span its background is charged
// over (and what the trace's pricing is told, dram_model_json).
uint64_t dram_span_cycles(const DramConfig& d, double frame_ns) {
  return uint64_t(frame_ns * 1000.0 / double(d.tCK_ps));
}

// A cache level: `instances` arrays of `c`, read per access and written per fill, leaking for
// the frame.
EnergyPart price_cache(const EnergyConfig& e, const Stats& s, const std::string& key,
                       const std::string& label, const char* level, const CacheConfig& c,
                       uint32_t instances, double frame_ns) {
  EnergyPart p{key, label, level};
  const double bank = double(c.size_bytes) / c.banks;
  const double access = e.sram_access_pj(bank, c.line_bytes);
  p.reads = uint64_t(s.get(key + ".accesses"));
  p.writes = uint64_t(s.get(key + ".fills"));
  p.dynamic_pj = double(p.reads) * access + double(p.writes) * access * e.write_factor;
  // mW x ns = pJ
  p.static_pj = e.leakage_mw.at(bank) * c.banks * instances * frame_ns;
  return p;
}

// A crossbar (both networks): its flits, each a flit's bytes. `key`: the type's (trv.icnt), or
// with private L2s each unit's (trv<i>.icnt, unit given).
EnergyPart price_link(const EnergyConfig& e, const Stats& s, const std::string& key,
                      const std::string& label, const LinkConfig& link, const std::string& unit) {
  EnergyPart p{key, label, ""};
  double flits = 0;
  for (const char* dir : {".request.flits", ".reply.flits"})
    flits += unit.empty() ? s.get(key + dir) : s.sum(unit, std::string(".icnt") + dir);
  p.reads = uint64_t(flits) * link.bytes_per_cycle;
  p.dynamic_pj = double(p.reads) * e.link_pj_per_byte;
  return p;
}

void price_units(const AcceleratorConfig& cfg, const EnergyConfig& e, const Stats& s,
                 FrameEnergy& out) {
  // The blocks outside the table: the generator makes each primary ray; the culling unit reads
  // an LVB bit per decision (culling on) and makes each shadow ray it does not cull.
  EnergyPart raygen{"raygen", "ray generator", ""};
  raygen.dynamic_pj = double(out.rays[size_t(RayType::kPrimary)]) * e.operation("ray_generation");
  out.units.push_back(raygen);
  for (const RayUnitType* t : unit_types(cfg)) {
    EnergyPart p{t->key, t->label, ""};
    for (const WorkCounter& w : t->work)
      if (w.op)
        p.dynamic_pj += s.get(std::string(t->key) + ".total." + w.counter) * e.operation(w.op);
    out.units.push_back(p);
  }
  EnergyPart culling{"culling", "shadow culling", ""};
  if (cfg.lvb_culling)
    culling.dynamic_pj += s.sum("culling.light", ".decisions") * e.operation("lvb_lookup");
  culling.dynamic_pj += s.sum("culling.light", ".generated") * e.operation("light_sample");
  out.units.push_back(culling);
}

void price_memory(const AcceleratorConfig& cfg, const EnergyConfig& e, const Stats& s,
                  FrameEnergy& out) {
  for (const RayUnitType* t : unit_types(cfg)) {
    const UnitTypeConfig& u = cfg.*t->config;
    const std::string key = t->key;
    out.caches.push_back(
        price_cache(e, s, key + ".l1", t->label, "L1", u.l1, u.count, out.frame_ns));
    if (t->l2_of != t->stage) continue;
    const uint32_t l2s = u.l2_sharing == L2Sharing::kUnit ? u.count : 1;
    out.caches.push_back(price_cache(e, s, key + ".l2", t->label, "L2", u.l2, l2s, out.frame_ns));
    out.links.push_back(price_link(e, s, key + ".icnt", t->label, u.link,
                                   u.l2_sharing == L2Sharing::kUnit ? key : ""));
  }
  // The culling unit's own L1 (culling.l1: own), a shading L1's configuration.
  if (cfg.culling.l1 == CullingL1::kOwn)
    out.caches.push_back(
        price_cache(e, s, "culling.l1", "shadow culling", "L1", cfg.shading.l1, 1, out.frame_ns));
  out.links.push_back(price_link(e, s, "memory.icnt", "L2 to memory", cfg.memory_link, ""));
  if (!s.has("dram.activates")) return;  // a memory outside the model: not priced here
  const DramConfig& d = cfg.dram;
  DramActivity a;
  a.activates = uint64_t(s.get("dram.activates"));
  a.precharges = uint64_t(s.get("dram.precharges"));
  a.read_bursts = uint64_t(s.get("dram.bursts"));
  a.write_bursts = uint64_t(s.get("dram.write_bursts"));
  a.refreshes = uint64_t(s.get_or("dram.refreshes", 0));  // registered when the DRAM refreshes
  a.active_cycles = uint64_t(s.get("dram.active_cycles"));
  const uint64_t span = dram_span_cycles(d, out.frame_ns) * d.channels;
  a.precharged_cycles = span > a.active_cycles ? span - a.active_cycles : 0;
  out.dram = dram_energy(d.power, d.energy_timing(), a);
}

// FrameEnergy::ray_type_pj: each type's own work, the walk-driven rest by node fetches, the
// static energy by the dynamic shares.
void share_by_ray_type(const AcceleratorConfig& cfg, const EnergyConfig& e, const Stats& s,
                       FrameEnergy& out) {
  constexpr size_t P = size_t(RayType::kPrimary), R = size_t(RayType::kReflection),
                   S = size_t(RayType::kShadow), B = size_t(RayType::kBounce);
  std::array<double, kRayTypes> own{}, fetches{};
  const double shade = e.operation("shade");
  own[P] = out.units.front().dynamic_pj;  // the generator's
  own[P] += s.get_or("shading.total.primary_hits", 0) * shade;
  own[R] += s.get_or("shading.total.reflection_hits", 0) * shade;
  own[B] += s.get_or("shading.total.bounce_hits", 0) * shade +
            s.get_or("shading.total.bounce_rays", 0) * e.operation("bounce_sample");
  own[S] += out.units.back().dynamic_pj;  // the culling unit's
  const std::string walk = std::string(unit_types(cfg)[kTrvStage]->key) + ".total.node_fetches_";
  double all_fetches = 0, all_own = 0;
  for (size_t t = 0; t < kRayTypes; ++t) {
    fetches[t] = s.get_or(walk + ray_type_name(t), 0);
    all_fetches += fetches[t];
    all_own += own[t];
  }
  // A traversal type that does not split its fetches: its rays stand for them.
  if (all_fetches == 0)
    for (size_t t = 0; t < kRayTypes; ++t) all_fetches += fetches[t] = double(out.rays[t]);
  const double rest = out.dynamic_pj() - all_own, leak = out.static_pj();
  const double dynamic = out.dynamic_pj();
  for (size_t t = 0; t < kRayTypes; ++t) {
    const double d = own[t] + (all_fetches > 0 ? rest * fetches[t] / all_fetches : 0.0);
    out.ray_type_pj[t] = d + (dynamic > 0 ? leak * d / dynamic : 0.0);
  }
}

template <class F>
double sum(const std::vector<EnergyPart>& parts, F f) {
  double s = 0;
  for (const EnergyPart& p : parts) s += f(p);
  return s;
}

}  // namespace

double FrameEnergy::dynamic_pj() const {
  const auto dyn = [](const EnergyPart& p) { return p.dynamic_pj; };
  return sum(units, dyn) + sum(caches, dyn) + sum(links, dyn) + dram.total() - dram.background;
}

double FrameEnergy::static_pj() const {
  const auto leak = [](const EnergyPart& p) { return p.static_pj; };
  return sum(units, leak) + sum(caches, leak) + sum(links, leak) + dram.background;
}

FrameEnergy price_frame(const AcceleratorConfig& cfg, const EnergyConfig& energy,
                        const nlohmann::json& stats, double frame_ns, const PerRayType& rays) {
  FrameEnergy out;
  out.node = energy.node;
  out.frame_ns = frame_ns;
  out.rays = rays;
  const Stats s(stats);
  price_units(cfg, energy, s, out);
  price_memory(cfg, energy, s, out);
  share_by_ray_type(cfg, energy, s, out);
  return out;
}

namespace {

constexpr double kPjPerUj = 1e6;

nlohmann::json parts_json(const std::vector<EnergyPart>& parts, bool cache) {
  nlohmann::json out = nlohmann::json::array();
  for (const EnergyPart& p : parts) {
    nlohmann::json j = {
        {"key", p.key}, {"label", p.label}, {"dynamic_uj", p.dynamic_pj / kPjPerUj}};
    if (cache) {
      j["level"] = p.level;
      j["static_uj"] = p.static_pj / kPjPerUj;
      j["reads"] = p.reads;
      j["writes"] = p.writes;
    }
    out.push_back(std::move(j));
  }
  return out;
}

// What the DRAM's terms were computed from: with a command trace (rtsim run --dram-commands),
// an outside tool prices the same stream (scripts/price-dram-trace.py).
nlohmann::json dram_model_json(const DramConfig& d, double frame_ns) {
  nlohmann::json rails = nlohmann::json::array();
  for (const DramCurrents* r : {&d.power.core, &d.power.aux, &d.power.io})
    if (r->vdd > 0)
      rails.push_back({{"vdd", r->vdd},
                       {"idd0", r->idd0},
                       {"idd2n", r->idd2n},
                       {"idd3n", r->idd3n},
                       {"idd4r", r->idd4r},
                       {"idd4w", r->idd4w},
                       {"idd5", r->idd5}});
  const DramEnergyTiming t = d.energy_timing();
  return {{"tck_ns", t.tck_ns},
          {"channels", d.channels},
          {"banks", d.banks},
          {"tRAS", t.tRAS},
          {"tRC", t.tRC},
          {"tRFC", t.tRFC},
          {"burst_cycles", t.burst_cycles},
          {"devices", t.devices},
          {"rails", rails},
          {"span_cycles", dram_span_cycles(d, frame_ns)}};
}

}  // namespace

nlohmann::json energy_json(const FrameEnergy& e, const DramConfig& dram, Integrator integrator) {
  nlohmann::json by_type = nlohmann::json::object();
  uint64_t rays = 0;
  for (size_t t = 0; t < kRayTypes; ++t) {
    const bool nee = t == size_t(RayType::kShadow) && integrator == Integrator::kPath;
    const double pj = e.ray_type_pj[t];
    rays += e.rays[t];
    by_type[nee ? "nee" : ray_type_name(t)] = {
        {"uj", pj / kPjPerUj},
        {"rays", e.rays[t]},
        {"nj_per_ray", e.rays[t] > 0 ? pj / 1000.0 / double(e.rays[t]) : 0.0}};
  }
  const DramEnergy& d = e.dram;
  nlohmann::json levels = nlohmann::json::object();
  for (const EnergyPart& c : e.caches)
    levels[c.level] = levels.value(c.level, 0.0) + c.total_pj() / kPjPerUj;
  const double total = e.total_pj();
  return {{"node", e.node},
          {"frame_ns", e.frame_ns},
          {"total_uj", total / kPjPerUj},
          {"dynamic_uj", e.dynamic_pj() / kPjPerUj},
          {"static_uj", e.static_pj() / kPjPerUj},
          // pJ / ns = mW
          {"average_power_w", e.frame_ns > 0 ? total / e.frame_ns / 1000.0 : 0.0},
          {"nj_per_ray", rays > 0 ? total / 1000.0 / double(rays) : 0.0},
          {"edp_uj_ms", total / kPjPerUj * e.frame_ns / 1e6},
          {"units", parts_json(e.units, false)},
          {"caches", parts_json(e.caches, true)},
          {"cache_levels_uj", levels},
          {"links", parts_json(e.links, false)},
          {"ray_types", by_type},
          {"dram",
           {{"dynamic_uj", (d.total() - d.background) / kPjPerUj},
            {"static_uj", d.background / kPjPerUj},
            {"pj",
             {{"activate", d.activate},
              {"precharge", d.precharge},
              {"read", d.read},
              {"write", d.write},
              {"refresh", d.refresh},
              {"background", d.background}}},
            {"model", dram_model_json(dram, e.frame_ns)}}}};
}

}  // namespace rtsim::model
