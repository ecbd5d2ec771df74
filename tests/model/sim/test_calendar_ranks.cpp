// The same-time order is the declared ranks', not the order blocks were added in: clients added in
// reverse of their ranks act in rank order at every time they share, and a client given no rank
// acts after the ranked ones. (One SystemC simulation per executable.)
#include "model/sim/calendar.h"

#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <utility>
#include <vector>

namespace rtsim::model {
namespace {

constexpr Tick kCycle = 1000;
std::vector<std::pair<Tick, int>> activations;

class Probe : public Calendar::Client {
 public:
  Probe(Calendar& c, int id) : calendar_(c), id_(id) {}
  void activate() override {
    activations.push_back({calendar_.now(), id_});
    if (calendar_.now() == 0) calendar_.schedule(this, 3 * kCycle);
  }

 private:
  Calendar& calendar_;
  int id_;
};

TEST(CalendarRanks, ClientsAddedInReverseActInTheDeclaredOrder) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  Calendar s("calendar");
  Probe unranked(s, 9), r2(s, 2), r1(s, 1), r0(s, 0);
  for (Probe* p : {&unranked, &r2, &r1, &r0}) s.add(p, kCycle);  // reverse of the ranks
  s.set_rank(r2, 2);
  s.set_rank(r0, 0);
  s.set_rank(r1, 1);
  for (Probe* p : {&r2, &unranked, &r0, &r1}) s.schedule(p, 0);
  test::simulate();
  const std::vector<std::pair<Tick, int>> expected = {
      {0, 0},          {0, 1},          {0, 2},          {0, 9},
      {3 * kCycle, 0}, {3 * kCycle, 1}, {3 * kCycle, 2}, {3 * kCycle, 9}};
  EXPECT_EQ(activations, expected);
}

}  // namespace
}  // namespace rtsim::model
