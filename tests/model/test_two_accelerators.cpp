// Two accelerators with different configurations in one simulation run side by side, each with
// its own calendar, and each gets exactly the figures it gets alone (computed in a child process,
// since SystemC elaborates once per process). Also: the module tree names every block where its
// statistics say it is.
#include "config_loader/scene_file.h"
#include "kernels/kdtree.h"
#include "kernels/memory_image.h"
#include "model/accelerator.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>
#include <systemc>

#include <sys/wait.h>
#include <unistd.h>
#include <fstream>
#include <memory>

namespace rtsim {
namespace {

constexpr int kW = 48, kH = 27;

model::AcceleratorConfig config_a() {
  model::AcceleratorConfig c;
  c.trv.count = 4;
  c.list.count = 2;
  c.ist.count = 2;
  return c;
}

model::AcceleratorConfig config_b() {
  model::AcceleratorConfig c = config_a();
  c.shading.count = 2;
  c.trv.l2_sharing = model::L2Sharing::kUnit;
  c.schedule = model::Schedule::kOnePhase;
  return c;
}

nlohmann::json figures(model::Accelerator& a) {
  const model::AcceleratorResult r = a.result();
  nlohmann::json occluded = nlohmann::json::array();
  for (const model::PixelState& px : r.frame.pixels) occluded.push_back(px.occluded);
  return {{"cycles_total", r.cycles_total},
          {"cycles_primary", r.cycles_primary},
          {"stats", r.stats},
          {"shadow_culled", r.shadow_culled},
          {"occluded", occluded}};
}

struct Fixture {
  Fixture() {
    const SceneSetup s =
        load_scene_file((test::source_dir() / "configs/scenes/city.yaml").string());
    scene = s.scene;
    tree = build_kdtree(scene.triangles, s.kdtree);
    image = std::make_unique<MemoryImage>(scene, tree);
  }
  model::FrameJob job() const { return {scene.camera, kW, kH}; }
  Scene scene;
  KdTree tree;
  std::unique_ptr<MemoryImage> image;
};

// The figures of `config` simulated alone, in a child process.
nlohmann::json alone(const Fixture& f, const model::AcceleratorConfig& config) {
  const std::filesystem::path out = test::temp_dir("alone") / "figures.json";
  const pid_t pid = fork();
  if (pid == 0) {
    sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
    model::Accelerator a("top", config, *f.image, f.job());
    sc_core::sc_start();
    std::ofstream(out) << figures(a).dump();
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  return nlohmann::json::parse(test::slurp(out));
}

TEST(TwoAccelerators, SideBySideEachHasTheFiguresItHasAlone) {
  const Fixture f;
  const nlohmann::json a_alone = alone(f, config_a()), b_alone = alone(f, config_b());

  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  model::Accelerator a("a", config_a(), *f.image, f.job());
  model::Accelerator b("b", config_b(), *f.image, f.job());
  // Names: hierarchical name = the statistic's prefix, below each accelerator.
  for (const char* name : {"a.trv3.l1", "a.trv.l2", "a.trv3.in", "a.memory.icnt", "a.memory.port",
                           "a.dram", "a.calendar", "b.trv3.l2", "b.shading1.l1", "b.lvb_updater"})
    EXPECT_NE(sc_core::sc_find_object(name), nullptr) << name;
  EXPECT_EQ(sc_core::sc_find_object("b.trv.l2"), nullptr) << "b's TRV L2s are private";
  test::simulate();
  ASSERT_TRUE(a.finished());
  ASSERT_TRUE(b.finished());
  const nlohmann::json a_side = figures(a), b_side = figures(b);
  EXPECT_EQ(a_side, a_alone);
  EXPECT_EQ(b_side, b_alone);
  EXPECT_NE(a_side["cycles_total"], b_side["cycles_total"]) << "two configurations, two figures";
  EXPECT_TRUE(a_side["stats"]["trv3"]["l1"].contains("hits"));
  EXPECT_TRUE(b_side["stats"]["trv3"]["l2"].contains("hits"));
}

}  // namespace
}  // namespace rtsim
