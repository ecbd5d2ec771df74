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
  explicit QueueScheduler(const DramConfig& config) : hit_pending_(config.banks) {}

  DramChoice choose(const DramChannel& ch) override {
    if (kFirstReady) std::fill(hit_pending_.begin(), hit_pending_.end(), uint8_t(0));
    size_t owner = ch.queue.size();  // the request between its first and last burst, if any
    for (size_t i = 0; i < ch.queue.size(); ++i) {
      const DramRequest& r = ch.queue[i];
      const DramBank& b = ch.banks[r.bank];
      if (kFirstReady && b.open && b.row == r.row) hit_pending_[r.bank] = 1;
      if (r.bursts_issued > 0) owner = i;
    }
    DramChoice best;
    for (size_t i = 0; i < ch.queue.size(); ++i) {
      DramChoice c;
      if (propose(ch, i, owner, kFirstReady && hit_pending_[ch.queue[i].bank] != 0, c) &&
          better(ch, c, best))
        best = c;
    }
    return best;
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
  // Request i's proposal into `c`, unless the policy holds it back: its column command while
  // another request owns the column commands (`owner`, queue.size() for none), its PRE while its
  // bank has a queued hit (FR-FCFS: `hit_pending`) or a started request (FCFS).
  static bool propose(const DramChannel& ch, size_t i, size_t owner, bool hit_pending,
                      DramChoice& c) {
    const DramRequest& r = ch.queue[i];
    const DramBank& b = ch.banks[r.bank];
    const bool owned = owner != ch.queue.size();
    DramCommand cmd;
    if (b.open && b.row == r.row) {
      if (owned && owner != i) return false;  // the column commands are taken
      cmd = r.write ? DramCommand::kWrite : DramCommand::kRead;
    } else if (b.open) {
      // FR-FCFS keeps the row open for its queued hits; both keep it for a started request.
      if (kFirstReady ? hit_pending : owned && r.bank == ch.queue[owner].bank) return false;
      cmd = DramCommand::kPrecharge;
    } else {
      cmd = DramCommand::kActivate;
    }
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

  std::vector<uint8_t> hit_pending_;  // bank has a queued row hit
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
