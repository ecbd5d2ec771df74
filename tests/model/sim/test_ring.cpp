// The ring behind the FIFOs and ready queues: first in, first out through growth and wrap-around,
// compared with a std::deque on random interleavings of pushes at either end, inserts from the
// tail and pops.
#include "model/sim/ring.h"

#include <gtest/gtest.h>

#include <deque>
#include <random>

namespace rtsim::model {
namespace {

TEST(Ring, MatchesADequeThroughGrowthAndWrapAround) {
  std::mt19937_64 rng(5);
  for (int round = 0; round < 100; ++round) {
    Ring<int> ring(1 + rng() % 8);
    std::deque<int> ref;
    for (int k = 0; k < 500; ++k) {
      const uint64_t kind = rng() % 6;
      if (kind < 2) {
        ring.push_back(k);
        ref.push_back(k);
      } else if (kind == 2) {
        ring.push_front(k);
        ref.push_front(k);
      } else if (kind == 3) {
        // Past the tail's values above a threshold (the ring is not sorted: the walk stops at
        // the first value from the tail that is not)
        const int x = int(rng() % 500);
        const auto less = [](int a, int b) { return a < b; };
        ring.insert_from_back(x, less);
        size_t i = ref.size();
        while (i > 0 && less(x, ref[i - 1])) --i;
        ref.insert(ref.begin() + long(i), x);
      } else if (!ref.empty()) {
        ASSERT_EQ(ring.front(), ref.front());
        ring.pop_front();
        ref.pop_front();
      }
      ASSERT_EQ(ring.size(), ref.size());
      for (size_t i = 0; i < ref.size(); ++i) ASSERT_EQ(ring[i], ref[i]);
      if (!ref.empty()) {
        ASSERT_EQ(ring.back(), ref.back());
      }
    }
  }
}

TEST(Ring, FullAtItsRoundedUpCapacityUntilItGrows) {
  Ring<int> ring(5);  // 8 slots
  for (int i = 0; i < 8; ++i) {
    EXPECT_FALSE(ring.full());
    ring.push_back(i);
  }
  EXPECT_TRUE(ring.full());
  ring.push_back(8);
  EXPECT_FALSE(ring.full());
  for (int i = 0; i <= 8; ++i, ring.pop_front()) EXPECT_EQ(ring.front(), i);
  EXPECT_TRUE(ring.empty());
}

TEST(Ring, PushesOneOfItsOwnValuesThroughGrowth) {
  // A full ring grows on the push: the value pushed must survive its old buffer.
  Ring<int> back(4), front(4);
  for (int i = 1; i <= 4; ++i) back.push_back(i), front.push_back(i);
  back.push_back(back[0]);
  front.push_front(front[3]);
  EXPECT_EQ(back.back(), 1);
  EXPECT_EQ(front.front(), 4);
  EXPECT_EQ(back.size(), 5u);
  EXPECT_EQ(front[1], 1);
}

}  // namespace
}  // namespace rtsim::model
