// The DRAM scheduler policy (DramConfig::scheduler): which queued request's next command a channel
// issues. One virtual call per decision (after a command or an arrival), not per cycle.
//
// Every queued request proposes the next command it needs: RD or WR if its bank has its row open
// (a row hit), ACT if the bank is closed, PRE if another row is open. A request between its first
// and last burst owns the channel's column commands (its bursts go back to back). The policy picks
// among the proposals legal at the earliest cycle at which any is:
//  - FR-FCFS (GPGPU-Sim's, the default): column commands (row hits) first, then the oldest
//    request (arrival time, then order of enqueue). A PRE is not proposed while a queued request
//    still hits the open row, so first-ready hits are not closed under their feet.
//  - FCFS: the oldest request first, hit or not, and a conflict's PRE is proposed even while
//    younger requests hit the open row (an older conflict is served before a younger hit), but
//    not for the bank of a request between its bursts.
// Implementations register by name (dram_policies.h): dram_fr_fcfs.cpp.
#pragma once

#include "model/memory/dram_channel.h"
#include "model/memory/dram_config.h"

#include <cstddef>

namespace rtsim::model {

class DramScheduler {
 public:
  virtual ~DramScheduler() = default;
  // The pick at the earliest cycle with a legal proposal; cycle kDramNever for an empty queue.
  virtual DramChoice choose(const DramChannel& ch) = 0;
  // choose(ch) once request `added` (the queue's last) has joined a queue whose pick was
  // `before`, nothing else having changed: a policy may weigh the one new proposal instead of
  // every one. By default it chooses again.
  virtual DramChoice add(const DramChannel& ch, const DramChoice& before, size_t added) {
    (void)before;
    (void)added;
    return choose(ch);
  }
};

}  // namespace rtsim::model
