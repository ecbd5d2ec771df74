// examples/platform: a driver programs the accelerator through its registers, twice, with two
// cameras, over one LT memory behind a router, and checks the hit records it reads back against
// the reference tracer. Each frame must come back whole (no wrong record) and in order: the
// second starts after the first's interrupt.
#include "tests/examples/run_example.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace rtsim {
namespace {

using test::run_example;

void expect_two_good_frames(const std::vector<nlohmann::json>& frames, uint64_t pixels) {
  ASSERT_EQ(frames.size(), 2u);
  for (const nlohmann::json& f : frames) {
    EXPECT_EQ(f["wrong_records"], 0) << f.dump();
    EXPECT_EQ(f["pixels"], pixels);
    EXPECT_GT(f["hits"].get<uint64_t>(), 0u);
    // The interrupt comes after the frame's cycles (1 GHz) and the records' writes.
    EXPECT_GE(f["interrupt_ns"].get<double>(),
              f["started_ns"].get<double>() + f["cycles"].get<double>());
  }
  EXPECT_GT(frames[1]["started_ns"].get<double>(), frames[0]["interrupt_ns"].get<double>());
  EXPECT_NE(frames[0]["cycles"], frames[1]["cycles"]);  // another camera, another frame
}

TEST(PlatformExample, TwoFramesOfTheCityComeBackWithNoWrongRecord) {
  expect_two_good_frames(run_example("city 64 36"), 64 * 36);
}

TEST(PlatformExample, TwoFramesOfTheKitchenComeBackWithNoWrongRecord) {
  RTSIM_REQUIRE_SHARED_SCENES();
  const std::string kitchen = (test::shared_scenes() / "bart/kitchen/kitchen.aff").string();
  expect_two_good_frames(run_example(kitchen + " 160 90"), 160 * 90);
}

}  // namespace
}  // namespace rtsim
