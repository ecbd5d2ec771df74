// LVB preprocessing time, the paper's all-pairs scan against the hierarchical walk, one core,
// in the same run. Usage:
//   bench_lvb [SCENE.yaml ...] [--repeat N] [--bounds cell|geometry] [--self-occlusion test|ignore]
//             [--scene-root DIR]
// Without scene files: the kitchen, robots and bunny setups.
#include "kernels/lvb.h"
#include "testbench/run/pipeline.h"

#include "bench/bench_util.h"

#include <fmt/format.h>

#include <algorithm>
#include <cstring>
#include <vector>

using namespace rtsim;

int main(int argc, char** argv) {
  std::vector<std::string> scenes;
  PrepareOptions prep;
  LvbParams base;
  int repeat = 3;
  for (int i = 1; i < argc; ++i) {
    auto next = [&] { return bench::option_value(argc, argv, i); };
    if (!std::strcmp(argv[i], "--repeat"))
      repeat = std::max(1, std::atoi(next()));
    else if (!std::strcmp(argv[i], "--scene-root"))
      prep.scene_root = next();
    else if (!std::strcmp(argv[i], "--bounds"))
      base.bounds = std::strcmp(next(), "geometry") ? LvbBounds::kCell : LvbBounds::kGeometry;
    else if (!std::strcmp(argv[i], "--self-occlusion"))
      base.self_occlusion =
          std::strcmp(next(), "ignore") ? LvbSelfOcclusion::kTest : LvbSelfOcclusion::kIgnore;
    else
      scenes.push_back(argv[i]);
  }
  if (scenes.empty())
    for (const char* s : {"kitchen", "robots", "bunny"})
      scenes.push_back(fmt::format("{}/configs/scenes/{}.yaml", RTSIM_SOURCE_DIR, s));
  fmt::print(
      "| scene | lights | non-empty leaves | bounds | self-occlusion | paper (s) | hierarchical "
      "(s) | speed-up | same bits |\n");
  fmt::print("|---|---|---|---|---|---|---|---|---|\n");
  for (const std::string& file : scenes) {
    const PreparedScene p = prepare_scene(file, prep);
    LvbParams lp = base;
    lp.threads = 1;
    lp.shadow_offset = lvb_shadow_offset(p.tree);
    lp.origin_margin = lvb_origin_margin(p.scene, p.tree);
    std::vector<double> paper, hier;
    std::vector<uint32_t> paper_words, hier_words;
    for (int k = 0; k < repeat; ++k) {
      lp.method = LvbMethod::kHierarchical;
      LvbResult h = compute_lvb(p.scene, p.tree, lp);
      hier.push_back(h.stats.seconds);
      hier_words = std::move(h.words);
      lp.method = LvbMethod::kPaper;
      LvbResult a = compute_lvb(p.scene, p.tree, lp);
      paper.push_back(a.stats.seconds);
      paper_words = std::move(a.words);
    }
    fmt::print("| {} | {} | {} | {} | {} | {:.3f} | {:.3f} | {:.1f}x | {} |\n", p.scene.name,
               p.scene.lights.size(), p.tree.stats.leaves - p.tree.stats.empty_leaves,
               to_string(lp.bounds), to_string(lp.self_occlusion), bench::median(paper),
               bench::median(hier), bench::median(paper) / bench::median(hier),
               paper_words == hier_words ? "yes" : "NO");
  }
  fmt::print("(medians of {} runs each, one thread)\n", repeat);
  return 0;
}
