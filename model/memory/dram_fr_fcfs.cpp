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

    const bool owned = owner != ch.queue.size();
    DramChoice best;
    for (size_t i = 0; i < ch.queue.size(); ++i) {
      const DramRequest& r = ch.queue[i];
      const DramBank& b = ch.banks[r.bank];
      DramCommand cmd;
      if (b.open && b.row == r.row) {
        if (owned && owner != i) continue;  // the column commands are taken
        cmd = r.write ? DramCommand::kWrite : DramCommand::kRead;
      } else if (b.open) {
        // FR-FCFS keeps the row open for its queued hits; both keep it for a started request.
        if (kFirstReady ? hit_pending_[r.bank] != 0 : owned && r.bank == ch.queue[owner].bank)
          continue;
        cmd = DramCommand::kPrecharge;
      } else {
        cmd = DramCommand::kActivate;
      }
      const size_t k = size_t(cmd);
      const uint64_t cycle =
          std::max({b.earliest[k], ch.earliest[k], r.arrival_cycle, ch.free_from});
      bool better = cycle < best.cycle;
      if (cycle == best.cycle) {
        const DramRequest& o = ch.queue[best.index];
        const bool older = r.arrival != o.arrival ? r.arrival < o.arrival : r.seq < o.seq;
        const bool col = dram_is_column(cmd), best_col = dram_is_column(best.command);
        better = kFirstReady && col != best_col ? col : older;
      }
      if (better) best = DramChoice{i, cmd, cycle, r.bank};
    }
    return best;
  }

 private:
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
