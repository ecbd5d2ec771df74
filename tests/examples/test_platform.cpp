// examples/platform: a driver programs the accelerator through its registers, twice, with two
// cameras, over one LT memory behind a router, and checks the hit records it reads back against
// the reference tracer. Each frame must come back whole (no wrong record) and in order: the
// second starts after the first's interrupt. The hardware is a file of configs/ (the package's
// when installed: scripts/package-test.sh), the memory sized by memory_layout().
#include "tests/examples/run_example.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <string>
#include <vector>

namespace rtsim {
namespace {

using test::run_example;

// The first line names the hardware file and the memory's size; a frame per line follows.
void expect_two_good_frames(std::vector<nlohmann::json> frames, uint64_t pixels) {
  ASSERT_EQ(frames.size(), 3u);
  const nlohmann::json platform = frames.front();
  frames.erase(frames.begin());
  EXPECT_NE(platform["hw"].get<std::string>().find("configs/hw/tni-paper.yaml"), std::string::npos);
  // The image, then a 64-byte record per pixel and level (the paper's machine: one reflection)
  EXPECT_GT(platform["memory_bytes"].get<uint64_t>(), pixels * 2 * 64);
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

// A hardware file the loader refuses: one error naming it, exit 2, no frame.
TEST(PlatformExample, ABadHardwareFileIsOneErrorAndExitTwo) {
  const test::RunResult r =
      test::run_command(std::string(RTSIM_EXAMPLE_BINARY) + " city 64 36 /nonexistent/hw.yaml");
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("/nonexistent/hw.yaml"), std::string::npos) << r.err;
  EXPECT_EQ(r.out.find("wrong_records"), std::string::npos);
}

}  // namespace
}  // namespace rtsim
