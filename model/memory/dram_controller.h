// The DRAM timing engine: per-channel controllers serving reads and writes, their policies
// chosen by the configuration (scheduler, row policy, refresh: dram_scheduler.h,
// dram_row_policy.h, dram_refresh.h; the defaults are GT200's FR-FCFS, open page, no refresh). Pure
// C++ (no SystemC); the sc_module in dram.h drives it.
//
// Timing (Ramulator-2.0 style): the constraints are a table of rules "after command P, command N
// may not issue for K cycles in the same bank / bank group / channel". Issuing P stamps, for each
// rule, the earliest cycle of N in that bank (a bank-group rule stamps every bank of the group) or
// channel; a command is legal at cycle c when c is at or past its bank's and its channel's stamps.
// The rules (DRAM command-clock cycles; GPGPU-Sim names and derivations in dram_config.h;
// docs/dram.md has the table with sources):
//   ACT->RD  tRCD  bank      ACT->WR  tRCD - (WL + 1) bank (activate_to_write, GPGPU-Sim tRCDWR)
//   ACT->PRE tRAS  bank      ACT->ACT tRC bank           ACT->ACT tRRD channel
//   PRE->ACT tRP   bank
//   RD->RD   tCCD  channel   RD->RD   BL/2 channel (data-bus occupancy)
//   WR->WR   tCCD  channel   WR->WR   BL/2 channel (data-bus occupancy)
//   RD->WR   tCCD  channel   RD->WR   CL + BL/2 + 2 - WL channel (read_to_write, tRTW)
//   WR->RD   tCCD  channel   WR->RD   WL + BL/2 + tCDLR channel (write_to_read, tWTR)
//   RD->PRE  max(BL/2, tRTP) bank (GDDR3 READ to PRECHARGE: GPGPU-Sim's RTP = BL / ratio)
//   WR->PRE  WL + BL/2 + tWR bank (write_to_precharge, GPGPU-Sim tWTP)
// With bank groups (bank_groups > 1) also: column -> column tCCD_L and ACT->ACT tRRD_L in the
// same bank group. With refresh: ACT->REF tRC, PRE->REF tRP and REF->ACT tRFC, all channel (REF
// is all-bank). BL/2 stands for burst_cycles() = burst_length / beats_per_clock.
// tCCD applies between any two column commands (GPGPU-Sim's one CCDc counter for RD and WR,
// dram.cc dram_t::issue_col_command). A read's data occupy the bus from RD + CL for BL/2 cycles,
// a write's from WR + WL for BL/2 cycles; the turnarounds keep the two apart (at their minimum,
// tRTW leaves 2 idle bus cycles between a read's data and a write's, tWTR leaves tCDLR + CL
// between a write's data and a read's). A read is complete when its last burst is: data ready =
// last RD + CL + BL/2; a write when its last burst's data are in: last WR + WL + BL/2 (tWR after
// that only delays the bank's PRE). Not modelled: power-down, tFAW, per-bank refresh, a separate
// write queue drained in batches (GPGPU-Sim's -dram_seperate_write_queue_enable: off by default,
// not set for GT200), data masks (every write is a full request).
//
// Scheduling, per channel, one command per command-clock cycle:
//  - A request of request_bytes needs request_bytes / burst_bytes bursts: consecutive column
//    commands to one row (as GPGPU-Sim serves a request's bursts back to back). While a request
//    is between its first and its last burst it owns the channel's column commands; ACT/PRE for
//    other banks may still use the free command cycles in between.
//  - Reads and writes share one queue (as GPGPU-Sim's FR-FCFS queue). The scheduler policy picks
//    the next command (dram_scheduler.h), the refresh policy may put a refresh's PRE or REF first
//    (dram_refresh.h), and after a request's last burst the row policy may precharge its bank
//    (dram_row_policy.h; auto-precharge: it takes no command cycle).
//  - The scheduler sees queue_size requests per channel (GPGPU-Sim's dram_sched_queue_size).
//    Requests beyond that wait in a per-channel FIFO of input_queue requests (GPGPU-Sim's L2-to-
//    DRAM queue; 0: unbounded), counted in queue_full_events; one enters the queue each time a
//    request leaves it (after its last column command). A request for a channel whose FIFO is
//    full must wait (accepts() says so): the caller holds it back and offers it again later.
//  - Row classification is made when a request's first command issues: RD/WR = row hit, ACT = row
//    miss (bank closed), PRE = row conflict. The row_* statistics count reads and writes.
//
// Time: requests arrive in picoseconds (enqueue's `now`); a request can use command cycles from
// the first command-clock edge at or after its arrival. A request enqueued with a time earlier
// than the engine's latest advance() is taken as arriving then (time never runs backwards), and
// never uses a cycle at or before a command this channel already issued.
#pragma once

