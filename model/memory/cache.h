// A non-blocking, set-associative, LRU, read-only cache that models timing and holds data.
//
// It is an sc_object driven by function calls (no SystemC process): towards the requester it
// is a LineSource, towards the level below a FillListener (for fills whose time was unknown when
// they were asked for, i.e. DRAM misses). Data are read-only, so a line's bytes are copied from
// the level below as soon as they are known to be exact (at request time when the delivery time
// is known, at on_fill otherwise).
//
// Timing (hit_latency H is in cycles of the cache's clock; all times are Ticks):
//  - hit: the line is present and was delivered by `now` -> now + H.
//  - merge: the line is allocated and still in flight (delivery T > now). No new request goes
//    below. The delivery is max(T, now + H): the data passes through as it arrives, but a merge
//    is never faster than a hit would be. If T is not known yet the requester is queued on the
//    line's MSHR, fetch_line returns kUnknown and it gets on_fill(line, cookie, max(T, now + H))
//    when the fill arrives.
//  - miss: the tag check takes H, so the level below is asked at now + H and its delivery time
//    is this cache's delivery time (no extra cost on the way back). Hence an L1 miss that hits in
//    an L2 is delivered at now + H_L1 + H_L2, and one that goes to memory at
//    now + H_L1 + H_L2 + (memory's answer to a request made at now + H_L1 + H_L2).
//    The line is allocated at request time in the LRU way among those not in flight; the MSHR
//    stays busy until the delivery.
//  - merge limit: an MSHR serves at most `max_merge` requests (the miss and its merges, GPGPU-Sim's
//    MSHR "max merged"); one more for its line waits for the fill and is served then, as a hit
//    (fill + H), counted as an MSHR stall. 0: no limit.
//  - MSHR / structural stall: a miss needs a free MSHR (at most `mshrs` lines in flight) and a
//    way of its set that is not in flight. If either is missing but the earliest one frees at a
//    known time, the miss is issued at that time instead of `now` (the level below may thus be
//    asked about a future time). If none frees at a known time, the request is queued and served
//    (in arrival order, as an access made at the fill time) when an on_fill frees an MSHR; it
//    then completes through listener->on_fill.
//
// Banks and ports: the array is split into `banks` banks by the lowest bits of the line number
// (bank = line_addr / line_bytes mod banks, so consecutive lines go to consecutive banks), each
// serving `ports` accesses per cycle (model/memory/port_schedule.h: first come, first served in the
// calendar's fixed order). A lookup takes a slot of its line's bank first and is made at that
// slot's cycle; the wait is counted per requester type. A fill (a line arriving from below) is a
// write into the array: with `fill_port` kShared it takes a slot of the same bank, competing with
// lookups as in a single-ported SRAM bank, and the line is delivered at that slot; with kSeparate
// (GPGPU-Sim's caches) fills have a port of their own and cost no lookup slot. A request that
// waits for an MSHR is served from the MSHR queue when one frees, without a second bank slot.
// `ports == 0` is the ideal cache: no bank limit at all.
//
// Statistics: accesses = hits + misses + mshr_merges (+ requests still queued; a queued
// request is classified when it is finally served). mshr_stall_events counts requests that
// waited for an MSHR or a way; mshr_stall_cycles their total wait, each rounded up to whole
// cycles. fills counts lines written into the data array, evictions valid lines replaced.
//
// Listener contract: on_fill may be called with a `when` later than the call's own time (a queued
// request served at a fill may complete after it); `when` is the delivery time. Listener calls
// are made only after the cache's state is consistent, so a listener may call back into it.
#pragma once

#include "model/memory/line_source.h"
#include "model/memory/port_schedule.h"
#include "model/sim/config_description.h"
#include "model/sim/stats_description.h"
#include "model/sim/stats_registry.h"
#include "model/sim/time.h"

#include <systemc>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace rtsim::model {

enum class FillPort { kShared, kSeparate };

struct CacheConfig {
  uint32_t size_bytes = 8192;
  uint32_t ways = 2;
  uint32_t line_bytes = 64;  // power of two, >= 4
  uint32_t hit_latency = 1;  // cycles of the cache's clock (0 allowed: an ideal cache)
  uint32_t mshrs = 16;       // outstanding misses (distinct lines)
  uint32_t banks = 1;        // power of two, at most the number of sets
  uint32_t ports = 0;        // accesses per bank per cycle; 0: unlimited (ideal)
  FillPort fill_port = FillPort::kShared;
  uint32_t max_merge = 0;  // requests one MSHR serves, the first included; 0: unbounded

