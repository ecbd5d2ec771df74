// All-bank refresh: a REF every tREFI cycles per channel, which blocks every bank of the channel
// for tRFC (dram_refresh.h has the sequence: the started request's bursts, PREs, then REF).
#include "model/memory/dram_policies.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace rtsim::model {

namespace {

class AllBankRefresh final : public DramRefreshPolicy {
 public:
  // Throws std::invalid_argument naming the field that does not fit (DramConfig::validate()).
  explicit AllBankRefresh(const DramConfig& config) : tREFI_(config.tREFI) {
    if (config.tRFC == 0)
      throw std::invalid_argument("DramConfig.tRFC: must be >= 1 with refresh: all-bank");
    // Otherwise the channel would do nothing but refresh.
    if (config.tREFI <= config.tRFC)
      throw std::invalid_argument("DramConfig.tREFI: must be > tRFC (" +
                                  std::to_string(config.tRFC) + ") with refresh: all-bank, got " +
                                  std::to_string(config.tREFI));
  }

  DramChoice arbitrate(const DramChannel& ch, const DramChoice& pick) const override {
    if (ch.queue.empty() || pick.cycle < ch.refresh_due) return pick;
    // A started request keeps the column commands until its last burst.
    for (size_t i = 0; i < ch.queue.size(); ++i) {
      const DramRequest& r = ch.queue[i];
      if (r.bursts_issued == 0) continue;
      const DramCommand cmd = r.write ? DramCommand::kWrite : DramCommand::kRead;
      const size_t k = size_t(cmd);
      const uint64_t cycle =
          std::max({ch.banks[r.bank].earliest[k], ch.earliest[k], r.arrival_cycle, ch.free_from});
      return DramChoice{i, cmd, cycle, r.bank};
    }
    return next_command(ch);
  }

  DramChoice catch_up(const DramChannel& ch, uint64_t until) const override {
    if (!ch.queue.empty() || ch.refresh_due > until) return {};
    return next_command(ch);
  }

  uint64_t first_due() const override { return tREFI_; }

 private:
  // The earliest PRE of an open bank; with every bank closed, the REF.
  static DramChoice next_command(const DramChannel& ch) {
    const size_t pre = size_t(DramCommand::kPrecharge), ref = size_t(DramCommand::kRefresh);
    const uint64_t from = std::max(ch.free_from, ch.refresh_due);
    DramChoice best;
    for (uint32_t b = 0; b < ch.banks.size(); ++b) {
      const DramBank& bank = ch.banks[b];
      if (!bank.open) continue;
      const uint64_t cycle = std::max({bank.earliest[pre], ch.earliest[pre], from});
      if (cycle < best.cycle) best = DramChoice{kDramNoRequest, DramCommand::kPrecharge, cycle, b};
    }
    if (best.cycle != kDramNever) return best;
    return DramChoice{kDramNoRequest, DramCommand::kRefresh, std::max(ch.earliest[ref], from), 0};
  }

  uint64_t tREFI_;
};

}  // namespace

void add_all_bank_refresh(DramRefreshPolicies& r) {
  r.add(
      "all-bank", [](const DramConfig& c) { return std::make_unique<AllBankRefresh>(c); },
      "REF every tREFI, all banks blocked for tRFC");
}

}  // namespace rtsim::model
