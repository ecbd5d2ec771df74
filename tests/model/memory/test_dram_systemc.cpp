// The Dram sc_module, a TLM-2.0 target, under the SystemC kernel and driven through the
// accelerator's TLM-2.0 initiator (model/memory/memory_port.h): idle latencies seen by a requester
// on the 1 GHz accelerator clock, the data carried by the responses, and posted writes into a store
// that extends past the memory image. SystemC elaborates once per process, so one simulation holds
// both scenarios: independent Dram modules on the one calendar, built (with the checks that must
// run before sc_start) and run once by the first test; each test then checks its own module.
#include "model/memory/dram.h"
#include "model/memory/memory_port.h"
#include "model/sim/stats_registry.h"

#include "tests/test_util.h"

#include <gtest/gtest.h>
#include <systemc>

#include <memory>
#include <stdexcept>
#include <vector>

namespace rtsim::model {
namespace {

struct Fill {
  uint64_t line, cookie;
  Tick when;                   // the time on_fill reports
  Tick sim_time;               // the simulation time of the call
  std::vector<uint8_t> bytes;  // the line's bytes as the response brought them
};

class Recorder : public FillListener {
 public:
  explicit Recorder(const LineSource* port) : port_(port) {}
  std::vector<Fill> fills;
  void on_fill(uint64_t line_addr, uint64_t cookie, Tick when) override {
    const uint8_t* p = port_->line_data(line_addr);
    fills.push_back({line_addr, cookie, when, Tick(sc_core::sc_time_stamp().value()),
                     std::vector<uint8_t>(p, p + 32)});
  }

 private:
  const LineSource* port_;
};

Tick sim_now() { return Tick(sc_core::sc_time_stamp().value()); }

std::vector<uint8_t> bytes_of(const uint8_t* p, size_t n = 32) {
  return std::vector<uint8_t>(p, p + n);
}

// Issues one read at each of 0, 100, 200 and 300 ns.
class ReadDriver : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(ReadDriver);
  ReadDriver(sc_core::sc_module_name name, MemoryPort& port, Recorder& rec)
      : sc_module(name), port_(port), rec_(rec) {
    SC_THREAD(run);
  }
  std::vector<Tick> returned;

 private:
  void run() {
    const uint64_t lines[] = {0, 32, 1u << 17, 256};
    for (uint64_t i = 0; i < 4; ++i) {
      if (i) wait(100, sc_core::SC_NS);
      returned.push_back(port_.fetch_line(lines[i], sim_now(), &rec_, i + 1));
    }
  }
  MemoryPort& port_;
  Recorder& rec_;
};

constexpr uint64_t kImageBytes = 64 * 1024;
constexpr uint64_t kExtraBytes = 8 * 1024;
constexpr uint64_t kLine = 0x40;                      // channel 0, bank 0, row 0
constexpr uint64_t kExtraLine = kImageBytes + 0x100;  // after the image: channel 1, bank 4, row 0

// At 0 ns: a posted write of line kLine and a read of it right after. At 100 ns: a posted write
// into the space after the image; at 200 ns a read of it.
class WriteDriver : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(WriteDriver);
  WriteDriver(sc_core::sc_module_name name, MemoryPort& port, const Dram& dram, Recorder& rec)
      : sc_module(name), port_(port), dram_(dram), rec_(rec) {
    SC_THREAD(run);
  }
  std::vector<uint8_t> a, b;  // the bytes written
  // line_data(kLine) right after write_line, before any DRAM time
  std::vector<uint8_t> right_after;

 private:
  void run() {
    for (int i = 0; i < 32; ++i) {
      a.push_back(uint8_t(0xA0 + i));
      b.push_back(uint8_t(0x50 ^ i));
    }
    port_.write_line(kLine, a.data(), sim_now(), "driver");
    right_after = bytes_of(dram_.line_data(kLine));
    port_.fetch_line(kLine, sim_now(), &rec_, 2);
    wait(100, sc_core::SC_NS);
    port_.write_line(kExtraLine, b.data(), sim_now(), "driver");
    wait(100, sc_core::SC_NS);
    port_.fetch_line(kExtraLine, sim_now(), &rec_, 3);
  }
  MemoryPort& port_;
  const Dram& dram_;
  Recorder& rec_;
};

struct Scenario {
  std::vector<uint8_t> memory, image, odd_image;
  std::unique_ptr<Calendar> calendar;
  std::unique_ptr<Dram> dram;
  std::unique_ptr<MemoryPort> port;
  std::unique_ptr<Recorder> rec;
  std::unique_ptr<ReadDriver> driver;
  StatsRegistry reg;