  // Throws std::invalid_argument naming the offending field.
  void validate() const;
  uint32_t sets() const { return size_bytes / (ways * line_bytes); }
};

// Every CacheConfig field, once (model/sim/config_description.h).
template <class V, class C>
DescribeOf<C, CacheConfig> describe(V& v, C& c) {
  v.kib("size_kb", c.size_bytes, 1, 1 << 20, "capacity");
  v.number("ways", c.ways, 1, 1024, "", "associativity (LRU replacement)");
  v.number("line_bytes", c.line_bytes, 4, 4096, "bytes", "line size, a power of two");
  v.number("hit_latency", c.hit_latency, 0, 10000, "cycles",
           "a hit's latency; a miss adds the level below's");
  v.number("mshrs", c.mshrs, 1, 65536, "lines", "misses in flight (distinct lines)");
  v.number("banks", c.banks, 1, 1024, "banks",
           "by line number mod banks; a power of two, at most the sets");
  v.number("ports", c.ports, 0, 64, "per bank and cycle",
           "lookups a bank serves per cycle; 0: unlimited (ideal)");
  v.choice("fill_port", c.fill_port,
           {{"shared", FillPort::kShared}, {"separate", FillPort::kSeparate}},
           "a fill takes one of its bank's slots (shared) or has a port of its own (separate)");
  v.number("max_merge", c.max_merge, 0, 65536, "requests",
           "requests an MSHR serves (the miss and its merges); more wait for the fill and hit; "
           "0: unbounded (ideal)");
}

struct CacheStats {
  uint64_t accesses = 0;
  uint64_t hits = 0;
  uint64_t misses = 0;
  uint64_t mshr_merges = 0;
  uint64_t mshr_stall_events = 0;
  uint64_t mshr_stall_cycles = 0;
  uint64_t fills = 0;
  uint64_t evictions = 0;
  uint64_t bank_stall_events = 0;
  uint64_t bank_stall_cycles = 0;
  uint64_t fill_stall_cycles = 0;
  uint64_t merge_full_events = 0;
};

// Every CacheStats field, once (model/sim/stats_description.h); `merge_limited` (max_merge > 0)
// and `banked` (ports > 0) say which limits the cache models, whose counters it then has.
template <class V>
void describe_stats(V& v, const CacheStats& s, bool merge_limited, bool banked) {
  v.counter("accesses", s.accesses, "count", "line requests received");
  v.counter("hits", s.hits, "count", "requests finding their line present and delivered");
  v.counter("misses", s.misses, "count",
            "requests that allocated a line and asked the level below");
  v.counter("mshr_merges", s.mshr_merges, "count", "requests merged into a line already in flight");
  v.counter("mshr_stall_events", s.mshr_stall_events, "count",
            "misses that waited for a free MSHR or a way not in flight, or requests for a line "
            "whose MSHR was full");
  v.counter("mshr_stall_cycles", s.mshr_stall_cycles, "cycles",
            "cycles misses waited for an MSHR or a way");
  v.counter("fills", s.fills, "count", "lines written into the data array");
  v.counter("evictions", s.evictions, "count", "valid lines replaced");
  if (merge_limited)
    v.counter("merge_full_events", s.merge_full_events, "count",
              "requests that found their line's MSHR full (max_merge): served by the fill");
  v.formula(
      "hit_rate", [&s] { return s.accesses ? double(s.hits) / double(s.accesses) : 0.0; }, "ratio",
      "hits / accesses");
  if (!banked) return;
  v.counter("bank.stall_events", s.bank_stall_events, "count",
            "lookups that waited for a slot of their bank");
  v.counter("bank.stall_cycles", s.bank_stall_cycles, "cycles",
            "cycles lookups waited for a bank slot");
  v.counter("bank.fill_stall_cycles", s.fill_stall_cycles, "cycles",
            "cycles fills waited for a bank slot");
}

