#include "model/memory/dram_rows.h"

#include "model/memory/dram_policies.h"

#include <algorithm>

namespace rtsim::model {

DramRows::DramRows(const DramConfig& c)
    : mapping_(c.address_mapping, c.channels),
      policy_(dram_row_policies().make(c.row_policy, c)),
      channels_(c.channels) {
  for (DramChannel& ch : channels_) {
    ch.banks.resize(c.banks);
    ch.queue.resize(1);
  }
  // A line's bursts, a column command each, no closer than tCCD (tCCD_L within a bank group).
  const uint32_t burst = c.burst_cycles(), bursts = std::max<uint32_t>(1, c.bursts_per_request());
  const uint32_t data = c.CL + burst + (bursts - 1) * std::max(burst, c.ccd_same_group());
  cycles_[kRowHit] = data;
  cycles_[kIdleBank] = c.tRCD + data;
  cycles_[kRowConflict] = c.tRP + c.tRCD + data;
}

DramRows::~DramRows() = default;

DramRows::Outcome DramRows::read(uint64_t addr) {
  const DramAddress a = mapping_.decode(addr);
  DramChannel& ch = channels_[a.channel];
  DramBank& bank = ch.banks[a.bank];
  const Outcome o = !bank.open ? kIdleBank : bank.row == a.row ? kRowHit : kRowConflict;
  DramRequest& r = ch.queue[0];
  r.bank = a.bank;
  r.row = a.row;
  r.column = a.column;
  bank.open = !policy_->close_after(ch, 0);
  bank.row = a.row;
  return o;
}

}  // namespace rtsim::model
