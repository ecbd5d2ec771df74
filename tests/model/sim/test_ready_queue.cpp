// The ready queue pops in (time, ray) order whatever the order of pushes, through its growth and
// its wrap-around: compared with a sorted multiset on random interleavings.
#include "model/sim/ready_queue.h"

#include <gtest/gtest.h>

#include <random>
#include <set>
#include <utility>

namespace rtsim::model {
namespace {

TEST(ReadyQueue, PopsInTimeThenRayOrder) {
  std::mt19937_64 rng(11);
  for (int round = 0; round < 200; ++round) {
    ReadyQueue q;
    std::set<std::pair<Tick, uint32_t>> ref;
    uint32_t next_ray = 0;
    Tick now = 0;
    const int ops = 1 + int(rng() % 400);
    for (int k = 0; k < ops; ++k) {
      // Mostly pushes due later than all (an operation issued), some before the head (a ray
      // admitted) or in between (a fill), and pops that let the ring wrap around.
      const uint64_t kind = rng() % 8;
      if (kind < 5) {
        const Tick when = kind == 0 ? now : now + rng() % (kind < 3 ? 4 : 40);
        q.push(when, next_ray);
        ref.insert({when, next_ray});
        ++next_ray;
      } else if (!ref.empty()) {
        ASSERT_EQ(q.next_time(), ref.begin()->first);
        ASSERT_EQ(q.pop(), ref.begin()->second);
        now = ref.begin()->first;
        ref.erase(ref.begin());
      }
      ASSERT_EQ(q.size(), ref.size());
    }
    for (; !ref.empty(); ref.erase(ref.begin())) ASSERT_EQ(q.pop(), ref.begin()->second);
    EXPECT_TRUE(q.empty());
    EXPECT_EQ(q.next_time(), kUnknown);
  }
}

TEST(ReadyQueue, EqualTimesPopByRay) {
  ReadyQueue q;
  for (uint32_t r : {7u, 3u, 40u, 1u, 3000u, 2u}) q.push(100, r);
  q.push(99, 9);
  EXPECT_EQ(q.pop(), 9u);
  for (uint32_t r : {1u, 2u, 3u, 7u, 40u, 3000u}) EXPECT_EQ(q.pop(), r);
}

}  // namespace
}  // namespace rtsim::model