class Cache : public sc_core::sc_object, public LineSource, public FillListener {
 public:
  // `below` must outlive the cache; the cache registers itself as below's listener. It may be
  // null when the level below is bound later (connect, before the first access). A bad
  // configuration is reported as rtsim/config.
  Cache(const char* name, const CacheConfig& cfg, const Clock& clock, LineSource* below);
  const char* kind() const override { return "rtsim_cache"; }
  Cache(const Cache&) = delete;  // the level below holds `this`
  Cache& operator=(const Cache&) = delete;

  // `line_addr` must be line-aligned (rtsim/internal otherwise). `listener` may be null when
  // the caller does not need a kUnknown completion.
  // A hit is served inline (most requests); everything else by access().
  Tick fetch_line(uint64_t line_addr, Tick now, FillListener* listener, uint64_t cookie) final {
    if (__builtin_expect(line_addr & (cfg_.line_bytes - 1), 0)) misaligned(line_addr);
    ++stats_.accesses;
    if (!banks_.empty()) now = lookup_slot(line_addr, now, listener);
    const uint32_t base = set_base(line_addr);
    for (uint32_t i = base; i < base + cfg_.ways; ++i) {
      Way& way = ways_[i];
      if (way.tag != line_addr) continue;
      if (way.ready > now) break;  // in flight: a merge
      way.lru = ++stamp_;
      ++stats_.hits;
      last_way_ = i;
      return now + hit_ticks_;
    }
    return access(line_addr, now, listener, cookie, now, false);
  }
  // The bytes of the line being handed to a listener in on_fill (as they were when its delivery
  // was decided), else the cache's own copy when it holds the line's bytes, else the level
  // below's.
  const uint8_t* line_data(uint64_t addr) const final {
    const uint64_t line = addr & ~uint64_t(cfg_.line_bytes - 1);
    const uint32_t w = last_way_;  // a line is in one way at most: the latest hit's, usually
    if ((!handing_.data || handing_.line != line) && ways_[w].tag == line &&
        ways_[w].ready != kUnknown)
      return &data_[size_t(w) * cfg_.line_bytes + (addr - line)];
    return line_data_elsewhere(addr);
  }
  uint32_t line_bytes() const final { return cfg_.line_bytes; }
  // The level below, when it was not known at construction (a unit's port, bound later).
  void connect(LineSource& below) { below_ = &below; }
  // A fill from below for a line this cache asked for with an unknown time.
  void on_fill(uint64_t line_addr, uint64_t cookie, Tick when) override;

  // The bank serving `line_addr` (a crossbar's destination port).
  uint32_t port_of(uint64_t line_addr) const override {
    return uint32_t((line_addr >> line_shift_) & (cfg_.banks - 1));
  }
  uint32_t port_count() const override { return cfg_.banks; }
  // Bank waits are also counted per requester type; unnamed requesters count as "other".
  void name_requester(const FillListener* requester, const std::string& type);

  // Registers its statistics (describe_stats) under <prefix>, and with banks modelled the bank
  // waits by requester type, .bank.stall_cycles_by.<type>.
  void register_stats(StatsRegistry& r, const std::string& prefix) const;

  const CacheStats& stats() const { return stats_; }
  const CacheConfig& config() const { return cfg_; }
  // Drops every line (a device reset or a new frame: the platform may have changed memory). Only
  // while nothing is in flight (rtsim/internal otherwise).
  void invalidate();
  // Functional warming (a sampled frame's, docs/sampling.md): makes `line_addr` its set's most
  // recently used line, putting it with `bytes` (the line's, from memory) in the LRU way when it
  // is absent, as a fill would, but at no time and counting nothing. Only while no miss is in
  // flight (otherwise nothing changes). Returns whether the line was there.
  bool warm(uint64_t line_addr, const uint8_t* bytes);
  // Probes without side effects (tests, debugging).
  bool contains(uint64_t line_addr) const { return find_way(line_addr) != kNoWay; }
  size_t queued_requests() const { return queued_.size(); }

 private:
  static constexpr uint64_t kInvalidTag = ~uint64_t(0);  // never line-aligned, never matches
  static constexpr uint32_t kNoWay = ~uint32_t(0);

