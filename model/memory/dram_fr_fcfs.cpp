// FR-FCFS (GPGPU-Sim's, the default) and FCFS (dram_scheduler.h says what each picks): one file
// because they share the proposal loop and differ in two decisions.
#include "model/memory/dram_policies.h"

#include <algorithm>

namespace rtsim::model {

namespace {

// Both policies share the proposal loop; kFirstReady selects FR-FCFS's two differences (no PRE
// under a pending hit, column commands before row commands).
template <bool kFirstReady>
class QueueScheduler final : public DramScheduler {
 public:
  explicit QueueScheduler(const DramConfig&) {}

  // Two passes over the queue, with selects where propose() and better() branch (the scheduler
  // is the host's hottest loop on memory-bound frames, and those branches are coin flips): the
  // banks with a queued hit and the owner of the column commands, then every proposal against
  // the best, which is what propose() and better() would pick.
  DramChoice choose(const DramChannel& ch) override {
    const size_t n = ch.queue.size();
    uint64_t hit_banks = 0;  // banks with a queued row hit (DramConfig: at most 64 banks)
    size_t owner = n;        // the request between its first and last burst, if any
    for (size_t i = 0; i < n; ++i) {
      const DramRequest& r = ch.queue[i];
      const DramBank& b = ch.banks[r.bank];
      hit_banks |= uint64_t(b.open & (b.row == r.row)) << r.bank;
      owner = r.bursts_issued > 0 ? i : owner;
    }
    const bool owned = owner != n;
    const uint32_t owner_bank = owned ? ch.queue[owner].bank : 0;
    DramStamps channel;  // the channel's part of every command's earliest cycle
    for (size_t k = 0; k < kDramCommands; ++k) channel[k] = std::max(ch.earliest[k], ch.free_from);
    // The best so far as its sort key: (cycle, FR-FCFS: not a column command) in one word, then
    // the arrival; a later index never wins a tie (the queue is in enqueue order).
    uint64_t best_key = ~uint64_t(0);
    Tick best_arrival = 0;
    size_t best = n;
    for (size_t i = 0; i < n; ++i) {
      const DramRequest& r = ch.queue[i];
      const DramBank& b = ch.banks[r.bank];
      const bool hit = b.open & (b.row == r.row);
      const DramCommand cmd = next_command(b, r);
      // A column command waits for the owner; a PRE for the bank's hits (FR-FCFS) or its started
      // request (FCFS)
      const bool held_pre =
          kFirstReady ? (hit_banks >> r.bank) & 1 : owned & (r.bank == owner_bank);
      const bool held = hit ? owned & (owner != i) : b.open & held_pre;
      const size_t k = size_t(cmd);
      const uint64_t cycle = std::max({b.earliest[k], channel[k], r.arrival_cycle});
      const uint64_t key = held ? ~uint64_t(0) : cycle << 1 | uint64_t(kFirstReady & !hit);
      const bool better = key < best_key || (key == best_key && r.arrival < best_arrival);
      best_key = better ? key : best_key;
      best_arrival = better ? r.arrival : best_arrival;
      best = better ? i : best;
    }
    if (best == n) return DramChoice{};
    const DramRequest& r = ch.queue[best];
    return DramChoice{best, next_command(ch.banks[r.bank], r), best_key >> 1, r.bank};
  }

  // The new request's proposal weighed against the pick before it came: the other proposals are
  // unchanged, but for FR-FCFS's PREs in the new request's bank when it is that bank's first
  // queued hit: then, if the pick was such a PRE, everything is weighed again.
  DramChoice add(const DramChannel& ch, const DramChoice& before, size_t added) override {
    const DramRequest& r = ch.queue[added];
    const DramBank& b = ch.banks[r.bank];
    size_t owner = ch.queue.size();
    bool hit_pending = false;  // a request before it hits its bank's open row
    for (size_t i = 0; i < added; ++i) {
      const DramRequest& q = ch.queue[i];
      if (q.bursts_issued > 0) owner = i;
      if (kFirstReady && q.bank == r.bank && b.open && b.row == q.row) hit_pending = true;
    }
    const bool hit = b.open && b.row == r.row;
    if (kFirstReady && hit && !hit_pending && before.cycle != kDramNever &&
        before.command == DramCommand::kPrecharge && before.bank == r.bank)
      return choose(ch);
    DramChoice c;
    if (!propose(ch, added, owner, hit_pending, c)) return before;
    return better(ch, c, before) ? c : before;
  }

 private:
  // The command request `r` needs next: RD or WR on a row hit, PRE on another open row, else ACT.
  static DramCommand next_command(const DramBank& b, const DramRequest& r) {
    if (b.open & (b.row == r.row)) return r.write ? DramCommand::kWrite : DramCommand::kRead;
    return b.open ? DramCommand::kPrecharge : DramCommand::kActivate;
  }

  // Request i's proposal into `c`, unless the policy holds it back: its column command while
  // another request owns the column commands (`owner`, queue.size() for none), its PRE while its
  // bank has a queued hit (FR-FCFS: `hit_pending`) or a started request (FCFS).
  static bool propose(const DramChannel& ch, size_t i, size_t owner, bool hit_pending,
                      DramChoice& c) {
    const DramRequest& r = ch.queue[i];
    const DramBank& b = ch.banks[r.bank];
    const bool owned = owner != ch.queue.size();
    const DramCommand cmd = next_command(b, r);
    if (dram_is_column(cmd) && owned && owner != i) return false;  // the column commands are taken
    // FR-FCFS keeps the row open for its queued hits; both keep it for a started request.
    if (cmd == DramCommand::kPrecharge &&
        (kFirstReady ? hit_pending : owned && r.bank == ch.queue[owner].bank))
      return false;
    const size_t k = size_t(cmd);
    c = DramChoice{i, cmd, std::max({b.earliest[k], ch.earliest[k], r.arrival_cycle, ch.free_from}),
                   r.bank};
    return true;
  }

  // The order the policy picks by: the earlier cycle; at the same cycle (FR-FCFS) a column
  // command first; then the older request (arrival, then enqueue order).
  static bool better(const DramChannel& ch, const DramChoice& c, const DramChoice& best) {
    if (c.cycle != best.cycle) return c.cycle < best.cycle;
    const DramRequest &r = ch.queue[c.index], &o = ch.queue[best.index];
    const bool older = r.arrival != o.arrival ? r.arrival < o.arrival : r.seq < o.seq;
    const bool col = dram_is_column(c.command), best_col = dram_is_column(best.command);
    return kFirstReady && col != best_col ? col : older;
  }
};

}  // namespace

void add_fr_fcfs_schedulers(DramSchedulers& r) {
  r.add(
      "fr-fcfs", [](const DramConfig& c) { return std::make_unique<QueueScheduler<true>>(c); },
      "row hits first, then the oldest");
  r.add(
      "fcfs", [](const DramConfig& c) { return std::make_unique<QueueScheduler<false>>(c); },
      "the oldest ready command");
}

}  // namespace rtsim::model
