// The memory hierarchy built from one MemorySystemConfig, on its own: each unit's L1 is its child
// (built in the unit's constructor), a type's shared L2 and crossbar are `<type>.l2` and
// `<type>.icnt`, a private L2 is the unit's own; the shading L1s and the culling unit's own L1 sit
// on the IST's L2; the memory crossbar and the TLM-2.0 port are `memory.icnt` and `memory.port`,
// with one frame-buffer writer per shading unit. Timing by the documented rule (a miss costs its
// tag check plus the level below's delivery): an L1 miss that hits a shared L2 costs both hit
// latencies, a cold line adds the memory's. Every statistic registers once under its block's
// name. One simulation for the file.
#include "model/memory/memory_system.h"

#include "examples/tlm_memory/fixed_latency_memory.h"
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

// A unit that owns its L1 (as a RayUnit does) and records the fills it is told of.
class FakeUnit : public sc_core::sc_module, public FillListener {
 public:
  FakeUnit(sc_core::sc_module_name name, MemorySystem& m, MemorySystem::Type type, uint32_t index)
      : sc_core::sc_module(name), memory(m.build_unit(type, index, this)) {}
  void on_fill(uint64_t line, uint64_t, Tick when) override { fills.push_back({line, when}); }
  Cache& l1() { return *memory->l1; }
  std::unique_ptr<UnitMemory> memory;
  std::vector<std::pair<uint64_t, Tick>> fills;
};

MemorySystemConfig config() {
  MemorySystemConfig c;
  for (TypeMemoryConfig* t : {&c.trv, &c.list, &c.ist, &c.shading}) {
    t->count = 1;
    t->l1.hit_latency = uint32_t(kL1Hit);
    t->l1.ports = 0;
    t->l2.hit_latency = uint32_t(kL2Hit);
    t->l2.ports = 0;
    t->link = {0, 0, 0};
  }
  c.trv.count = 2;
  c.list.l2_sharing = L2Sharing::kUnit;
  c.culling_l1 = true;
  c.memory_link = {0, 0, 0};
  c.dram = dram_preset("gddr3-gt200-1ghz");  // its address mapping routes lines to channels
  c.dram.request_bytes = c.trv.l2.line_bytes;
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
        trv0("trv0", memory, MemorySystem::kTrv, 0),
        trv1("trv1", memory, MemorySystem::kTrv, 1),
        list0("list0", memory, MemorySystem::kList, 0),
        ist0("ist0", memory, MemorySystem::kIst, 0),
        shading0("shading0", memory, MemorySystem::kShading, 0),
        culling("culling", memory, MemorySystem::kCulling, 0) {
    memory.interconnect().port().socket.bind(ram.socket);
    SC_THREAD(run);
  }
  Calendar calendar;
  MemorySystem memory;
  example::FixedLatencyMemory ram;
  FakeUnit trv0, trv1, list0, ist0, shading0, culling;
  Tick trv1_delivery = 0, shading_delivery = 0, culling_delivery = 0;

 private:
  void run() {
    // trv0 brings line 0 into the TRV L2; 100 cycles later trv1 misses its L1 and hits there.
    trv0.l1().fetch_line(0, 0, &trv0, 0);
    wait(sc_core::sc_time::from_value(100 * kCycle));
    trv1_delivery = trv1.l1().fetch_line(0, 100 * kCycle, &trv1, 0);
    // The shading unit's L1 brings line 64 into the IST L2; then the culling unit's L1 hits there.
    shading0.l1().fetch_line(64, 100 * kCycle, &shading0, 0);
    wait(sc_core::sc_time::from_value(100 * kCycle));
    culling_delivery = culling.l1().fetch_line(64, 200 * kCycle, &culling, 0);
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
  for (const char* name : {"trv.l2", "trv.icnt", "trv0.l1", "trv1.l1", "list0.l1", "list0.l2",
                           "list0.icnt", "ist.l2", "ist.icnt", "ist0.l1", "shading0.l1",
                           "culling.l1", "memory.icnt", "memory.port", "memory.writer0"})
    EXPECT_NE(sc_core::sc_find_object(path(name).c_str()), nullptr) << name;
  // Private L2s: no shared LIST L2; the shading and culling L1s have no L2 of their own.
  for (const char* name : {"list.l2", "shading.l2", "shading0.l2", "culling.l2"})
    EXPECT_EQ(sc_core::sc_find_object(path(name).c_str()), nullptr) << name;
}

TEST(MemorySystem, AColdLineCostsBothTagChecksAndTheMemory) {
  Bench& b = run();
  ASSERT_EQ(b.trv0.fills.size(), 1u);
  EXPECT_EQ(b.trv0.fills[0].second, (kL1Hit + kL2Hit + kMemory) * kCycle);
  EXPECT_EQ(b.ram.reads, 2u) << "line 0 for the TRV L2, line 64 for the IST L2";
}

TEST(MemorySystem, AnL1MissThatHitsTheSharedL2CostsBothHitLatencies) {
  Bench& b = run();
  EXPECT_EQ(b.trv1_delivery, (100 + kL1Hit + kL2Hit) * kCycle);
  EXPECT_EQ(b.memory.interconnect().port().stats().reads, 2u);
}

TEST(MemorySystem, TheShadingAndCullingL1sSitOnTheIstL2) {
  Bench& b = run();
  ASSERT_EQ(b.shading0.fills.size(), 1u);
  EXPECT_EQ(b.shading0.fills[0].second, (100 + kL1Hit + kL2Hit + kMemory) * kCycle);
  EXPECT_EQ(b.culling_delivery, (200 + kL1Hit + kL2Hit) * kCycle) << "a hit in the IST L2";
  StatsRegistry r;
  b.memory.register_stats(r, b, nullptr);
  EXPECT_EQ(r.value("ist.l2.accesses"), 2.0);
  EXPECT_EQ(r.value("ist.l2.hits"), 1.0);
  EXPECT_EQ(r.value("culling.l1.misses"), 1.0);
}

TEST(MemorySystem, RegistersEveryCacheOnceAndTotalsPerType) {
  Bench& b = run();
  StatsRegistry r;
  const Tick end = 300 * kCycle;
  ASSERT_NO_THROW(b.memory.register_stats(r, b, &end));
  EXPECT_EQ(r.value("trv.l1.accesses"), 2.0) << "the total over trv0.l1 and trv1.l1";
  EXPECT_EQ(r.value("trv0.l1.accesses") + r.value("trv1.l1.accesses"), 2.0);
  EXPECT_EQ(r.value("trv.l2.misses"), 1.0);
  EXPECT_TRUE(r.has("list.l2.accesses")) << "private L2s get a total per type";
  EXPECT_TRUE(r.has("list0.l2.accesses"));
  EXPECT_TRUE(r.has("memory.port.reads"));
  EXPECT_TRUE(r.has("memory.icnt.request.packets"));
}

}  // namespace
}  // namespace rtsim::model
