// --accel end to end: a frame rendered through any BVH format is the kd-tree's frame byte for byte,
// the reports name the structure, and a bad name is one line and exit code 2.
#include "kernels/bvh_image.h"
#include "tests/test_util.h"
#include "tests/testbench/cli_util.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <string>

namespace rtsim::cli_test {
namespace {

std::string city() { return (test::source_dir() / "configs/scenes/city.yaml").string(); }

// rtsim render of the city, small, with one mirror bounce; the output directory.
fs::path render(const std::string& accel, const fs::path& dir) {
  const fs::path out = dir / accel;
  const RunResult r = run("render " + city() + " --width 96 --height 54 --reflections 1 --accel " +
                          accel + " --out " + out.string());
  EXPECT_EQ(r.code, 0) << accel << ": " << r.err;
  return out;
}

TEST(CliAccel, RenderWithEveryBvhIsTheKdTreesFrame) {
  const fs::path dir = test::temp_dir("cli_accel_render");
  const fs::path kd = render("kdtree", dir);
  const nlohmann::json kd_json = nlohmann::json::parse(slurp(kd / "render.json"));
  ASSERT_TRUE(kd_json.contains("kdtree"));
  EXPECT_GT(kd_json["kdtree"]["nodes"].get<int>(), 0);
  // The kd-tree's report as before the BVHs: no structure name, no bvh section.
  EXPECT_FALSE(kd_json.contains("bvh"));
  EXPECT_FALSE(kd_json.contains("accel"));
  EXPECT_GT(kd_json["rays"]["reflection_hits"].get<int>(), 0) << "the mirror is in the frame";
  for (const std::string accel : {"bvh2", "bvh4", "bvh8", "cwbvh8"}) {
    SCOPED_TRACE(accel);
    const fs::path out = render(accel, dir);
    for (const char* file : {"mask.npy", "render.png", "visibility.npy"})
      EXPECT_TRUE(slurp(out / file) == slurp(kd / file)) << file << " differs from the kd-tree's";
    const nlohmann::json j = nlohmann::json::parse(slurp(out / "render.json"));
    EXPECT_EQ(j["accel"], accel);
    ASSERT_TRUE(j.contains("bvh"));
    EXPECT_GT(j["bvh"]["nodes"].get<int>(), 0);
    EXPECT_EQ(j["bvh"]["params"]["branching"], accel_branching(parse_accel(accel)));
    EXPECT_EQ(j["bvh"]["prims"].get<int>() + j["bvh"]["left_out"].get<int>(),
              j["scene"]["triangles"].get<int>());
    EXPECT_FALSE(j.contains("kdtree"));
    EXPECT_EQ(j["rays"], kd_json["rays"]) << "the same hits cast the same rays";
    EXPECT_EQ(j["per_light"], kd_json["per_light"]);
  }
  fs::remove_all(dir);
}

TEST(CliAccel, InfoNamesTheBvh) {
  const RunResult r = run("info " + city() + " --accel bvh4 --json");
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json j = nlohmann::json::parse(r.out);
  EXPECT_EQ(j["accel"], "bvh4");
  EXPECT_EQ(j["bvh"]["params"]["branching"], 4);
  EXPECT_GT(j["bvh"]["nodes"].get<int>(), 0);
  EXPECT_GT(j["bvh"]["leaves"].get<int>(), 0);
  EXPECT_FALSE(j.contains("kdtree"));
  const RunResult text = run("info " + city() + " --accel bvh8");
  ASSERT_EQ(text.code, 0) << text.err;
  EXPECT_NE(text.out.find("\nbvh8 "), std::string::npos) << text.out;
  EXPECT_EQ(text.out.find("kd-tree"), std::string::npos) << text.out;
}

TEST(CliAccel, UnknownStructureIsAnInputError) {
  const fs::path dir = test::temp_dir("cli_accel_errors");
  const std::string out = " --out " + (dir / "out").string();
  for (const char* command : {"render ", "info ", "lvb "})
    expect_input_error(command + city() + " --accel bvh16" + out, {"--accel", "bvh16"});
  expect_input_error(city_run(dir / "run", "--accel bvh16"), {"--accel", "bvh16"});
  expect_input_error("sweep " + (test::source_dir() / "configs/sweeps/ablation.yaml").string() +
                         " --accel kd" + out,
                     {"--accel", "kd"});
  expect_input_error(city_run(dir / "run", "--set run.accel=bvh9"),
                     {"run.accel", "bvh9", "'kdtree'", "'bvh8'"});
  EXPECT_FALSE(fs::exists(dir / "run")) << "nothing written";
  fs::remove_all(dir);
}

// The BVH machine renders what the reference tracer does; a kd-tree image on it is refused.
TEST(CliAccel, RunWithABvhChecksAgainstTheReferenceTracer) {
  const fs::path dir = test::temp_dir("cli_accel_run");
  RunResult r =
      run("run " + city() + " --hw " + (test::source_dir() / "configs/hw/bvh-tni.yaml").string() +
          " --accel bvh4 --width 64 --height 36 --no-plots --check --quiet --out " + dir.string());
  EXPECT_EQ(r.code, 0) << r.err;
  r = run(city_run(dir, "--accel cwbvh8 --quiet"));
  EXPECT_EQ(r.code, 2);
  EXPECT_NE(r.err.find("hw.structure"), std::string::npos) << r.err;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rtsim::cli_test