#include "model/memory/dram_channel.h"
#include "model/memory/dram_config.h"
#include "model/memory/dram_refresh.h"
#include "model/memory/dram_row_policy.h"
#include "model/memory/dram_scheduler.h"
#include "model/memory/line_source.h"
#include "model/sim/stats_description.h"

#include <algorithm>
#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <queue>
#include <string>
#include <vector>

namespace rtsim::model {

struct DramStats {
  uint64_t requests = 0;            // read requests accepted by enqueue
  uint64_t reads = 0;               // read requests completed (reported by advance)
  uint64_t bursts = 0;              // RD commands
  uint64_t activates = 0;           // ACT commands
  uint64_t precharges = 0;          // PRE commands
  uint64_t row_hits = 0;            // first command was RD or WR (reads and writes)
  uint64_t row_misses = 0;          // first command was ACT (bank closed)
  uint64_t row_conflicts = 0;       // first command was PRE (another row open)
  uint64_t bytes = 0;               // completed reads * request_bytes
  uint64_t data_bus_busy_ps = 0;    // summed over channels: (bursts + write_bursts) * BL/2 * tCK
  uint64_t queue_full_events = 0;   // requests that found their channel's queue full
  uint64_t latency_sum_ps = 0;      // over completed reads: data ready - arrival
  uint64_t first_arrival_ps = 0;    // of the first request, read or write (0 until one arrives)
  uint64_t last_completion_ps = 0;  // data ready of the latest completed read
  std::vector<uint64_t> channel_reads;    // completed reads per channel
  uint64_t write_requests = 0;            // write requests accepted by enqueue
  uint64_t writes = 0;                    // write requests completed (reported by advance)
  uint64_t write_bursts = 0;              // WR commands
  uint64_t bytes_written = 0;             // completed writes * request_bytes
  uint64_t last_write_completion_ps = 0;  // data in of the latest completed write
  uint64_t refreshes = 0;                 // REF commands (refresh: all-bank)
  // Summed over channels: cycles with a row open in some bank (active standby); the rest of a
  // channel's cycles it has every bank closed (precharge standby). The energy's background.
  uint64_t active_cycles = 0;

