// The Dram sc_module under the SystemC kernel: idle latencies seen by a requester on the 1 GHz
// accelerator clock. SystemC elaborates once per process, so this file holds one scenario.
#include "model/dram.h"
#include "model/stats_registry.h"

#include <gtest/gtest.h>
#include <systemc>

#include <stdexcept>
#include <vector>

namespace rtsim::model {
namespace {

struct Fill {
  uint64_t line, cookie;
  Tick when;      // the time on_fill reports
  Tick sim_time;  // the simulation time of the call
};

class Recorder : public FillListener {
 public:
  std::vector<Fill> fills;
  void on_fill(uint64_t line_addr, uint64_t cookie, Tick when) override {
    fills.push_back(Fill{line_addr, cookie, when, Tick(sc_core::sc_time_stamp().value())});
  }
};

// Issues one read at each of 0, 100, 200 and 300 ns.
class Driver : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(Driver);
  Driver(sc_core::sc_module_name name, Dram& dram, Recorder& rec) : sc_module(name), dram_(dram), rec_(rec) {
    SC_THREAD(run);
  }
  std::vector<Tick> returned;

 private:
  void run() {
    const uint64_t lines[] = {0, 32, 1u << 17, 256};
    for (uint64_t i = 0; i < 4; ++i) {
      if (i) wait(100, sc_core::SC_NS);
      const Tick now = Tick(sc_core::sc_time_stamp().value());
      returned.push_back(dram_.fetch_line(lines[i], now, &rec_, i + 1));
    }
  }
  Dram& dram_;
  Recorder& rec_;
};

TEST(DramSystemC, IdleLatenciesOnTheAcceleratorClock) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  std::vector<uint8_t> memory(256 * 1024);
  for (size_t i = 0; i < memory.size(); ++i) memory[i] = uint8_t(i * 7);
  Recorder rec;
  Dram dram("dram", dram_preset("gddr3-gt200"), &memory, Clock(1.0));
  Driver driver("driver", dram, rec);
  StatsRegistry reg;
  dram.register_stats(reg, "dram");

  // Data come from the memory image. (Checked before sc_start: an exception thrown after the
  // kernel has switched coroutine stacks trips AddressSanitizer's false positives.)
  EXPECT_EQ(dram.line_data(0), memory.data());
  EXPECT_EQ(dram.line_data(1u << 17)[5], memory[(1u << 17) + 5]);
  EXPECT_EQ(dram.line_data(memory.size() - 32), memory.data() + memory.size() - 32);
  EXPECT_THROW(dram.line_data(memory.size()), std::out_of_range);
  EXPECT_THROW(dram.line_data(memory.size() - 16), std::out_of_range);
  EXPECT_THROW(dram.fetch_line(memory.size(), 0, &rec, 9), std::out_of_range);
  EXPECT_THROW(dram.fetch_line(16, 0, &rec, 9), std::logic_error);  // not a 32-byte line address

  sc_core::sc_start();

  EXPECT_EQ(driver.returned, std::vector<Tick>(4, kUnknown));
  ASSERT_EQ(rec.fills.size(), 4u);
  // Closed bank 30 ns; row hit 15 ns; row conflict 42.5 ns -> the 1 GHz edge at 43 ns; a closed
  // bank in another channel 30 ns.
  const Tick expect_when[] = {30000, 115000, 243000, 330000};
  const uint64_t expect_line[] = {0, 32, 1u << 17, 256};
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(rec.fills[i].cookie, i + 1);
    EXPECT_EQ(rec.fills[i].line, expect_line[i]);
    EXPECT_EQ(rec.fills[i].when, expect_when[i]);
    EXPECT_EQ(rec.fills[i].sim_time, expect_when[i]);  // delivered at that time, not earlier
  }
  EXPECT_EQ(dram.stats().row_misses, 2u);
  EXPECT_EQ(dram.stats().row_hits, 1u);
  EXPECT_EQ(dram.stats().row_conflicts, 1u);
  EXPECT_EQ(dram.stats().channel_reads[1], 1u);
  EXPECT_DOUBLE_EQ(reg.value("dram.reads"), 4.0);
  // Engine time is DRAM time (42.5 ns), not the accelerator edge.
  EXPECT_DOUBLE_EQ(reg.value("dram.avg_latency_ns"), (30.0 + 15.0 + 42.5 + 30.0) / 4);
}

}  // namespace
}  // namespace rtsim::model