  std::unique_ptr<Dram> wdram;
  std::unique_ptr<MemoryPort> wport;
  std::unique_ptr<Recorder> wrec;
  std::unique_ptr<WriteDriver> wdriver;
  std::unique_ptr<Dram> odd;          // built only for its store's layout; never accessed in time
  std::unique_ptr<MemoryPort> oport;  // (its socket must be bound all the same)

  Scenario() {
    sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
    calendar = std::make_unique<Calendar>("calendar");
    memory.resize(256 * 1024);
    for (size_t i = 0; i < memory.size(); ++i) memory[i] = uint8_t(i * 7);
    const DramConfig cfg = dram_preset("gddr3-gt200");
    dram = std::make_unique<Dram>("dram", cfg, &memory, Clock(1.0), *calendar);
    port = std::make_unique<MemoryPort>("port", cfg.request_bytes, cfg, Clock(1.0), *calendar);
    port->socket.bind(dram->socket);
    rec = std::make_unique<Recorder>(port.get());
    driver = std::make_unique<ReadDriver>("driver", *port, *rec);
    dram->register_stats(reg, "dram");

    image.resize(kImageBytes);
    for (size_t i = 0; i < image.size(); ++i) image[i] = uint8_t(i * 13 + 1);
    wdram = std::make_unique<Dram>("wdram", cfg, &image, Clock(1.0), *calendar, kExtraBytes);
    wport = std::make_unique<MemoryPort>("wport", cfg.request_bytes, cfg, Clock(1.0), *calendar);
    wport->socket.bind(wdram->socket);
    wrec = std::make_unique<Recorder>(wport.get());
    wdriver = std::make_unique<WriteDriver>("wdriver", *wport, *wdram, *wrec);

    odd_image.assign(1000, 0xEE);  // not a whole number of 32-byte lines
    odd = std::make_unique<Dram>("odd", cfg, &odd_image, Clock(1.0), *calendar, 1024);
    oport = std::make_unique<MemoryPort>("oport", cfg.request_bytes, cfg, Clock(1.0), *calendar);
    oport->socket.bind(odd->socket);

    // Checks that throw must run before sc_start: an exception thrown after the kernel has
    // switched coroutine stacks trips AddressSanitizer's false positives.
    test::ExpectReports expected({"rtsim/memory"});
    // Read scenario: data come from the memory image.
    EXPECT_EQ(dram->line_data(0), memory.data());
    EXPECT_EQ(dram->line_data(1u << 17)[5], memory[(1u << 17) + 5]);
    EXPECT_EQ(dram->line_data(memory.size() - 32), memory.data() + memory.size() - 32);
    EXPECT_THROW(dram->line_data(memory.size()), sc_core::sc_report);
    EXPECT_THROW(dram->line_data(memory.size() - 16), sc_core::sc_report);
    // A request outside the store, or not one aligned line, completes with an error response,
    // which the port reports (rtsim/memory).
    EXPECT_THROW(port->fetch_line(memory.size(), 0, rec.get(), 9), sc_core::sc_report);
    EXPECT_THROW(port->fetch_line(16, 0, rec.get(), 9), sc_core::sc_report);
    // Write scenario: the store is the image and kExtraBytes of zeros after it.
    EXPECT_EQ(wdram->store_bytes(), kImageBytes + kExtraBytes);
    EXPECT_EQ(wdram->line_data(kImageBytes - 32), image.data() + kImageBytes - 32);
    EXPECT_EQ(bytes_of(wdram->line_data(kImageBytes)), std::vector<uint8_t>(32, 0));
    EXPECT_EQ(bytes_of(wdram->line_data(kImageBytes + kExtraBytes - 32)),
              std::vector<uint8_t>(32, 0));
    EXPECT_THROW(wdram->line_data(kImageBytes + kExtraBytes), sc_core::sc_report);
    EXPECT_THROW(wport->write_line(kImageBytes + kExtraBytes, image.data(), 0, "test"),
                 sc_core::sc_report);
    EXPECT_THROW(wport->write_line(kImageBytes + 16, image.data(), 0, "test"), sc_core::sc_report);
    EXPECT_EQ(wdram->pages_written(), 0u);
    // A line across the image's end holds the image's bytes, then zeros.
    std::vector<uint8_t> across(8, 0xEE);
    across.resize(32, 0);
    EXPECT_EQ(bytes_of(odd->line_data(992)), across);
    EXPECT_EQ(odd->store_bytes(), 2024u);

    test::simulate();
  }
};

Scenario& scenario() {
  static Scenario s;  // built and simulated once per process
  return s;
}

