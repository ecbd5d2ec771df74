// The memory hierarchy built from one MemorySystemConfig (data that names no unit), on its own:
// each client's L1 is its child (model/memory/client_caches.h), a shared L2 and its crossbar are
// `<name>.l2` and `<name>.icnt`, a private L2 is its client's own; clients of any type share an L2
// when the data says so; the memory crossbar and the TLM-2.0 port are `memory.icnt` and
// `memory.port`, with the writers the data names. Timing by the documented rule (a miss costs its
// tag check plus the level below's delivery): an L1 miss that hits a shared L2 costs both hit
// latencies, a cold line adds the memory's. Every statistic registers once under its block's
// name. One simulation for the file.
#include "model/memory/memory_system.h"

#include "examples/tlm_memory/fixed_latency_memory.h"
#include "model/memory/client_caches.h"
#include "model/sim/calendar.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

namespace rtsim::model {
namespace {

constexpr Tick kCycle = 1000;
constexpr uint64_t kL1Hit = 1, kL2Hit = 4, kMemory = 20;  // cycles; distinct, so a mix-up shows

// A client that owns its caches (as a RayUnit does), reaches below through its port, and records
// the fills it is told of.
class FakeClient : public sc_core::sc_module, public FillListener {
 public:
  FakeClient(sc_core::sc_module_name name, const TypeMemoryConfig& cfg, bool private_l2,
             const char* type)
      : sc_core::sc_module(name), caches(cfg, private_l2, Clock(), this, type) {}
  void end_of_elaboration() override { caches.connect_below(); }
  void on_fill(uint64_t line, uint64_t, Tick when) override { fills.push_back({line, when}); }
  Cache& l1() { return caches.l1(); }
  ClientCaches caches;
  sc_core::sc_port<LineSource>& mem_side = caches.mem_side;
  std::vector<std::pair<uint64_t, Tick>> fills;
};

TypeMemoryConfig caches() {
  TypeMemoryConfig t;
  t.l1.hit_latency = uint32_t(kL1Hit);
  t.l1.ports = 0;
  t.l2.hit_latency = uint32_t(kL2Hit);
  t.l2.ports = 0;
  t.link = {0, 0, 0};
  return t;
}

// Two clients "a" on a shared L2 `a`; a client "b" with a private L2 (L2 1, named after it,
// `b0`); clients "c" and "d" on a shared L2 `c`; two writers.
MemorySystemConfig config() {
  MemorySystemConfig c;
  const TypeMemoryConfig t = caches();
  c.l2s.push_back({"a", t.l2, t.link, {"a", "a"}});
  c.l2s.push_back({"b0", t.l2, t.link, {}});
  c.l2s.push_back({"c", t.l2, t.link, {"c", "d"}});
  c.writers = {"w0", "w1"};
  c.memory_link = {0, 0, 0};
  c.dram = dram_preset("gddr3-gt200-1ghz");  // its address mapping routes lines to channels
  c.dram.request_bytes = t.l2.line_bytes;
  return c;
}

class Bench : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(Bench);
  explicit Bench(sc_core::sc_module_name name)
      : sc_core::sc_module(name),
        calendar("calendar"),
        memory(config(), Clock(), calendar),
        ram("ram", std::vector<uint8_t>(1 << 16, 0x5a),
            // kMemory - 0.5 ns: the port takes the response at the next edge, kMemory cycles on
            sc_core::sc_time(double(kMemory) - 0.5, sc_core::SC_NS)),
        a0("a0", caches(), false, "a"),
        a1("a1", caches(), false, "a"),
        b0("b0", caches(), true, "b"),
        c0("c0", caches(), false, "c"),
        d0("d0", caches(), false, "d") {
    memory.interconnect().port().socket.bind(ram.socket);
    a0.mem_side.bind(memory.client_port(0, 0));
    a1.mem_side.bind(memory.client_port(0, 1));
    b0.mem_side.bind(memory.memory_port(1));
    c0.mem_side.bind(memory.client_port(2, 0));
    d0.mem_side.bind(memory.client_port(2, 1));
    SC_THREAD(run);
  }
  Calendar calendar;
  MemorySystem memory;
  example::FixedLatencyMemory ram;
  FakeClient a0, a1, b0, c0, d0;
  Tick a1_delivery = 0, d_delivery = 0;