  struct Waiter {
    FillListener* listener;
    uint64_t cookie;
    Tick earliest;  // the requester's arrival + hit latency
  };
  struct Mshr {
    uint64_t line = kInvalidTag;  // the line it was last allocated to
    uint32_t merged = 0;          // requests for that line, the first included
    std::vector<Waiter> waiters;  // keeps its capacity: no allocation once warmed up
  };
  struct Queued {  // a miss that found no MSHR / way with a known free time
    uint64_t line;
    FillListener* listener;
    uint64_t cookie;
    Tick arrival;
  };
  struct Delivery {
    FillListener* listener;
    uint64_t line;
    uint64_t cookie;
    Tick when;
  };

  struct FillScratch {  // on_fill's lists, kept between fills
    std::vector<Delivery> out;
    std::vector<uint8_t> bytes;
    std::vector<Queued> waiting;
  };

  struct Way {
    uint64_t tag = kInvalidTag;
    Tick ready = 0;     // delivery time of the line's data; kUnknown while awaiting a fill
    uint64_t lru = 0;   // last-use stamp; the smallest is the LRU
    uint32_t mshr = 0;  // the MSHR serving the way while ready is kUnknown
  };

  struct Handing {  // the line an on_fill listener is being told of, and its bytes
    uint64_t line = 0;
    const uint8_t* data = nullptr;
  };

  uint32_t set_base(uint64_t line) const {  // the global index of the line's set's first way
    return uint32_t((line >> line_shift_) & set_mask_) * cfg_.ways;
  }
  uint32_t find_way(uint64_t line_addr) const;              // global way index or kNoWay
  const uint8_t* line_data_elsewhere(uint64_t addr) const;  // line_data() but the latest hit
  [[noreturn]] void misaligned(uint64_t line_addr) const;
  // The access proper, at time `now`. `arrival` is when the request first arrived (< now for a
  // queued request served at a fill); `requeued` says its stall event was already counted.
  Tick access(uint64_t line, Tick now, FillListener* listener, uint64_t cookie, Tick arrival,
              bool requeued);
  Tick miss(uint64_t line, uint32_t base, Tick now, FillListener* listener, uint64_t cookie,
            Tick arrival, bool requeued);
  uint64_t ceil_cycles(Tick t) const { return clock_.ceil_cycles(t); }
  // The cycle a lookup by `requester` made at `now` gets a slot of the line's bank.
  Tick lookup_slot(uint64_t line, Tick now, const FillListener* requester) {
    const Tick slot = banks_[port_of(line)].reserve(now);
    if (slot > now) count_bank_stall(ceil_cycles(slot - now), requester);
    return slot;
  }
  void count_bank_stall(uint64_t wait, const FillListener* requester);
  // The time a fill of `line` arriving at `when` is written into the array.
  Tick fill_slot(uint64_t line, Tick when);

  // What a hit touches first, together: the host's cache misses on these, not on the arithmetic.
  CacheConfig cfg_;
  Tick hit_ticks_;
  uint32_t line_shift_;
  uint64_t set_mask_;
  uint64_t stamp_ = 0;
  uint32_t last_way_ = 0;  // the way of the latest hit: line_data()'s first guess
  std::vector<Way> ways_;  // indexed set * ways + way: a set's ways are adjacent
  std::vector<uint8_t> data_;
  std::vector<PortSchedule> banks_;  // empty: ideal
  Handing handing_;
  CacheStats stats_;

  Clock clock_;
  LineSource* below_;
  std::vector<std::unique_ptr<FillScratch>> fill_scratch_;  // by depth of on_fill calls
  uint32_t fill_depth_ = 0;

  std::vector<Mshr> mshrs_;
  // By MSHR: busy while > t; kUnknown until its fill arrives. Apart from the MSHRs: a miss scans
  // them all.
  std::vector<Tick> mshr_free_at_;
  uint32_t awaiting_ = 0;  // MSHRs waiting for a fill of unknown time
  std::vector<Queued> queued_;
  std::vector<std::pair<const FillListener*, uint32_t>> requester_type_;
  std::vector<std::string> type_names_{"other"};
  std::vector<uint64_t> stall_cycles_by_type_{0};
  struct {  // count_bank_stall's last requester and its type
    bool known = false;
    const FillListener* requester = nullptr;
    uint32_t type = 0;
  } stall_type_;
};

}  // namespace rtsim::model
