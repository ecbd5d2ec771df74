#include "model/memory/cache.h"

#include "model/sim/report.h"

#include <algorithm>
#include <cstring>
#include <memory>
#include <stdexcept>
#include <utility>

namespace rtsim::model {

namespace {

bool is_pow2(uint64_t v) { return v != 0 && (v & (v - 1)) == 0; }

[[noreturn]] void bad(const char* field, const std::string& why) {
  throw std::invalid_argument(std::string("CacheConfig.") + field + ": " + why);
}

}  // namespace

void CacheConfig::validate() const {
  // The ranges of describe(); a cache built in code may be smaller than the files' 1 KB.
  if (size_bytes == 0) bad("size_bytes", "must be positive");
  RangeCheck check("CacheConfig");
  describe(check, *this);
  if (!is_pow2(line_bytes)) bad("line_bytes", "must be a power of two >= 4");
  if (size_bytes % line_bytes != 0) bad("size_bytes", "must be a multiple of line_bytes");
  const uint64_t lines = size_bytes / line_bytes;
  if (ways > lines) bad("ways", "exceeds the number of lines (" + std::to_string(lines) + ")");
  if (lines % ways != 0) bad("size_bytes", "must be a multiple of ways * line_bytes");
  if (!is_pow2(lines / ways))
    bad("size_bytes", "sets (" + std::to_string(lines / ways) + ") must be a power of two");
  if (!is_pow2(banks) || banks > lines / ways)
    bad("banks", "must be a power of two of at most the number of sets (" +
                     std::to_string(lines / ways) + ")");
}

Cache::Cache(const char* name, const CacheConfig& cfg, const Clock& clock, LineSource* below)
    : sc_core::sc_object(name), cfg_(cfg), clock_(clock), below_(below) {
  try {
    cfg_.validate();
  } catch (const std::invalid_argument& e) {
    report_error(kReportConfig, std::string(this->name()) + ": " + e.what());
  }
  hit_ticks_ = clock_.cycles(cfg_.hit_latency);
  line_shift_ = 0;
  while ((1u << line_shift_) < cfg_.line_bytes) ++line_shift_;
  set_mask_ = cfg_.sets() - 1;
  const size_t n = size_t(cfg_.sets()) * cfg_.ways;
  ways_.assign(n, Way{});
  data_.assign(n * cfg_.line_bytes, 0);
  mshrs_.resize(cfg_.mshrs);
  mshr_free_at_.assign(cfg_.mshrs, 0);
  if (cfg_.ports > 0) banks_.assign(cfg_.banks, PortSchedule(clock_.period(), cfg_.ports));
}

void Cache::invalidate() {
  if (awaiting_ > 0 || !queued_.empty())
    report_error(kReportInternal, std::string(name()) + ": invalidated with misses in flight");
  std::fill(ways_.begin(), ways_.end(), Way{});
}

bool Cache::warm(uint64_t line, const uint8_t* bytes) {
  if (line & (cfg_.line_bytes - 1)) misaligned(line);
  if (awaiting_ > 0 || !queued_.empty()) return true;  // a window still draining: left as it is
  const uint32_t base = set_base(line);
  uint32_t victim = base;
  for (uint32_t i = base; i < base + cfg_.ways; ++i) {
    if (ways_[i].tag == line) {
      ways_[i].lru = ++stamp_;
      return true;
    }
    if (ways_[i].lru < ways_[victim].lru) victim = i;
  }
  Way& v = ways_[victim];
  v.tag = line;
  v.lru = ++stamp_;
  v.ready = 0;
  std::memcpy(&data_[size_t(victim) * cfg_.line_bytes], bytes, cfg_.line_bytes);
  return false;
}

void Cache::name_requester(const FillListener* requester, const std::string& type) {
  const auto it = std::find(type_names_.begin(), type_names_.end(), type);
  const uint32_t index = uint32_t(it - type_names_.begin());
  if (it == type_names_.end()) {
    type_names_.push_back(type);
    stall_cycles_by_type_.push_back(0);
  }
  requester_type_.push_back({requester, index});
  stall_type_.known = false;
}

void Cache::count_bank_stall(uint64_t wait, const FillListener* requester) {
  ++stats_.bank_stall_events;
  stats_.bank_stall_cycles += wait;
  // The last requester's type is kept: an L1 has one requester, and an L2's come in runs.
  if (!stall_type_.known || stall_type_.requester != requester) {
    uint32_t type = 0;
    for (const auto& [who, t] : requester_type_)
      if (who == requester) type = t;
    stall_type_ = {true, requester, type};
  }
  stall_cycles_by_type_[stall_type_.type] += wait;
}

Tick Cache::fill_slot(uint64_t line, Tick when) {
  if (banks_.empty() || cfg_.fill_port == FillPort::kSeparate) return when;
  const Tick slot = banks_[port_of(line)].reserve(when);
  stats_.fill_stall_cycles += ceil_cycles(slot - when);
  return slot;
}

uint32_t Cache::find_way(uint64_t line) const {
  const uint32_t base = set_base(line);
  for (uint32_t i = base; i < base + cfg_.ways; ++i)
    if (ways_[i].tag == line) return i;
  return kNoWay;
}

void Cache::misaligned(uint64_t line) const {
  report_error(kReportInternal, std::string(name()) + ": line address " + std::to_string(line) +
                                    " not line-aligned");
}

Tick Cache::access(uint64_t line, Tick now, FillListener* listener, uint64_t cookie, Tick arrival,
                   bool requeued) {
  const uint32_t base = set_base(line);
  for (uint32_t i = base; i < base + cfg_.ways; ++i) {
    Way& way = ways_[i];
    if (way.tag != line) continue;
    way.lru = ++stamp_;
    if (requeued && now > arrival) stats_.mshr_stall_cycles += ceil_cycles(now - arrival);
    const Tick earliest = now + hit_ticks_;
    if (way.ready <= now) {
      ++stats_.hits;
      return earliest;
    }
    Mshr& m = mshrs_[way.mshr];
    if (cfg_.max_merge > 0 && m.line == line && m.merged >= cfg_.max_merge) {
      // Its MSHR serves no more requests: served by the fill, as a hit then
      ++stats_.merge_full_events;
      if (!requeued) ++stats_.mshr_stall_events;
      if (way.ready == kUnknown) {
        queued_.push_back({line, listener, cookie, arrival});
        return kUnknown;
      }
      stats_.mshr_stall_cycles += ceil_cycles(way.ready - now);
      ++stats_.hits;
      return way.ready + hit_ticks_;
    }
    ++m.merged;
    ++stats_.mshr_merges;
    if (way.ready != kUnknown) return std::max(way.ready, earliest);
    m.waiters.push_back({listener, cookie, earliest});
    return kUnknown;
  }
  return miss(line, base, now, listener, cookie, arrival, requeued);
}

Tick Cache::miss(uint64_t line, uint32_t base, Tick now, FillListener* listener, uint64_t cookie,
                 Tick arrival, bool requeued) {
  // When can the miss go? It needs an MSHR and a way that are free (not in flight).
  uint32_t mshr = 0;
  Tick mshr_free = kUnknown;
  if (awaiting_ < cfg_.mshrs)  // else every MSHR waits for a fill of unknown time
    for (uint32_t m = 0; m < cfg_.mshrs; ++m)
      // Earliest, lowest index
      if (mshr_free_at_[m] < mshr_free) mshr_free = mshr_free_at_[m], mshr = m;
  Tick way_free = kUnknown;
  for (uint32_t i = base; i < base + cfg_.ways; ++i) way_free = std::min(way_free, ways_[i].ready);
  const Tick issue = std::max({now, mshr_free, way_free});

  if (issue == kUnknown) {  // nothing frees at a known time: wait for a fill
    if (!requeued) ++stats_.mshr_stall_events;
    queued_.push_back({line, listener, cookie, arrival});
    return kUnknown;
  }
  if (issue > now && !requeued) ++stats_.mshr_stall_events;
  if (issue > arrival) stats_.mshr_stall_cycles += ceil_cycles(issue - arrival);
  ++stats_.misses;

  // Victim: the LRU way among those not in flight at the issue time (never-used ways have stamp 0).
  uint32_t victim = kNoWay;
  for (uint32_t i = base; i < base + cfg_.ways; ++i)
    if (ways_[i].ready <= issue && (victim == kNoWay || ways_[i].lru < ways_[victim].lru))
      victim = i;
  Way& v = ways_[victim];
  if (v.tag != kInvalidTag) ++stats_.evictions;
  v.tag = line;
  v.lru = ++stamp_;

  const Tick earliest = issue + hit_ticks_;
  Tick delivered = below_->fetch_line(line, earliest, this, line);
  Mshr& m = mshrs_[mshr];
  m.line = line;
  m.merged = 1;
  v.mshr = mshr;
  if (delivered != kUnknown) {
    delivered = fill_slot(line, delivered);
    std::memcpy(&data_[size_t(victim) * cfg_.line_bytes], below_->line_data(line), cfg_.line_bytes);
    ++stats_.fills;
    v.ready = delivered;
    mshr_free_at_[mshr] = delivered;
    return delivered;
  }
  v.ready = kUnknown;
  mshr_free_at_[mshr] = kUnknown;
  ++awaiting_;
  m.waiters.clear();
  m.waiters.push_back({listener, cookie, earliest});
  return kUnknown;
}

void Cache::on_fill(uint64_t line, uint64_t /*cookie: the line address*/, Tick when) {
  const uint32_t way = find_way(line);
  if (way == kNoWay || ways_[way].ready != kUnknown)
    report_error(kReportInternal, std::string(name()) + ": fill for line " + std::to_string(line) +
                                      " that is not awaited");
  when = fill_slot(line, when);
  std::memcpy(&data_[size_t(way) * cfg_.line_bytes], below_->line_data(line), cfg_.line_bytes);
  ++stats_.fills;
  ways_[way].ready = when;
  ways_[way].lru = ++stamp_;  // the waiters use it now
  Mshr& m = mshrs_[ways_[way].mshr];
  mshr_free_at_[ways_[way].mshr] = when;
  --awaiting_;

  // Collect every completion first and call the listeners last, so they may call back in. Each
  // takes the line's bytes as they are when it is decided: a request served below may evict the
  // line before its listener reads it, and the data travel with the delivery.
  // Scratch of this depth (a listener's call back in may fill again): no allocation per fill.
  if (fill_depth_ == fill_scratch_.size()) fill_scratch_.push_back(std::make_unique<FillScratch>());
  FillScratch& scratch = *fill_scratch_[fill_depth_++];
  std::vector<Delivery>& out = scratch.out;
  std::vector<uint8_t>& bytes = scratch.bytes;
  out.clear();
  bytes.clear();
  const auto deliver = [&](FillListener* listener, uint64_t l, uint64_t cookie, Tick t) {
    out.push_back({listener, l, cookie, t});
    const uint8_t* data = line_data(l);
    bytes.insert(bytes.end(), data, data + cfg_.line_bytes);
  };
  out.reserve(m.waiters.size());
  for (const Waiter& w : m.waiters) deliver(w.listener, line, w.cookie, std::max(when, w.earliest));
  m.waiters.clear();

  // The freed MSHR serves the queued requests in arrival order, as accesses made at the fill time.
  // One that still cannot go (its set is all in flight on unknown fills) is queued again.
  if (!queued_.empty()) {
    std::vector<Queued>& waiting = scratch.waiting;
    waiting.clear();
    waiting.swap(queued_);
    for (const Queued& q : waiting) {
      // Without an MSHR that frees at a known time, only a request whose line is now in the cache
      // (a hit or a merge) can go; the others stay queued, in order, as access() would leave them.
      if (awaiting_ == cfg_.mshrs && find_way(q.line) == kNoWay) {
        queued_.push_back(q);
        continue;
      }
      const Tick t =
          access(q.line, std::max(when, q.arrival), q.listener, q.cookie, q.arrival, true);
      if (t != kUnknown) deliver(q.listener, q.line, q.cookie, t);
    }
  }

  const Handing outer = handing_;
  for (size_t i = 0; i < out.size(); ++i) {
    const Delivery& d = out[i];
    handing_ = {d.line, &bytes[i * cfg_.line_bytes]};
    if (d.listener) d.listener->on_fill(d.line, d.cookie, d.when);
  }
  handing_ = outer;
  --fill_depth_;
}

// An upstream cache of a smaller line asks for an address inside one of ours.
const uint8_t* Cache::line_data_elsewhere(uint64_t addr) const {
  const uint64_t line = addr & ~uint64_t(cfg_.line_bytes - 1);
  if (handing_.data && handing_.line == line) return handing_.data + (addr - line);
  const uint32_t way = find_way(line);
  if (way != kNoWay && ways_[way].ready != kUnknown)
    return &data_[size_t(way) * cfg_.line_bytes + (addr - line)];
  return below_->line_data(addr);
}

void Cache::register_stats(StatsRegistry& r, const std::string& prefix) const {
  StatsRegistrar v(r, prefix);
  describe_stats(v, stats_, cfg_.max_merge > 0, !banks_.empty());
  if (banks_.empty()) return;
  // By requester type: the types are the netlist's names, known only once it is built.
  for (size_t t = 0; t < type_names_.size(); ++t)
    r.counter(prefix + ".bank.stall_cycles_by." + type_names_[t], &stall_cycles_by_type_[t],
              "cycles", "cycles lookups from " + type_names_[t] + " waited for a bank slot");
}

}  // namespace rtsim::model
