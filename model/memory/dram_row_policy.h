// The DRAM row policy (DramConfig::row_policy): whether a request's last burst closes its row.
// Asked once per completed request, not per cycle.
//  - Open page (GT200's, the default): rows stay open; only a conflict's PRE closes them.
//  - Closed page: the last burst precharges the bank (auto-precharge: no command slot, at the
//    earliest cycle the bank's PRE rules allow) unless another queued request hits the same row,
//    which then keeps it open for its own burst(s). A later request to the row pays ACT again.
// Implementations register by name (dram_policies.h): dram_open_page.cpp, dram_closed_page.cpp.
#pragma once

#include "model/memory/dram_channel.h"
#include "model/memory/dram_config.h"

#include <cstddef>

namespace rtsim::model {

class DramRowPolicy {
 public:
  virtual ~DramRowPolicy() = default;
  // After the last burst of ch.queue[done]: precharge its bank now?
  virtual bool close_after(const DramChannel& ch, size_t done) const = 0;
};

}  // namespace rtsim::model
