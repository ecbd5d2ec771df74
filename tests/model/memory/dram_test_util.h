// What the DRAM engine's tests share: address bits of the GT200 mapping, the clock, and helpers
// that run the engine to its end and read its command trace.
#pragma once

#include "model/memory/dram_config.h"
#include "model/memory/dram_controller.h"
#include "model/sim/stats_registry.h"

#include <gtest/gtest.h>

#include <stdexcept>
#include <string>
#include <vector>

namespace rtsim::model::dram_test {

using Cmd = DramController::Command;

// Addresses under the GT200 mapping (bits: 0-4 byte, 5-7 column, 8-10 channel, 11-13 column,
// 14-16 bank, 17+ row).
constexpr uint64_t kCol1 = 1u << 5;

constexpr uint64_t kChan1 = 1u << 8;
constexpr uint64_t kBank1 = 1u << 14;
constexpr uint64_t kRow1 = 1u << 17;
constexpr Tick kNs = 1000;
constexpr Tick kTck = 1250;
inline DramConfig gt200() { return dram_preset("gddr3-gt200"); }

// Runs the engine until it is idle; returns every completion.
inline std::vector<DramController::Completion> drain(DramController& e) {
  std::vector<DramController::Completion> done;
  for (Tick t = e.next_event_time(); t != kUnknown; t = e.next_event_time()) e.advance(t, done);
  return done;
}

inline Tick ready_of(const std::vector<DramController::Completion>& done, uint64_t id) {
  for (const auto& c : done)
    if (c.id == id) return c.data_ready;
  ADD_FAILURE() << "no completion for id " << id;
  return kUnknown;
}

inline std::vector<Tick> times_of(const std::vector<DramController::CommandRecord>& trace,
                                  Cmd cmd) {
  std::vector<Tick> out;
  for (const auto& r : trace)
    if (r.command == cmd) out.push_back(r.time);
  return out;
}

// Three reads (or writes) 100 ns apart on an idle engine: a closed bank, then a row hit (row 0 is
// open), then a row conflict. Returns their latencies.
inline std::vector<Tick> idle_latencies(DramController& e, bool write = false) {
  std::vector<DramController::Completion> done;
  const std::vector<uint64_t> addrs{0, kCol1, kRow1};
  for (uint64_t i = 0; i < addrs.size(); ++i) {
    e.enqueue(addrs[i], i * 100 * kNs, i + 1, write);
    e.advance((i + 1) * 100 * kNs, done);
  }
  EXPECT_EQ(done.size(), 3u);
  for (const auto& c : done) EXPECT_EQ(c.write, write);
  std::vector<Tick> latency;
  for (uint64_t i = 0; i < addrs.size(); ++i)
    latency.push_back(ready_of(done, i + 1) - i * 100 * kNs);
  return latency;
}

inline std::vector<uint64_t> ids_of(const std::vector<DramController::CommandRecord>& trace,
                                    Cmd cmd) {
  std::vector<uint64_t> out;
  for (const auto& r : trace)
    if (r.command == cmd) out.push_back(r.id);
  return out;
}

// Opens row 0 of bank 0 (and of bank 1 with `bank1`) with reads at 0 and runs to 100 ns (cycle
// 80), so that the requests a test enqueues at 100 ns find the engine idle.
inline void open_rows(DramController& e, bool bank1 = false) {
  std::vector<DramController::Completion> done;
  e.enqueue(0, 0, 100);
  if (bank1) e.enqueue(kBank1, 0, 101);
  e.advance(100 * kNs, done);
  ASSERT_EQ(done.size(), bank1 ? 2u : 1u);
}

}  // namespace rtsim::model::dram_test