TEST(DramSystemC, IdleLatenciesOnTheAcceleratorClock) {
  Scenario& s = scenario();
  EXPECT_EQ(s.driver->returned, std::vector<Tick>(4, kUnknown));
  ASSERT_EQ(s.rec->fills.size(), 4u);
  // Closed bank 30 ns; row hit 15 ns; row conflict 42.5 ns -> the 1 GHz edge at 43 ns; a closed
  // bank in another channel 30 ns.
  const Tick expect_when[] = {30000, 115000, 243000, 330000};
  const uint64_t expect_line[] = {0, 32, 1u << 17, 256};
  for (size_t i = 0; i < 4; ++i) {
    EXPECT_EQ(s.rec->fills[i].cookie, i + 1);
    EXPECT_EQ(s.rec->fills[i].line, expect_line[i]);
    EXPECT_EQ(s.rec->fills[i].when, expect_when[i]);
    EXPECT_EQ(s.rec->fills[i].sim_time, expect_when[i]);  // delivered at that time, not earlier
  }
  EXPECT_EQ(s.dram->stats().row_misses, 2u);
  EXPECT_EQ(s.dram->stats().row_hits, 1u);
  EXPECT_EQ(s.dram->stats().row_conflicts, 1u);
  EXPECT_EQ(s.dram->stats().channel_reads[1], 1u);
  EXPECT_DOUBLE_EQ(s.reg.value("dram.reads"), 4.0);
  // Engine time is DRAM time (42.5 ns), not the accelerator edge.
  EXPECT_DOUBLE_EQ(s.reg.value("dram.avg_latency_ns"), (30.0 + 15.0 + 42.5 + 30.0) / 4);
}

TEST(DramSystemC, PostedWriteThenReadReturnsTheWrittenBytes) {
  Scenario& s = scenario();
  const WriteDriver& d = *s.wdriver;
  EXPECT_EQ(d.right_after, d.a);  // stored at once, before any DRAM time
  ASSERT_EQ(s.wrec->fills.size(), 2u);
  // The write (ACT 0, WR at tRCD - (WL + 1) = 4) is done at 4 + WL + BL/2 = 13 cycles = 16.25 ns.
  // The read of the same line waits for the write-to-read turnaround: RD at 4 + 15 = 19 (not
  // tRCD = 12), data at 19 + 12 = 31 cycles = 38.75 ns -> the 1 GHz edge at 39 ns, with the
  // written bytes.
  EXPECT_EQ(s.wrec->fills[0].cookie, 2u);
  EXPECT_EQ(s.wrec->fills[0].when, 39000u);
  EXPECT_EQ(s.wrec->fills[0].sim_time, 39000u);
  EXPECT_EQ(s.wrec->fills[0].bytes, d.a);
  // The posted write after the image (channel 1: ACT 80, WR 84) and its read at 200 ns = cycle 160,
  // a row hit long after the turnaround: data at 172 cycles = 215 ns.
  EXPECT_EQ(s.wrec->fills[1].cookie, 3u);
  EXPECT_EQ(s.wrec->fills[1].line, kExtraLine);
  EXPECT_EQ(s.wrec->fills[1].when, 215000u);
  EXPECT_EQ(s.wrec->fills[1].bytes, d.b);
  EXPECT_EQ(s.wport->stats().writes, 4u);     // with the two answered by an error before the run
  EXPECT_EQ(s.wport->stats().responses, 4u);  // two reads, and the two good writes' responses

  EXPECT_EQ(bytes_of(s.wdram->line_data(kLine)), d.a);
  EXPECT_EQ(bytes_of(s.wdram->line_data(kExtraLine)), d.b);
  // Copy-on-write: the written lines' neighbours keep their bytes, and the image is untouched.
  EXPECT_EQ(bytes_of(s.wdram->line_data(kLine + 32)), bytes_of(s.image.data() + kLine + 32));
  EXPECT_EQ(bytes_of(s.wdram->line_data(kLine - 32)), bytes_of(s.image.data() + kLine - 32));
  EXPECT_EQ(bytes_of(s.wdram->line_data(kExtraLine + 32)), std::vector<uint8_t>(32, 0));
  EXPECT_EQ(s.image[kLine], uint8_t(kLine * 13 + 1));
  EXPECT_EQ(s.wdram->pages_written(), 2u);

  const DramStats& st = s.wdram->stats();
  EXPECT_EQ(st.write_requests, 2u);
  EXPECT_EQ(st.writes, 2u);
  EXPECT_EQ(st.write_bursts, 2u);
  EXPECT_EQ(st.bytes_written, 64u);
  EXPECT_EQ(st.requests, 2u);
  EXPECT_EQ(st.reads, 2u);
  EXPECT_EQ(st.row_misses, 2u);  // the two writes opened their rows
  EXPECT_EQ(st.row_hits, 2u);    // the two reads found them open
  EXPECT_EQ(st.last_write_completion_ps, 93 * 1250u);
}

}  // namespace
}  // namespace rtsim::model