  double row_hit_rate() const;
  double bandwidth_gbps() const;  // read bandwidth: bytes / (last completion - first arrival)
  double avg_latency_ns() const;
};

// Every DramStats figure, once (model/sim/stats_description.h); `channels` for the bus's share,
// `refresh`: the memory refreshes (its REF count is a figure only then).
template <class V>
void describe_stats(V& v, const DramStats& s, uint32_t channels, bool refresh) {
  v.counter("requests", s.requests, "count", "read requests accepted");
  v.counter("reads", s.reads, "count", "read requests completed");
  v.counter("bursts", s.bursts, "count", "RD commands (one burst each)");
  v.counter("activates", s.activates, "count", "ACT commands");
  v.counter("precharges", s.precharges, "count", "PRE commands");
  v.counter("row_hits", s.row_hits, "count", "requests (reads and writes) whose row was open");
  v.counter("row_misses", s.row_misses, "count",
            "requests (reads and writes) that found their bank closed");
  v.counter("row_conflicts", s.row_conflicts, "count",
            "requests (reads and writes) that found another row open");
  v.counter("bytes", s.bytes, "bytes", "bytes read (completed requests)");
  v.counter("data_bus_busy_ps", s.data_bus_busy_ps, "ps",
            "data-bus busy time (reads and writes) summed over channels (ps)");
  v.counter("queue_full_events", s.queue_full_events, "count",
            "requests that waited in the overflow FIFO");
  v.counter("latency_sum_ps", s.latency_sum_ps, "ps", "sum of read arrival-to-data latencies (ps)");
  v.counter("write_requests", s.write_requests, "count", "write requests accepted");
  v.counter("writes", s.writes, "count", "write requests completed");
  v.counter("write_bursts", s.write_bursts, "count", "WR commands (one burst each)");
  v.counter("bytes_written", s.bytes_written, "bytes", "bytes written (completed requests)");
  v.counter("active_cycles", s.active_cycles, "cycles",
            "DRAM cycles with a row open, summed over channels (the rest: every bank closed)");
  if (refresh)
    v.counter("refreshes", s.refreshes, "count",
              "REF commands (refresh: all-bank; up to each channel's last request)");
  for (size_t i = 0; i < s.channel_reads.size(); ++i)
    v.counter("ch" + std::to_string(i) + ".reads", s.channel_reads[i], "count",
              "read requests completed by channel");
  v.formula(
      "row_hit_rate", [&s] { return s.row_hit_rate(); }, "ratio",
      "row_hits / (hits + misses + conflicts)");
  v.formula(
      "bandwidth_gbps", [&s] { return s.bandwidth_gbps(); }, "GB/s",
      "bytes / (last completion - first arrival), GB/s");
  v.formula(
      "avg_latency_ns", [&s] { return s.avg_latency_ns(); }, "ns", "latency_sum / reads (ns)");
  v.formula(
      "bus_utilization",
      [&s, channels] {
        const uint64_t last = std::max(s.last_completion_ps, s.last_write_completion_ps);
        const uint64_t span = last > s.first_arrival_ps ? last - s.first_arrival_ps : 0;
        return span ? double(s.data_bus_busy_ps) / (double(channels) * double(span)) : 0.0;
      },
      "ratio", "data_bus_busy / (channels * (last read or write completion - first arrival))");
}

class DramController {
 public:
  using Command = DramCommand;
  static constexpr size_t kCommands = kDramCommands;
  static constexpr bool is_column(Command c) { return dram_is_column(c); }

  struct Completion {
    uint64_t id;
    Tick data_ready;  // ps, on a DRAM command-clock edge; for a write, its last data beat is in
    bool write = false;
  };

  // One issued command, for tests and debugging (see set_command_trace).
  struct CommandRecord {
    Tick time;
    uint32_t channel;
    uint32_t bank;
    Command command;
    uint64_t row;
    uint64_t column;  // RD and WR only
    uint64_t id;      // the request it was issued for (kNoRequest: a refresh's PRE or REF)
  };
  static constexpr uint64_t kNoRequest = ~uint64_t(0);

  // Validates `config` (std::invalid_argument).
  explicit DramController(const DramConfig& config);

  // A read (or, with `write`, a write) of the request_bytes-aligned block holding `addr`, arriving
  // at `now`; `id` comes back in its Completion. Only when accepts(addr).
  void enqueue(uint64_t addr, Tick now, uint64_t id, bool write = false);
  // Whether the channel of `addr` has room for a request (its FIFO is not full).
  bool accepts(uint64_t addr) const { return has_room(channels_[mapping_.channel(addr)]); }
  // When the engine next has something to do (a command to issue or a completion to report);
  // kUnknown when idle.
  Tick next_event_time() const;
  // Issues every command legal up to `now` and appends the completions with data ready <= now,
  // in (time, enqueue order).
  void advance(Tick now, std::vector<Completion>& done);
  // Counts the cycles up to `now` that channels with a row open have spent so: a span's
  // active_cycles are complete once this ran at its end (and at its start, before a reset).
  void settle_active(Tick now);
  bool idle() const { return next_event_time() == kUnknown; }
  // Requests waiting per channel, and the next command's cycle (for the watchdog's report).
  std::string state() const;

  const DramConfig& config() const { return config_; }
  const AddressMapping& mapping() const { return mapping_; }
  const DramStats& stats() const { return stats_; }
  // Registers the statistics under `prefix` ("dram" -> "dram.reads", "dram.ch0.reads", ...). The
  // registry keeps pointers: the controller must not move afterwards.
  void register_stats(StatsRegistry& registry, const std::string& prefix) const;
  // Appends every issued command to *trace (nullptr: off).
  void set_command_trace(std::vector<CommandRecord>* trace) { trace_ = trace; }

