// The DRAM refresh policy (DramConfig::refresh). Asked once per decision, not per cycle.
//  - None (GT200's, the default; GPGPU-Sim models no refresh).
//  - All-bank: a REF is due every tREFI cycles per channel (the first at tREFI). From the cycle it
//    is due, the channel lets a started request finish its bursts, then precharges its open banks
//    (one PRE per bank, at the earliest legal cycles) and issues REF once ACT -> REF tRC and
//    PRE -> REF tRP allow; REF keeps every ACT of the channel back for tRFC. Requests wait
//    meanwhile. A late REF does not move the next one: refresh_due advances by tREFI each time.
//    A channel with nothing queued issues no commands (the engine is then idle and costs no host
//    time); the refreshes it would have issued meanwhile are issued when its next request arrives
//    (catch_up), at the cycles they were due, so the request sees them as if they had happened.
//    Refreshes after a channel's last request are therefore not counted.
// Implementations register by name (dram_policies.h): dram_no_refresh.cpp,
// dram_all_bank_refresh.cpp (which also checks tREFI and tRFC).
#pragma once

#include "model/memory/dram_channel.h"
#include "model/memory/dram_config.h"

#include <cstdint>

namespace rtsim::model {

class DramRefreshPolicy {
 public:
  virtual ~DramRefreshPolicy() = default;
  // The command a channel with queued requests issues: the scheduler's `pick`, or a refresh's PRE
  // or REF (index kDramNoRequest) when one is due by then.
  virtual DramChoice arbitrate(const DramChannel& ch, const DramChoice& pick) const = 0;
  // For a channel with nothing queued: its next refresh command if one is due at or before cycle
  // `until`; cycle kDramNever otherwise.
  virtual DramChoice catch_up(const DramChannel& ch, uint64_t until) const = 0;
  // The first REF's due cycle (kDramNever: never).
  virtual uint64_t first_due() const = 0;
};

}  // namespace rtsim::model
