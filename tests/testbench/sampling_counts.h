// What the functional pass's tests share (test_sampling_features, test_sampling_shadow): a named
// statistic of a simulated frame, and the check that the pass's reads equal the model's for the
// units that walk the rays (TRV, LIST, IST).
#pragma once

#include "model/functional/functional_machine.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <cstdint>

namespace rtsim::test {

inline uint64_t stat(const nlohmann::json& stats, const char* type, const char* group,
                     const char* name) {
  return uint64_t(stats[type][group][name].get<double>());
}

inline uint64_t count(const std::array<uint64_t, model::kStages>& a, model::Stage s) {
  return a[s];
}

// TRV: a read per node fetched, leaves included, one line each. LIST: a leaf record and a
// primitive list per leaf, the lines of both. IST: a triangle per test (across two lines for half
// of them).
inline void expect_walk_reads(const model::CacheCounts& c, const nlohmann::json& s) {
  EXPECT_EQ(count(c.reads, model::kTrvStage), stat(s, "trv", "total", "node_fetches"));
  EXPECT_EQ(count(c.l1_lines, model::kTrvStage), stat(s, "trv", "l1", "accesses"));
  EXPECT_EQ(count(c.reads, model::kListStage), 2 * stat(s, "list", "total", "leaves"));
  EXPECT_EQ(count(c.l1_lines, model::kListStage), stat(s, "list", "l1", "accesses"));
  EXPECT_EQ(count(c.reads, model::kIstStage), stat(s, "ist", "total", "tests"));
  EXPECT_EQ(count(c.l1_lines, model::kIstStage), stat(s, "ist", "l1", "accesses"));
}

}  // namespace rtsim::test
