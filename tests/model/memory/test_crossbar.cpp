// The interconnect: a packet's flits over ports of a given width, latency, and queueing where
// packets meet; and a crossbar port in front of a banked cache.
#include "model/memory/cache.h"
#include "model/memory/crossbar.h"

#include <gtest/gtest.h>

#include <vector>

namespace rtsim::model {
namespace {

constexpr Tick kCycle = 1000;

LinkConfig link(uint32_t width, uint32_t latency = 0, uint32_t header = 0) {
  LinkConfig l;
  l.bytes_per_cycle = width;
  l.latency = latency;
  l.header_bytes = header;
  return l;
}

TEST(Crossbar, ALineOverAPortTakesLineOverWidthCycles) {
  for (uint32_t width : {8u, 16u, 32u, 64u}) {
    Crossbar x("x", link(width), Clock(), 1, 1);
    EXPECT_EQ(x.reply(0, 0, 64, 10 * kCycle), (10 + 64 / width) * kCycle) << width;
  }
}

TEST(Crossbar, LatencyAndHeaderAddToThePacket) {
  // 64 + 8 bytes over 32-byte flits: 3 flits; 2 cycles of wire.
  Crossbar x("x", link(32, 2, 8), Clock(), 1, 1);
  EXPECT_EQ(x.reply(0, 0, 64, 0), (2 + 3) * kCycle);
  // A header-only request is one flit.
  EXPECT_EQ(x.request(0, 0, 0, 0), (2 + 1) * kCycle);
}

TEST(Crossbar, PacketsMeetingAtADestinationQueue) {
  // Two sources send a 64-byte line each to one destination over 32-byte ports at once: the
  // destination receives one flit per cycle, so the second packet is there two cycles later.
  Crossbar x("x", link(32), Clock(), 2, 1);
  EXPECT_EQ(x.request(0, 0, 64, 0), 2 * kCycle);
  EXPECT_EQ(x.request(1, 0, 64, 0), 4 * kCycle);
}

TEST(Crossbar, PacketsToDifferentDestinationsDoNotQueue) {
  Crossbar x("x", link(32), Clock(), 2, 2);
  EXPECT_EQ(x.request(0, 0, 64, 0), 2 * kCycle);
  EXPECT_EQ(x.request(1, 1, 64, 0), 2 * kCycle);
}

TEST(Crossbar, RequestsAndRepliesUseSeparateNetworks) {
  Crossbar x("x", link(32), Clock(), 1, 1);
  EXPECT_EQ(x.request(0, 0, 64, 0), 2 * kCycle);
  EXPECT_EQ(x.reply(0, 0, 64, 0), 2 * kCycle);
}

// GPGPU-Sim's 8-flit input buffers, here 2: a flit that would wait more than 2 cycles at its
// destination waits at its source instead, and blocks the source's port meanwhile.
TEST(Crossbar, AFullDestinationBufferHoldsTheFlitAndBlocksItsSource) {
  for (uint32_t buffer : {0u, 2u}) {
    LinkConfig l = link(32);
    l.buffer_flits = buffer;
    Crossbar x("x", l, Clock(), 2, 2);
    for (int k = 0; k < 8; ++k) x.request(0, 0, 0, 0);  // destination 0 busy for 8 cycles
    EXPECT_EQ(x.request(1, 0, 0, 0), 9 * kCycle);       // its arrival does not change
    // Source 1's next packet, to an idle destination, waits behind the held flit.
    EXPECT_EQ(x.request(1, 1, 0, 0), (buffer ? 8 : 2) * kCycle) << buffer;
  }
}

TEST(Crossbar, TheIdealWireAddsOnlyItsLatency) {
  Crossbar x("x", link(0, 3), Clock(), 4, 4);
  for (int k = 0; k < 10; ++k) EXPECT_EQ(x.reply(0, 0, 64, 5 * kCycle), 8 * kCycle);
}

// A memory answering every line after a fixed latency.
class FixedMemory : public LineSource {
 public:
  Tick fetch_line(uint64_t, Tick now, FillListener*, uint64_t) override {
    return now + 10 * kCycle;
  }
  const uint8_t* line_data(uint64_t) const override { return bytes.data(); }
  uint32_t line_bytes() const override { return 64; }
  std::vector<uint8_t> bytes = std::vector<uint8_t>(64, 7);
};

CacheConfig banked(uint32_t banks, uint32_t ports) {
  CacheConfig c;
  c.size_bytes = 8192;
  c.ways = 2;
  c.line_bytes = 64;
  c.hit_latency = 4;
  c.mshrs = 16;
  c.banks = banks;
  c.ports = ports;
  return c;
}

TEST(CrossbarPort, RepliesFromOneBankQueueAtItsPortAndFromTwoBanksDoNot) {
  FixedMemory mem;
  Cache l2("l2", banked(2, 0), Clock(), &mem);
  l2.fetch_line(0, 0, nullptr, 0);  // lines 0 (bank 0), 64 (bank 1), 128 (bank 0) present by 14
  l2.fetch_line(64, 0, nullptr, 0);
  l2.fetch_line(128, 0, nullptr, 0);
  Crossbar x("x", link(32), Clock(), 2, 2);
  CrossbarPort a(&x, 0, 1, &l2, 64), b(&x, 1, 1, &l2, 64);
  // Request: one flit (1 cycle); L2 hit: 4; reply: 2 flits.
  const Tick t = 100 * kCycle;
  EXPECT_EQ(a.fetch_line(0, t, nullptr, 0), t + 7 * kCycle);
  EXPECT_EQ(b.fetch_line(64, t, nullptr, 0), t + 7 * kCycle);   // the other bank: in parallel
  EXPECT_EQ(b.fetch_line(128, t, nullptr, 0), t + 9 * kCycle);  // bank 0's reply port is busy
}

}  // namespace
}  // namespace rtsim::model
