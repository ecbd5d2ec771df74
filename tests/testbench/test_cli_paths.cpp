// Path-traced frames on the model (rtsim run --integrator path): the kd-tree machine and the BVH
// machine on every node format, in two phases and in one, with culling on and off, trace the
// reference tracer's paths: the same radiance bit for bit and the same counts at every bounce;
// and a path run the machine or the settings cannot hold is one line and exit code 2, with
// nothing written.
#include "tests/test_util.h"
#include "tests/testbench/cli_util.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <string>

namespace rtsim::cli_test {
namespace {

std::string source(const char* file) { return (test::source_dir() / file).string(); }

// A run of `scene` with `args`; its report.
nlohmann::json run_paths(const std::string& scene, const std::string& args, const fs::path& out) {
  const RunResult r = run("run " + scene + " --integrator path --check --no-plots --quiet --out " +
                          out.string() + " " + args);
  EXPECT_EQ(r.code, 0) << args << ": " << r.err;
  return nlohmann::json::parse(slurp(out / "report.json"));
}

// The check found nothing, and the report's bounces add up to its rays and its per-light counts.
void expect_the_references_paths(const nlohmann::json& rep, bool culling, int max_depth) {
  const nlohmann::json& check = rep["reference_check"];
  EXPECT_EQ(check["mismatched_pixels"], 0);
  EXPECT_EQ(check["radiance_identical"], true);
  EXPECT_EQ(check["mismatched_bounces"], 0);
  const nlohmann::json& bounces = rep["path"]["bounces"];
  ASSERT_EQ(bounces.size(), size_t(max_depth) + 1);
  EXPECT_EQ(bounces[0]["rays"], rep["rays"]["primary"]);
  EXPECT_EQ(bounces[1]["rays"], bounces[0]["hits"]);  // no roulette before bounce 2
  uint64_t later = 0, decided = 0, culled = 0, traced = 0, per_light = 0, per_light_culled = 0;
  for (size_t b = 0; b < bounces.size(); ++b) {
    if (b > 0) later += bounces[b]["rays"].get<uint64_t>();
    EXPECT_LE(bounces[b]["hits"], bounces[b]["rays"]);
    decided += bounces[b]["shadow_rays"].get<uint64_t>();
    culled += bounces[b]["culled"].get<uint64_t>();
    traced += bounces[b]["traced"].get<uint64_t>();
    EXPECT_GT(bounces[b]["ray_cycles"].get<uint64_t>(), bounces[b]["rays"].get<uint64_t>());
  }
  for (const nlohmann::json& l : rep["per_light"]) {
    per_light += l["shadow_rays"].get<uint64_t>();
    per_light_culled += l["culled"].get<uint64_t>();
  }
  EXPECT_EQ(later,
            rep["rays"]["bounce"].get<uint64_t>() + rep["rays"]["reflection"].get<uint64_t>());
  EXPECT_EQ(decided, per_light);
  EXPECT_EQ(culled, per_light_culled);
  EXPECT_EQ(traced, rep["rays"]["shadow"].get<uint64_t>());
  EXPECT_EQ(decided, culled + traced);
  if (culling)
    EXPECT_GT(bounces[1]["culled"].get<uint64_t>(), 0u);  // bounce hits are culled too
  else
    EXPECT_EQ(culled, 0u);
}

TEST(CliPaths, EveryMachineTracesTheReferencesPaths) {
  const fs::path dir = test::temp_dir("cli_paths");
  const std::string city = source("configs/scenes/city.yaml");
  const std::string size = " --width 64 --height 36 --spp 2";
  struct Case {
    const char* name;
    std::string args;
    bool culling;
  };
  const Case cases[] = {
      {"kd-tree, two phases", "--hw " + source("configs/hw/tni-paper.yaml"), true},
      {"kd-tree, culling off", "--hw " + source("configs/hw/tni-paper.yaml") + " --lvb off", false},
      {"kd-tree, one phase",
       "--hw " + source("configs/hw/tni-paper.yaml") + " --set hw.schedule=one-phase", true},
      {"bvh2", "--hw " + source("configs/hw/bvh-tni.yaml") + " --accel bvh2", true},
      {"bvh4", "--hw " + source("configs/hw/bvh-tni.yaml") + " --accel bvh4", true},
      {"bvh8", "--hw " + source("configs/hw/bvh-tni.yaml") + " --accel bvh8", true},
      {"cwbvh8", "--hw " + source("configs/hw/bvh-tni.yaml") + " --accel cwbvh8", true},
  };
  for (const Case& c : cases) {
    SCOPED_TRACE(c.name);
    const nlohmann::json rep = run_paths(city, c.args + size, dir / "run");
    expect_the_references_paths(rep, c.culling, 3);
    EXPECT_EQ(rep["rays"]["primary"], 64 * 36 * 2);
    EXPECT_TRUE(fs::exists(dir / "run" / "radiance.npy"));
  }
  fs::remove_all(dir);
}

// An area light's samples are placed per path and bounce (path_light_key): the model's and the
// reference's shadow rays still agree, sample for sample.
TEST(CliPaths, AreaLightSamplesFollowThePathAndBounce) {
  const fs::path dir = test::temp_dir("cli_paths_area");
  write(dir / "area.yaml",
        "geometry:\n  - procedural: {kind: city, blocks: 2}\nresolution: [64, 36]\nlights:\n"
        "  from_files: false\n  add:\n"
        "    - {area: {corner: [0, 40, 0], edge1: [4, 0, 0], edge2: [0, 0, 4]}, samples: 4}\n");
  const nlohmann::json rep = run_paths(
      (dir / "area.yaml").string(),
      "--hw " + source("configs/hw/tni-paper.yaml") + " --spp 2 --max-depth 2", dir / "run");
  expect_the_references_paths(rep, true, 2);
  fs::remove_all(dir);
}

// --culled-rays: the shadow rays the model's culling unit culled are the reference tracer's, byte
// for byte (rtsim lvb writes the reference's), on every bounce.
TEST(CliPaths, TheModelCullsTheReferencesShadowRays) {
  const fs::path dir = test::temp_dir("cli_paths_culled");
  const std::string city = source("configs/scenes/city.yaml");
  const std::string frame = " --width 96 --height 54 --integrator path --spp 2 --culled-rays ";
  RunResult r = run("lvb " + city + " --out " + (dir / "lvb").string() + frame +
                    (dir / "reference.npy").string());
  ASSERT_EQ(r.code, 0) << r.err;
  r = run("run " + city + " --hw " + source("configs/hw/tni-paper.yaml") +
          " --no-plots --quiet --out " + (dir / "run").string() + frame +
          (dir / "model.npy").string());
  ASSERT_EQ(r.code, 0) << r.err;
  const std::string reference = slurp(dir / "reference.npy"), model = slurp(dir / "model.npy");
  const nlohmann::json rep = nlohmann::json::parse(slurp(dir / "run" / "report.json"));
  uint64_t culled = 0;
  for (const nlohmann::json& l : rep["per_light"]) culled += l["culled"].get<uint64_t>();
  EXPECT_GT(culled, 0u);
  EXPECT_EQ(model.size() - model.find('\n') - 1, 40 * culled);  // a record per culled ray
  EXPECT_TRUE(model == reference) << "the model's culled rays differ from the reference's";
  expect_input_error("run " + city + " --hw " + source("configs/hw/tni-paper.yaml") +
                         " --sample 0.5 --culled-rays " + (dir / "x.npy").string(),
                     {"--culled-rays", "sampled"});
  fs::remove_all(dir);
}

TEST(CliPaths, PathRunsTheMachineCannotHoldAreRefused) {
  const fs::path dir = test::temp_dir("cli_paths_bad");
  const std::string head = "run " + source("configs/scenes/city.yaml") + " --hw " +
                           source("configs/hw/tni-paper.yaml") + " --no-plots --out " +
                           (dir / "out").string() + " ";
  expect_input_error(head + "--set run.integrator=photon", {"run.integrator", "'path'"});
  expect_input_error(head + "--set run.integrator=path --set run.spp=0", {"run.spp", "[1, 65536]"});
  expect_input_error(head + "--set run.integrator=path --set run.max_depth=-2",
                     {"run.max_depth", "[0, 64]"});
  expect_input_error(head + "--integrator path --reflections 1", {"reflections", "lobes"});
  expect_input_error(head + "--integrator path --sample 0.1", {"run.sample", "Whitted"});
  // 64 paths of 4 records a pixel at 640x360: 3.5 GB of frame buffer in a 1 GiB memory.
  expect_input_error(head + "--integrator path --spp 64",
                     {"hw.dram.capacity_mib", "256 hit records", "run.spp"});
  EXPECT_FALSE(fs::exists(dir / "out" / "report.json"));
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rtsim::cli_test
