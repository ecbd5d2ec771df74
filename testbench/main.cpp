// rtsim: the command-line front end. Input errors print one line and exit with code 2.
#include "common/error.h"
#include "testbench/commands.h"

#include <CLI/CLI.hpp>
#include <fmt/format.h>

#include <cstdio>
#include <exception>
#include <filesystem>

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

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    const int code = app.exit(e);
    return code == 0 ? 0 : 2;
  }
  try {
    if (*render_cmd) return rtsim::run_render(render);
    if (*info_cmd) return rtsim::run_info(info);
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
