// FR-FCFS (GPGPU-Sim's, the default) and FCFS (dram_scheduler.h says what each picks): one file
// because they share the proposal loop and differ in two decisions.
#include "model/memory/dram_policies.h"

#include <algorithm>

namespace rtsim::model {

namespace {

// Both policies share the proposals and their order; kFirstReady selects FR-FCFS's two
// differences (no PRE under a pending hit, column commands before row commands).
template <bool kFirstReady>
class QueueScheduler final : public DramScheduler {
 public:
  explicit QueueScheduler(const DramConfig&) {}

  // Two passes over the queue: the banks with a queued hit and the owner of the column commands,
  // then every proposal's key against the best's, with selects rather than branches (the
  // scheduler is the host's hottest loop on memory-bound frames, and such branches are coin
  // flips).
  DramChoice choose(const DramChannel& ch) override {
    const size_t n = ch.queue.size();
    const Holders holders = holders_among(ch, n);
    const DramStamps channel = channel_stamps(ch);
    // A later index never wins a tie of key and arrival (the queue is in enqueue order).
    uint64_t best_key = kHeld;
    Tick best_arrival = 0;
    size_t best = n;
    for (size_t i = 0; i < n; ++i) {
      const uint64_t key = proposal_key(ch, channel, i, holders);
      const Tick arrival = ch.queue[i].arrival;
      const bool better = key < best_key || (key == best_key && arrival < best_arrival);
      best_key = better ? key : best_key;
      best_arrival = better ? arrival : best_arrival;
      best = better ? i : best;
    }
    return best == n ? DramChoice{} : choice(ch, best, best_key);
  }

  // The new request's proposal weighed against the pick before it came: the other proposals are
  // unchanged, but for FR-FCFS's PREs in the new request's bank when it is that bank's first
  // queued hit: then, if the pick was such a PRE, everything is weighed again.
  DramChoice add(const DramChannel& ch, const DramChoice& before, size_t added) override {
    const DramRequest& r = ch.queue[added];
    const DramBank& b = ch.banks[r.bank];
    const Holders holders = holders_among(ch, added);  // the requests before it
    const bool hit_pending = (holders.hit_banks >> r.bank) & 1;
    const bool hit = b.open && b.row == r.row;
    if (kFirstReady && hit && !hit_pending && before.cycle != kDramNever &&
        before.command == DramCommand::kPrecharge && before.bank == r.bank)
      return choose(ch);
    const uint64_t key = proposal_key(ch, channel_stamps(ch), added, holders);
    // The pick before wins a tie of key and arrival: it is older in the queue.
    const bool better =
        before.cycle == kDramNever
            ? key != kHeld
            : key < pick_key(before) ||
                  (key == pick_key(before) && r.arrival < ch.queue[before.index].arrival);
    return better ? choice(ch, added, key) : before;
  }

 private:
  // What holds proposals back (proposal_key): the banks with a queued hit, the request between
  // its bursts (queue.size() for none) and its bank.
  struct Holders {
    uint64_t hit_banks;
    size_t owner;
    uint32_t owner_bank;
  };
  static constexpr uint64_t kHeld = ~uint64_t(0);  // the key of a proposal held back

  // The holders among the queue's first `count` requests.
  static Holders holders_among(const DramChannel& ch, size_t count) {
    uint64_t hit_banks = 0;          // DramConfig: at most 64 banks
    size_t owner = ch.queue.size();  // none
    for (size_t i = 0; i < count; ++i) {
      const DramRequest& r = ch.queue[i];
      const DramBank& b = ch.banks[r.bank];
      hit_banks |= uint64_t(b.open & (b.row == r.row)) << r.bank;
      owner = r.bursts_issued > 0 ? i : owner;
    }
    return Holders{hit_banks, owner, owner != ch.queue.size() ? ch.queue[owner].bank : 0};
  }

  // The command request `r` needs next: RD or WR on a row hit, PRE on another open row, else ACT.
  static DramCommand next_command(const DramBank& b, const DramRequest& r) {
    if (b.open & (b.row == r.row)) return r.write ? DramCommand::kWrite : DramCommand::kRead;
    return b.open ? DramCommand::kPrecharge : DramCommand::kActivate;
  }

  // The channel's part of every command's earliest cycle.
  static DramStamps channel_stamps(const DramChannel& ch) {
    DramStamps channel;
    for (size_t k = 0; k < kDramCommands; ++k) channel[k] = std::max(ch.earliest[k], ch.free_from);
    return channel;
  }

  // Request i's proposal as the order the policy picks by, in one word: the earlier cycle, then
  // at the same cycle (FR-FCFS) a column command first; the older request (arrival, then enqueue
  // order) breaks a tie. kHeld when the policy holds it back: its column command while another
  // request owns the column commands, its PRE while its bank has a queued hit (FR-FCFS) or a
  // started request (FCFS).
  static uint64_t proposal_key(const DramChannel& ch, const DramStamps& channel, size_t i,
                               const Holders& h) {
    const DramRequest& r = ch.queue[i];
    const DramBank& b = ch.banks[r.bank];
    const bool hit = b.open & (b.row == r.row);
    const bool owned = h.owner != ch.queue.size();
    const bool held_pre =
        kFirstReady ? (h.hit_banks >> r.bank) & 1 : owned & (r.bank == h.owner_bank);
    const bool held = hit ? owned & (h.owner != i) : b.open & held_pre;
    const size_t k = size_t(next_command(b, r));
    const uint64_t cycle = std::max({b.earliest[k], channel[k], r.arrival_cycle});
    return held ? kHeld : cycle << 1 | uint64_t(kFirstReady & !hit);
  }

  // A pick's key (proposal_key), from the pick.
  static uint64_t pick_key(const DramChoice& c) {
    return c.cycle << 1 | uint64_t(kFirstReady & !dram_is_column(c.command));
  }

  // The pick of request i, whose proposal's key is `key`.
  static DramChoice choice(const DramChannel& ch, size_t i, uint64_t key) {
    const DramRequest& r = ch.queue[i];
    return DramChoice{i, next_command(ch.banks[r.bank], r), key >> 1, r.bank};
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
