// The router on its own: a ray handed back goes to the TRV unit that owns its slot, a finished ray
// to the shading unit that serves its owner (TRV unit i -> shading unit i x shading / trv), and a
// retirement frees the owner's slot and the pool's and tells the phase controller, all at the
// time given (the router adds none). (One SystemC simulation per executable.)
#include "model/units/ray_router.h"

#include "model/sim/calendar.h"
#include "model/units/ray_state.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <memory>
#include <string>
#include <vector>

namespace rtsim::model {
namespace {

struct Call {
  std::string what;
  uint32_t ray;
  Tick when;
  bool operator==(const Call& o) const { return what == o.what && ray == o.ray && when == o.when; }
};

class FakeOwner : public sc_core::sc_object, public RayOwner {
 public:
  explicit FakeOwner(const char* name) : sc_core::sc_object(name) {}
  bool leaf_done(uint32_t ray, Tick when) override {
    calls.push_back({"leaf_done", ray, when});
    return true;
  }
  void reflect(uint32_t ray, Tick when) override { calls.push_back({"reflect", ray, when}); }
  void release_slot(uint32_t ray) override { calls.push_back({"release_slot", ray, 0}); }
  std::vector<Call> calls;
};

class FakePhases : public sc_core::sc_object, public RetireListener {
 public:
  explicit FakePhases(const char* name) : sc_core::sc_object(name) {}
  void retired(RayType type, Tick when) override { calls.push_back({type, when}); }
  std::vector<std::pair<RayType, Tick>> calls;
};

struct Bench : sc_core::sc_module {
  explicit Bench(sc_core::sc_module_name name)
      : sc_core::sc_module(name), calendar("calendar"), pool(8), router("router", context()) {
    for (int i = 0; i < 4; ++i)
      owners.push_back(std::make_unique<FakeOwner>(("trv" + std::to_string(i)).c_str()));
    for (int s = 0; s < 2; ++s)
      shading.push_back(
          std::make_unique<RayFifo>(("shading" + std::to_string(s)).c_str(), 8, nullptr));
    for (auto& o : owners) router.owners.bind(*o);
    for (auto& f : shading) router.shading.bind(*f);
    router.phases.bind(phases);
  }
  const ModelContext& context() {
    ctx.calendar = &calendar;
    ctx.pool = &pool;
    return ctx;
  }
  // A ray whose slot TRV unit `owner` holds.
  uint32_t ray(uint16_t owner) {
    const uint32_t id = pool.create(RayInfo{});
    pool[id].trv.owner = owner;
    return id;
  }
  Calendar calendar;
  RayPool pool;
  ModelContext ctx;
  RayRouter router;
  std::vector<std::unique_ptr<FakeOwner>> owners;
  std::vector<std::unique_ptr<RayFifo>> shading;
  FakePhases phases{"phases"};
};

Bench& bench() {
  static Bench* b = [] {
    sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
    auto* made = new Bench("bench");
    test::simulate();  // elaborates: the router takes what its ports are bound to
    return made;
  }();
  return *b;
}

TEST(RayRouter, HandsARayBackToTheTrvUnitThatOwnsItsSlot) {
  Bench& b = bench();
  const uint32_t a = b.ray(3), c = b.ray(1);
  EXPECT_TRUE(b.router.leaf_done(a, 700));
  b.router.reflect(c, 900);
  EXPECT_EQ(b.owners[3]->calls, (std::vector<Call>{{"leaf_done", a, 700}}));
  EXPECT_EQ(b.owners[1]->calls, (std::vector<Call>{{"reflect", c, 900}}));
  EXPECT_TRUE(b.owners[0]->calls.empty());
  EXPECT_TRUE(b.owners[2]->calls.empty());
}

TEST(RayRouter, SendsAFinishedRayToTheShadingUnitOfItsOwner) {
  Bench& b = bench();
  // 4 TRV units, 2 shading units: TRV 0 and 1 finish in shading 0, TRV 2 and 3 in shading 1.
  const uint32_t r0 = b.ray(1), r1 = b.ray(2);
  ASSERT_TRUE(b.router.push(r0, 1200, 1000));
  ASSERT_TRUE(b.router.push(r1, 1300, 1000));
  ASSERT_EQ(b.shading[0]->size(), 1u);
  ASSERT_EQ(b.shading[1]->size(), 1u);
  EXPECT_EQ(b.shading[0]->head_ready(), 1200u);
  EXPECT_EQ(b.shading[0]->pop(2000), r0);
  EXPECT_EQ(b.shading[1]->pop(2000), r1);
}

TEST(RayRouter, RetiringFreesBothSlotsAndTellsThePhases) {
  Bench& b = bench();
  const uint32_t in_flight = b.pool.in_flight();
  const uint32_t r = b.ray(2);
  b.router.retire(r, RayType::kShadow, 5000);
  EXPECT_EQ(b.owners[2]->calls.back(), (Call{"release_slot", r, 0}));
  EXPECT_EQ(b.pool.in_flight(), in_flight);
  ASSERT_FALSE(b.phases.calls.empty());
  EXPECT_EQ(b.phases.calls.back(), (std::pair<RayType, Tick>{RayType::kShadow, 5000}));
}

}  // namespace
}  // namespace rtsim::model