 private:
  void run() {
    // a0 brings line 0 into L2 `a`; 100 cycles later a1 misses its L1 and hits there.
    a0.l1().fetch_line(0, 0, &a0, 0);
    wait(sc_core::sc_time::from_value(100 * kCycle));
    a1_delivery = a1.l1().fetch_line(0, 100 * kCycle, &a1, 0);
    // c0's L1 brings line 64 into L2 `c`; then d0's L1 hits there.
    c0.l1().fetch_line(64, 100 * kCycle, &c0, 0);
    b0.l1().fetch_line(128, 100 * kCycle, &b0, 0);
    wait(sc_core::sc_time::from_value(100 * kCycle));
    d_delivery = d0.l1().fetch_line(64, 200 * kCycle, &d0, 0);
  }
};

Bench& run() {
  static Bench* b = [] {
    sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
    auto* bench = new Bench("bench");
    test::simulate();
    return bench;
  }();
  return *b;
}

std::string path(const char* name) { return std::string("bench.") + name; }

TEST(MemorySystem, NamesEachBlockWhereItSits) {
  run();
  for (const char* name : {"a.l2", "a.icnt", "a0.l1", "a1.l1", "b0.l1", "b0.l2", "b0.icnt", "c.l2",
                           "c.icnt", "c0.l1", "d0.l1", "a0.mem_side", "b0.mem_side", "memory.icnt",
                           "memory.port", "memory.writer0", "memory.writer1"})
    EXPECT_NE(sc_core::sc_find_object(path(name).c_str()), nullptr) << name;
  // A private L2 is its client's: no module of the memory system holds it.
  for (const char* name : {"b.l2", "b0.l2.l2", "c0.l2", "d0.l2"})
    EXPECT_EQ(sc_core::sc_find_object(path(name).c_str()), nullptr) << name;
}

TEST(MemorySystem, AColdLineCostsBothTagChecksAndTheMemory) {
  Bench& b = run();
  ASSERT_EQ(b.a0.fills.size(), 1u);
  EXPECT_EQ(b.a0.fills[0].second, (kL1Hit + kL2Hit + kMemory) * kCycle);
  ASSERT_EQ(b.b0.fills.size(), 1u) << "through its private L2";
  EXPECT_EQ(b.b0.fills[0].second, (100 + kL1Hit + kL2Hit + kMemory) * kCycle);
  EXPECT_EQ(b.ram.reads, 3u) << "line 0 for L2 a, 64 for L2 c, 128 for b0's L2";
}

TEST(MemorySystem, AnL1MissThatHitsTheSharedL2CostsBothHitLatencies) {
  Bench& b = run();
  EXPECT_EQ(b.a1_delivery, (100 + kL1Hit + kL2Hit) * kCycle);
  EXPECT_EQ(b.memory.interconnect().port().stats().reads, 3u);
}

TEST(MemorySystem, ClientsOfOneL2ShareItWhateverTheirType) {
  Bench& b = run();
  ASSERT_EQ(b.c0.fills.size(), 1u);
  EXPECT_EQ(b.c0.fills[0].second, (100 + kL1Hit + kL2Hit + kMemory) * kCycle);
  EXPECT_EQ(b.d_delivery, (200 + kL1Hit + kL2Hit) * kCycle) << "a hit in L2 c";
  StatsRegistry r;
  b.memory.register_stats(r, b, nullptr);
  b.d0.caches.register_stats(r, b, nullptr);
  EXPECT_EQ(r.value("c.l2.accesses"), 2.0);
  EXPECT_EQ(r.value("c.l2.hits"), 1.0);
  EXPECT_EQ(r.value("d0.l1.misses"), 1.0);
}

TEST(MemorySystem, RegistersItsLevelsOnceAndClientsTheirOwn) {
  Bench& b = run();
  StatsRegistry r;
  const Tick end = 300 * kCycle;
  ASSERT_NO_THROW(b.memory.register_stats(r, b, &end));
  EXPECT_TRUE(r.has("a.l2.accesses"));
  EXPECT_FALSE(r.has("a0.l1.accesses")) << "a client's L1 is its own to register";
  EXPECT_FALSE(r.has("b0.l2.accesses"));
  for (FakeClient* c : {&b.a0, &b.a1, &b.b0}) ASSERT_NO_THROW(c->caches.register_stats(r, b, &end));
  EXPECT_TRUE(r.has("b0.l2.accesses"));
  EXPECT_TRUE(r.has("b0.icnt.request.packets"));
  register_cache_totals(r, "a.l1", {&b.a0.l1(), &b.a1.l1()});
  EXPECT_EQ(r.value("a.l1.accesses"), 2.0) << "the total over a0.l1 and a1.l1";
  EXPECT_EQ(r.value("a0.l1.accesses") + r.value("a1.l1.accesses"), 2.0);
  EXPECT_EQ(r.value("a.l2.misses"), 1.0);
  EXPECT_TRUE(r.has("memory.port.reads"));
  EXPECT_TRUE(r.has("memory.icnt.request.packets"));
}

}  // namespace
}  // namespace rtsim::model
