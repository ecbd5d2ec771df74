// One DRAM channel's state as the timing engine (dram_controller.h) keeps it and its policies
// (dram_scheduler.h, dram_row_policy.h, dram_refresh.h) read it: the banks' open rows, the earliest
// legal cycle of every command per bank and per channel, and the queued requests.
#pragma once

#include "model/memory/line_source.h"

#include <array>
#include <cstdint>
#include <deque>
#include <vector>

namespace rtsim::model {

// Column commands (RD, WR) come last: dram_is_column() relies on it.
enum class DramCommand : uint8_t { kActivate, kPrecharge, kRefresh, kRead, kWrite };
inline constexpr size_t kDramCommands = 5;
constexpr bool dram_is_column(DramCommand c) { return c >= DramCommand::kRead; }

inline constexpr uint64_t kDramNever = ~uint64_t(0);
// The request index of a command no request asked for (a refresh's PRE and REF).
inline constexpr size_t kDramNoRequest = ~size_t(0);

using DramStamps = std::array<uint64_t, kDramCommands>;  // earliest legal cycle per command

// One host cache line each, the fields the scheduler reads first: it scans the queue after every
// command, and on a memory-bound frame the scan waits on the host's memory.
struct alignas(64) DramRequest {
  Tick arrival;
  uint64_t arrival_cycle;  // first command-clock edge at or after arrival
  uint64_t row;
  uint32_t bank;
  uint32_t bursts_issued;
  bool write;
  bool classified;
  uint64_t id, seq, column;
};

struct DramBank {
  bool open = false;
  uint64_t row = 0;
  DramStamps earliest{};
};

struct DramChannel {
  std::vector<DramBank> banks;
  DramStamps earliest{};
  std::vector<DramRequest> queue;  // at most queue_size, in enqueue order
  std::deque<DramRequest> overflow;
  uint64_t free_from = 0;            // first cycle after the last issued command
  uint64_t next_cycle = kDramNever;  // cycle of the next legal command (cached)
  uint64_t refresh_due = 0;          // cycle the next REF is due (refresh: all-bank)
};

// A command to issue: for queue[index] (or kDramNoRequest) in `bank`, at `cycle`.
struct DramChoice {
  size_t index = 0;
  DramCommand command = DramCommand::kRead;
  uint64_t cycle = kDramNever;
  uint32_t bank = 0;
};

}  // namespace rtsim::model
