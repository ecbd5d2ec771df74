// The phase controller on its own, its ports bound to fakes of the ray generator and the shadow
// culling unit, told of retirements by a thread as the router would tell it: in two phases the
// culling unit's scan starts once, when the last pixel's chain of rays (a primary ray, or the
// reflection it turned into) has retired, at that retirement's time; in one phase the culling
// unit is told that no more hits come. A freed ray slot wakes the generator while it has rays to
// issue, and the culling unit when it may be waiting for one. The frame is finished when every
// shadow ray the culling unit emitted has retired. One simulation for the file.
#include "model/units/phase_controller.h"

#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <vector>

namespace rtsim::model {
namespace {

constexpr Tick kCycle = 1000;

class FakeGenerator : public sc_core::sc_object, public PrimaryRays {
 public:
  explicit FakeGenerator(const char* name) : sc_core::sc_object(name) {}
  bool finished() const override { return all_issued; }
  uint64_t issued() const override { return 3; }
  void slot_freed(Tick now) override { woken.push_back(now); }
  bool all_issued = false;
  std::vector<Tick> woken;
};

class FakeCulling : public sc_core::sc_object, public ShadowRays {
 public:
  explicit FakeCulling(const char* name) : sc_core::sc_object(name) {}
  void scan_all(Tick now) override { scans.push_back(now); }
  void close(Tick now) override { closes.push_back(now); }
  void slot_freed(Tick now) override { woken.push_back(now); }
  bool finished() const override { return done; }
  uint64_t generated() const override { return 2; }
  std::vector<Tick> scans, closes, woken;
  bool done = false;
};

struct Controller {
  Controller(const std::string& name, Schedule schedule, Calendar& calendar)
      : phases(name.c_str(), schedule, calendar),
        generator((name + "_generator").c_str()),
        culling((name + "_culling").c_str()) {
    phases.primaries.bind(generator);
    phases.shadows.bind(culling);
  }
  PhaseController phases;
  FakeGenerator generator;
  FakeCulling culling;
  std::vector<bool> finished;  // after each shadow retirement
};

class Driver : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(Driver);
  explicit Driver(sc_core::sc_module_name name)
      : sc_core::sc_module(name),
        calendar("calendar"),
        two("two_phase", Schedule::kTwoPhase, calendar),
        one("one_phase", Schedule::kOnePhase, calendar) {
    SC_THREAD(run);
  }
  Calendar calendar;
  Controller two, one;

 private:
  void at(uint64_t cycle) {
    wait(sc_core::sc_time::from_value(cycle * kCycle) - sc_core::sc_time_stamp());
  }
  void run() {
    for (Controller* c : {&two, &one})
      c->phases.retirements->retired(RayType::kPrimary, 12 * kCycle);
    at(10);
    for (Controller* c : {&two, &one}) {
      c->generator.all_issued = true;
      c->phases.retirements->retired(RayType::kReflection, 25 * kCycle);
    }
    at(30);
    for (Controller* c : {&two, &one})
      c->phases.retirements->retired(RayType::kPrimary, 35 * kCycle);
    at(40);
    for (Controller* c : {&two, &one}) {
      c->phases.retirements->retired(RayType::kShadow, 50 * kCycle);
      c->finished.push_back(c->phases.finished());
      c->culling.done = true;
      c->phases.retirements->retired(RayType::kShadow, 45 * kCycle);
      c->finished.push_back(c->phases.finished());
    }
  }
};

Driver& run() {
  static Driver* d = [] {
    auto* driver = new Driver("driver");
    test::simulate();
    return driver;
  }();
  return *d;
}

TEST(PhaseController, TwoPhasesStartTheScanOnceWhenTheLastChainOfRaysRetires) {
  Controller& c = run().two;
  // The third chain ended at cycle 30 with a retirement at 35: the scan starts then, once.
  EXPECT_EQ(c.culling.scans, (std::vector<Tick>{35 * kCycle}));
  EXPECT_TRUE(c.culling.closes.empty());
  EXPECT_EQ(c.phases.primaries_retired(), 3u) << "the reflection ended its pixel's chain";
  EXPECT_EQ(c.phases.primary_end(), 35 * kCycle);
  // Shadow retirements wake the culling unit (a slot for its next ray); primary ones do not.
  EXPECT_EQ(c.culling.woken, (std::vector<Tick>{40 * kCycle, 40 * kCycle}));
}

TEST(PhaseController, OnePhaseClosesTheCullingUnitsIntakeAndWakesItOnEveryRetirement) {
  Controller& c = run().one;
  EXPECT_TRUE(c.culling.scans.empty());
  EXPECT_EQ(c.culling.closes, (std::vector<Tick>{30 * kCycle}));
  // Every retirement frees a slot it may be waiting for; a shadow one wakes it once more.
  EXPECT_EQ(c.culling.woken.size(), 3u + 2u * 2u);
}

TEST(PhaseController, AFreedSlotWakesTheGeneratorWhileItHasRaysToIssue) {
  // Only the first retirement, at cycle 0, came before every primary ray was issued.
  for (Controller* c : {&run().two, &run().one})
    EXPECT_EQ(c->generator.woken, (std::vector<Tick>{0}));
}

TEST(PhaseController, TheFrameIsFinishedWhenEveryEmittedShadowRayHasRetired) {
  for (Controller* c : {&run().two, &run().one}) {
    EXPECT_EQ(c->finished, (std::vector<bool>{false, true}));
    EXPECT_EQ(c->phases.shadows_retired(), 2u);
    EXPECT_EQ(c->phases.end(), 50 * kCycle) << "the latest retirement, not the last told";
  }
}

}  // namespace
}  // namespace rtsim::model
