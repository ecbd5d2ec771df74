// Memory before the work (testbench/run/resources.h): a frame too big for the process's limits is
// one error naming the estimate and the limit, exit 2, before the frame's state is allocated.
#include "testbench/run/resources.h"

#include "common/error.h"
#include "kernels/lvb.h"
#include "tests/test_util.h"
#include "tests/testbench/cli_util.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>

namespace rtsim {
namespace {

Scene frame(int width, int height, size_t lights = 2) {
  Scene s;
  s.width = width;
  s.height = height;
  s.lights.resize(lights);
  return s;
}

TEST(Resources, TheEstimateGrowsWithThePixelsAndNamesItsParts) {
  const model::AcceleratorConfig hw;
  const MemoryNeed small = run_memory_need(hw, frame(160, 90), false);
  const MemoryNeed big = run_memory_need(hw, frame(16384, 16384), false);
  EXPECT_EQ(big.what, "a 16384x16384 frame");
  EXPECT_GT(big.total(), 6'000'000'000u);
  // Per pixel the same: the ratio of the totals is the ratio of the pixels.
  EXPECT_EQ(big.total() / (16384ull * 16384), small.total() / (160ull * 90));
  EXPECT_GT(run_memory_need(hw, frame(160, 90), true).total(), small.total());  // --check
  EXPECT_GT(render_memory_need(frame(16384, 16384)).total(), 4'000'000'000u);
}

TEST(Resources, ANeedAboveTheRoomIsAnInputErrorNamingTheEstimateAndTheLimit) {
  const model::AcceleratorConfig hw;
  const MemoryRoom room{5000000000, "the address-space limit (ulimit -v) (1.0 GB of 6.0 GB)"};
  check_memory(run_memory_need(hw, frame(1920, 1080), false), room);  // fits: no throw
  try {
    check_memory(run_memory_need(hw, frame(16384, 16384), false), room);
    FAIL() << "no error";
  } catch (const InputError& e) {
    const std::string m = e.what();
    for (const char* part : {"a 16384x16384 frame needs about", "the frame's per-pixel state",
                             "address-space limit", "leaves 5.0 GB", "lower the resolution"})
      EXPECT_NE(m.find(part), std::string::npos) << part << " not in: " << m;
  }
}

// The run's peak: what the prepared scene holds plus the larger of the LVB computation's working
// set (freed before the frame) and the frame's state, or the build's peak if that was higher.
TEST(Resources, ThePeakAddsTheHeldStructuresToTheLargerPhase) {
  PreparedScene p;
  p.scene = frame(64, 32);
  p.scene.triangles.resize(1000);
  p.tree.nodes.resize(3000);
  p.tree.leaves.resize(1500);
  p.tree.prims.resize(4000);
  const model::AcceleratorConfig hw;
  MemoryNeed need = run_memory_need(hw, p.scene, false);
  const uint64_t frame_bytes = need.total();
  add_scene_memory(p, true, true, 1000000, need);
  ASSERT_EQ(need.transient.size(), 1u);
  const uint64_t lvb = need.transient[0].second;
  EXPECT_EQ(lvb, lvb_working_bytes(1000, 1500, 4000, true));
  EXPECT_LT(lvb_working_bytes(1000, 1500, 4000, false), lvb);  // exact mode keeps origin boxes
  uint64_t held = 0;
  for (const auto& part : need.held) held += part.second;
  EXPECT_GE(held, 1000000 + 1000 * sizeof(Triangle) + 4000 * sizeof(uint32_t));
  EXPECT_EQ(need.total(), std::max(lvb, frame_bytes));
  EXPECT_EQ(need.peak(), std::max(held + need.total(), need.peak_so_far));
  need.peak_so_far = need.peak() + 1;  // a build that peaked higher than the rest of the run
  EXPECT_EQ(need.peak(), need.peak_so_far);
}

// A sweep's points running at once share the machine: each counts on its share of the available
// memory (the sweep sets RTSIM_POINTS_AT_ONCE for them), and the limit says so.
TEST(Resources, SweepPointsRunningAtOnceEachCountOnTheirShare) {
  unsetenv(kPointsAtOnceEnv);
  const MemoryRoom alone = memory_room();
  setenv(kPointsAtOnceEnv, "4", 1);
  const MemoryRoom shared = memory_room();
  unsetenv(kPointsAtOnceEnv);
  if (alone.limit.find("available memory") == std::string::npos)
    GTEST_SKIP() << "a per-process limit binds here: " << alone.limit;
  // MemAvailable moves between the two reads: a tenth either way
  EXPECT_LT(double(shared.bytes), 0.275 * double(alone.bytes));
  EXPECT_GT(double(shared.bytes), 0.225 * double(alone.bytes));
  EXPECT_NE(shared.limit.find("shared by 4 sweep points at once (--jobs)"), std::string::npos)
      << shared.limit;
}

// The whole command under an address-space limit (not under AddressSanitizer, whose shadow
// memory needs more address space than any such limit allows).
TEST(Resources, ACityFrameTooBigForTheAddressSpaceLimitStopsBeforeTheWork) {
#if defined(__SANITIZE_ADDRESS__)
  GTEST_SKIP() << "AddressSanitizer reserves more address space than the limit";
#else
  const std::filesystem::path out = test::temp_dir("resources");
  const test::RunResult r = test::run_command(
      "bash -c 'ulimit -v 5859375 && " + std::string(RTSIM_BINARY) + " run " +
      (test::source_dir() / "configs/scenes/city.yaml").string() + " --hw " +
      (test::source_dir() / "configs/hw/tni-paper.yaml").string() +
      " --width 16384 --height 16384 --no-plots --quiet --out " + out.string() + "'");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("rtsim: error: a 16384x16384 frame needs about"), std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("the address-space limit (ulimit -v)"), std::string::npos) << r.err;
  EXPECT_FALSE(std::filesystem::exists(out / "report.json"));
  std::filesystem::remove_all(out);
#endif
}

// Past a file-size limit a write fails: one error naming the file and why, exit 2, and neither a
// partial file nor a temporary one is left (SIGXFSZ would have killed the process mid-write).
TEST(Resources, AFileSizeLimitIsOneErrorAndLeavesNoPartialFile) {
  const std::filesystem::path out = test::temp_dir("fsize");
  const test::RunResult r =
      test::run_command("bash -c 'ulimit -f 8 && " + std::string(RTSIM_BINARY) + " render " +
                        (test::source_dir() / "configs/scenes/city.yaml").string() +
                        " --width 160 --height 90 --out " + out.string() + "'");
  EXPECT_EQ(r.code, 2) << r.err;
  EXPECT_NE(r.err.find("cannot write (File too large)"), std::string::npos) << r.err;
  EXPECT_EQ(std::count(r.err.begin(), r.err.end(), '\n'), 1) << r.err;
  for (const auto& f : std::filesystem::directory_iterator(out)) {
    EXPECT_EQ(f.path().string().find(".tmp."), std::string::npos) << f.path();
    EXPECT_LE(std::filesystem::file_size(f.path()), 8u * 1024) << f.path();
    EXPECT_EQ(r.err.find(f.path().filename().string() + ":"), std::string::npos)
        << "the file the error names exists: " << f.path();
  }
  std::filesystem::remove_all(out);
}

}  // namespace
}  // namespace rtsim
