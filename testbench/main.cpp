// rtsim: the command-line front end. Input errors print one line and exit with code 2.
#include "common/error.h"
#include "testbench/commands.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdio>
#include <exception>
#include <filesystem>
#include <map>

namespace {

void add_prepare_options(CLI::App* cmd, rtsim::PrepareOptions& p) {
  cmd->add_option("--scene-root", p.scene_root, "Directory that relative geometry paths resolve against")
      ->envname("RTSIM_SCENE_ROOT");
  cmd->add_option("--width", p.width, "Override the scene's image width")->check(CLI::Range(1, 16384));
  cmd->add_option("--height", p.height, "Override the scene's image height")->check(CLI::Range(1, 16384));
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"rtsim: a ray-tracing accelerator model with LVB shadow-ray culling"};
  app.require_subcommand(1);

  rtsim::RenderArgs render;
  CLI::App* render_cmd = app.add_subcommand("render", "Render a scene with the reference tracer");
  render_cmd->add_option("scene", render.scene, "Scene description (YAML)")->required();
  render_cmd->add_option("--out", render.out, "Output directory")->required();
  render_cmd->add_option("--threads", render.threads, "Host threads (0 = all cores)")->check(CLI::Range(0, 1024));
  render_cmd->add_option("--reflections", render.reflection_depth, "Mirror reflection depth")->check(CLI::Range(0, 16));
  add_prepare_options(render_cmd, render.prepare);

  rtsim::InfoArgs info;
  CLI::App* info_cmd = app.add_subcommand("info", "Print scene and kd-tree statistics");
  info_cmd->add_option("scene", info.scene, "Scene description (YAML)")->required();
  info_cmd->add_flag("--json", info.json, "Print JSON");
  add_prepare_options(info_cmd, info.prepare);

  rtsim::LvbArgs lvb;
  CLI::App* lvb_cmd = app.add_subcommand("lvb", "Compute the LVB words and measure culling (Tables 4 and 5)");
  lvb_cmd->add_option("scene", lvb.scene, "Scene description (YAML)")->required();
  lvb_cmd->add_option("--out", lvb.out, "Output directory")->required();
  const std::map<std::string, rtsim::LvbMethod> methods{{"paper", rtsim::LvbMethod::kPaper},
                                                        {"hierarchical", rtsim::LvbMethod::kHierarchical}};
  const std::map<std::string, rtsim::LvbBounds> bounds{{"cell", rtsim::LvbBounds::kCell},
                                                       {"geometry", rtsim::LvbBounds::kGeometry}};
  const std::map<std::string, rtsim::LvbSelfOcclusion> self{{"test", rtsim::LvbSelfOcclusion::kTest},
                                                            {"ignore", rtsim::LvbSelfOcclusion::kIgnore}};
  lvb_cmd->add_option("--method", lvb.lvb.method, "paper (all pairs) or hierarchical (kd-tree walk)")
      ->transform(CLI::CheckedTransformer(methods));
  lvb_cmd->add_option("--bounds", lvb.lvb.bounds, "cell (the paper) or geometry (clipped to the cell)")
      ->transform(CLI::CheckedTransformer(bounds));
  lvb_cmd->add_option("--self-occlusion", lvb.lvb.self_occlusion, "test (exact, never wrong) or ignore (the paper)")
      ->transform(CLI::CheckedTransformer(self));
  lvb_cmd->add_flag("--verify", lvb.verify, "Also trace culled rays and count those that were occluded");
  lvb_cmd->add_option("--threads", lvb.threads, "Host threads for tracing (0 = all cores)")->check(CLI::Range(0, 1024));
  lvb_cmd->add_option("--lvb-threads", lvb.lvb.threads, "Host threads for preprocessing")->check(CLI::Range(1, 1024));
  add_prepare_options(lvb_cmd, lvb.prepare);

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    if (*render_cmd) return rtsim::run_render(render);
    if (*info_cmd) return rtsim::run_info(info);
    if (*lvb_cmd) return rtsim::run_lvb(lvb);
  } catch (const rtsim::InputError& e) {
    fmt::print(stderr, "rtsim: error: {}\n", e.what());
    return 2;
  } catch (const std::filesystem::filesystem_error& e) {
    fmt::print(stderr, "rtsim: error: {}\n", e.what());
    return 2;
  } catch (const std::exception& e) {
    fmt::print(stderr, "rtsim: internal error: {}\n", e.what());
    return 1;
  }
  return 2;
}
