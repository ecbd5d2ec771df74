#include "model/memory/client_caches.h"

#include "model/sim/report.h"

namespace rtsim::model {

ClientCaches::ClientCaches(const TypeMemoryConfig& cfg, bool private_l2, const Clock& clock,
                           const FillListener* requester, const std::string& type)
    : mem_side("mem_side") {
  if (private_l2) {
    l2_ = std::make_unique<Cache>("l2", cfg.l2, clock, nullptr);
    icnt_ = std::make_unique<Crossbar>("icnt", cfg.link, clock, 1, cfg.l2.banks);
    to_l2_ = std::make_unique<CrossbarPort>(icnt_.get(), 0, 1, l2_.get(), cfg.l2.line_bytes);
    l2_->name_requester(to_l2_.get(), type);
  }
  l1_ = std::make_unique<Cache>("l1", cfg.l1, clock, to_l2_.get());
  l1_->name_requester(requester, type);
}

ClientCaches::~ClientCaches() = default;

void ClientCaches::connect_below() { (l2_ ? *l2_ : *l1_).connect(*mem_side[0]); }

void ClientCaches::invalidate() {
  l1_->invalidate();
  if (l2_) l2_->invalidate();
}

void ClientCaches::register_stats(StatsRegistry& r, const sc_core::sc_object& top,
                                  const Tick* span) const {
  l1_->register_stats(r, stat_prefix(*l1_, top));
  if (!l2_) return;
  l2_->register_stats(r, stat_prefix(*l2_, top));
  icnt_->register_stats(r, stat_prefix(*icnt_, top), span);
}

void register_cache_totals(StatsRegistry& r, const std::string& prefix,
                           std::vector<const Cache*> caches) {
  std::vector<const CacheStats*> parts;
  for (const Cache* c : caches) parts.push_back(&c->stats());
  register_totals(r, prefix, "all of " + prefix + ": ", parts,
                  {"accesses", "hits", "misses", "mshr_merges", "fills"},
                  [](auto& v, const CacheStats& s) { describe_stats(v, s, false, false); });
  r.formula(
      prefix + ".hit_rate",
      [parts] {
        uint64_t h = 0, a = 0;
        for (const CacheStats* s : parts) h += s->hits, a += s->accesses;
        return a > 0 ? double(h) / double(a) : 0.0;
      },
      "ratio", "all of " + prefix + ": hits / accesses");
}

}  // namespace rtsim::model