 private:
  enum class Scope : uint8_t { kBank, kBankGroup, kChannel };
  struct TimingRule {
    Command prev, next;
    Scope scope;
    uint32_t cycles;
  };
  using Channel = DramChannel;
  using Choice = DramChoice;
  struct Pending {
    Tick time;
    uint64_t seq;
    uint64_t id;
    uint32_t channel;
    Tick arrival;
    bool write;
    bool operator>(const Pending& o) const { return time != o.time ? time > o.time : seq > o.seq; }
  };

  bool has_room(const Channel& ch) const {
    return config_.input_queue == 0 || ch.queue.size() < config_.queue_size ||
           ch.overflow.size() < config_.input_queue;
  }
  void add_rules();
  // Chooses channel i's next command after it changed (a request queued, a command issued), and
  // keeps the choice: until the channel changes again it stands, so advance() issues it without
  // choosing again.
  void rechoose(uint32_t i) {
    picks_[i] = scheduler_->choose(channels_[i]);
    settle(i);
  }
  // The same after request `added` joined channel i's queue, nothing else having changed: the
  // scheduler weighs the new request against its pick (DramScheduler::add).
  void rechoose_added(uint32_t i, size_t added) {
    picks_[i] = scheduler_->add(channels_[i], picks_[i], added);
    settle(i);
  }
  // The refresh policy's say on the scheduler's pick: the command at the earliest cycle with a
  // legal one. Without refresh it would return the pick unchanged: the call is skipped (host time).
  void settle(uint32_t i) {
    next_[i] = refreshing_ ? refresh_->arbitrate(channels_[i], picks_[i]) : picks_[i];
    channels_[i].next_cycle = next_[i].cycle;
  }
  void catch_up_refresh(uint32_t channel_index, uint64_t until);
  void issue(uint32_t channel_index, const Choice& c);
  void issue_refresh(uint32_t channel_index, const Choice& c);
  void complete(uint32_t channel_index, const Choice& c);
  // Applies the rules of `cmd` issued at `cycle` in `bank`.
  void stamp(Channel& ch, uint32_t bank, Command cmd, uint64_t cycle);
  void record(uint64_t cycle, uint32_t channel, uint32_t bank, Command cmd, uint64_t row,
              uint64_t column, uint64_t id) {
    if (trace_)
      trace_->push_back(CommandRecord{cycle * config_.tCK_ps, channel, bank, cmd, row, column, id});
  }

  DramConfig config_;
  AddressMapping mapping_;
  std::array<std::vector<TimingRule>, kCommands> rules_by_prev_;        // bank and channel scope
  std::array<std::vector<TimingRule>, kCommands> group_rules_by_prev_;  // bank-group scope
  std::unique_ptr<DramScheduler> scheduler_;
  std::unique_ptr<DramRowPolicy> row_policy_;
  std::unique_ptr<DramRefreshPolicy> refresh_;
  bool refreshing_;
  std::vector<Channel> channels_;
  // Per channel, of its state as it is (rechoose): the scheduler's pick, and the command to issue.
  std::vector<Choice> picks_, next_;
  // Per channel: banks with a row open, and the cycle since which some has been (active_cycles).
  // A closed-page row's auto-precharge is booked at a later cycle than commands issued after it,
  // so closes come out of time order: a stretch with a row open ends at the latest close booked
  // in it (stretch_end_), and a stretch that opens before the last one's end starts at that end
  // (counted_until_), so no cycle is counted twice.
  std::vector<uint32_t> open_banks_;
  std::vector<uint64_t> open_since_, stretch_end_, counted_until_;
  void bank_opened(uint32_t channel, uint64_t cycle);
  void bank_closed(uint32_t channel, uint64_t cycle);
  std::priority_queue<Pending, std::vector<Pending>, std::greater<Pending>> completions_;
  Tick now_ = 0;  // latest advance()
  uint64_t next_seq_ = 0;
  DramStats stats_;
  std::vector<CommandRecord>* trace_ = nullptr;
};

}  // namespace rtsim::model
