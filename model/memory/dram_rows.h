// The DRAM's open rows without time (the accelerator's functional mode, model/functional/): each
// line read finds its bank as the configured DRAM's address mapping and row policy leave it, with
// nothing else queued, and costs what the DRAM's timings say of that state: a row hit CL, an idle
// bank tRCD + CL, another row open tRP + tRCD + CL, then the line's bursts. The banks are the
// controller's own state (DramChannel's DramBank) and the policy is the registered one it runs
// (dram_row_policy.h). Not modelled: time (a bank's tRAS or tRC still running), the queues and the
// scheduler's reordering, the bus, refresh.
#pragma once

#include "model/memory/dram_channel.h"
#include "model/memory/dram_config.h"
#include "model/memory/dram_row_policy.h"

#include <cstdint>
#include <memory>
#include <vector>

namespace rtsim::model {

class DramRows {
 public:
  enum Outcome { kRowHit, kIdleBank, kRowConflict, kOutcomes };

  explicit DramRows(const DramConfig& config);
  ~DramRows();
  // A read of the line at `addr`: what its bank found; the bank's row is open after it unless the
  // row policy closes it.
  Outcome read(uint64_t addr);
  // The command-clock cycles from a read's ACT, PRE or RD to its line's last data beat.
  uint32_t cycles(Outcome o) const { return cycles_[o]; }

 private:
  AddressMapping mapping_;
  std::unique_ptr<DramRowPolicy> policy_;
  std::vector<DramChannel> channels_;  // their banks, and a queue of the one request asked about
  uint32_t cycles_[kOutcomes] = {};
};

}  // namespace rtsim::model
