// rtsim: the command-line front end. Input errors print one line and exit with code 2.
#include "common/error.h"
#include "testbench/commands.h"
#include "testbench/hw_config.h"
#include "testbench/sweep.h"

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <systemc>

#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>

namespace {

// Where render, lvb and run write without --out: out/<scene file's stem>-<command>, relative to
// the working directory (each command names the files it wrote).
std::string default_out(const std::string& scene, const char* command) {
  return (std::filesystem::path("out") /
          fmt::format("{}-{}", std::filesystem::path(scene).stem().string(), command))
      .string();
}

void add_prepare_options(CLI::App* cmd, rtsim::PrepareOptions& p) {
  cmd->add_option("--scene-root", p.scene_root,
                  "Directory that relative geometry paths resolve against")
      ->envname("RTSIM_SCENE_ROOT");
  cmd->add_option("--width", p.width, "Override the scene's image width")
      ->check(CLI::Range(1, 16384));
  cmd->add_option("--height", p.height, "Override the scene's image height")
      ->check(CLI::Range(1, 16384));
}

}  // namespace

extern "C" int sc_main(int argc, char** argv) {
  // stdout carries reports
  sc_core::sc_report_handler::set_actions(sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
  CLI::App app{"rtsim: a ray-tracing accelerator model with LVB shadow-ray culling"};
  app.require_subcommand(1);

  rtsim::RenderArgs render;
  CLI::App* render_cmd = app.add_subcommand("render", "Render a scene with the reference tracer");
  render_cmd->add_option("scene", render.scene, "Scene description (YAML)")->required();
  render_cmd->add_option("--out", render.out, "Output directory (default: out/SCENE-render)");
  render_cmd->add_option("--threads", render.threads, "Host threads (0 = all cores)")
      ->check(CLI::Range(0, 1024));
  render_cmd->add_option("--reflections", render.reflection_depth, "Mirror reflection depth")
      ->check(CLI::Range(0, 16));
  add_prepare_options(render_cmd, render.prepare);

  rtsim::InfoArgs info;
  CLI::App* info_cmd = app.add_subcommand("info", "Print scene and kd-tree statistics");
  info_cmd->add_option("scene", info.scene, "Scene description (YAML)")->required();
  info_cmd->add_flag("--json", info.json, "Print JSON");
  add_prepare_options(info_cmd, info.prepare);

  rtsim::LvbArgs lvb;
  CLI::App* lvb_cmd =
      app.add_subcommand("lvb", "Compute the LVB words and measure culling (Tables 4 and 5)");
  lvb_cmd->add_option("scene", lvb.scene, "Scene description (YAML)")->required();
  lvb_cmd->add_option("--out", lvb.out, "Output directory (default: out/SCENE-lvb)");
  std::string method = "hierarchical", bounds = "cell", self_occlusion = "test";
  lvb_cmd->add_option("--method", method, "paper (all pairs) or hierarchical (kd-tree walk)")
      ->check(CLI::IsMember({"paper", "hierarchical"}));
  lvb_cmd->add_option("--bounds", bounds, "cell (the paper) or geometry (clipped to the cell)")
      ->check(CLI::IsMember({"cell", "geometry"}));
  lvb_cmd
      ->add_option("--self-occlusion", self_occlusion,
                   "test (exact, never wrong) or ignore (the paper)")
      ->check(CLI::IsMember({"test", "ignore"}));
  lvb_cmd->add_flag("--verify", lvb.verify,
                    "Also trace culled rays and count those that were occluded");
  lvb_cmd->add_option("--threads", lvb.threads, "Host threads for tracing (0 = all cores)")
      ->check(CLI::Range(0, 1024));
  lvb_cmd->add_option("--lvb-threads", lvb.lvb.threads, "Host threads for preprocessing")
      ->check(CLI::Range(1, 1024));
  add_prepare_options(lvb_cmd, lvb.prepare);

  rtsim::RunArgs run;
  std::string lvb_switch = "on";
  int run_width = 0, run_height = 0, run_reflections = 0;
  bool run_check = false, run_no_plots = false;
  CLI::App* run_cmd =
      app.add_subcommand("run", "Simulate a frame on the SystemC model of the accelerator");
  run_cmd->add_option("scene", run.sources.scene_file, "Scene description (YAML)");
  run_cmd->add_option("--hw", run.sources.hw_file, "Hardware configuration (YAML)");
  run_cmd->add_option("--config", run.sources.config_file,
                      "Repeat a run from its config.json (instead of SCENE --hw)");
  run_cmd
      ->add_option("--set", run.sources.set,
                   "Override a key: hw.PATH=VALUE, scene.PATH=VALUE or run.PATH=VALUE")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  run_cmd->add_option("--out", run.out,
                      "Output directory (default: out/SCENE-run; required with --config)");
  CLI::Option* lvb_opt =
      run_cmd->add_option("--lvb", lvb_switch, "LVB shadow-ray culling: on or off")
          ->check(CLI::IsMember({"on", "off"}));
  CLI::Option* check_opt =
      run_cmd->add_flag("--check", run_check,
                        "Compare every pixel with the reference tracer (exit 1 on a difference)");
  CLI::Option* refl_opt =
      run_cmd->add_option("--reflections", run_reflections, "Mirror reflection depth")
          ->check(CLI::Range(0, 8));
  CLI::Option* width_opt =
      run_cmd->add_option("--width", run_width, "Override the scene's image width")
          ->check(CLI::Range(1, 16384));
  CLI::Option* height_opt =
      run_cmd->add_option("--height", run_height, "Override the scene's image height")
          ->check(CLI::Range(1, 16384));
  CLI::Option* plots_opt = run_cmd->add_flag("--no-plots", run_no_plots, "Skip the PNG figures");
  run_cmd
      ->add_option("--scene-root", run.sources.scene_root,
                   "Directory that relative geometry paths resolve against")
      ->envname("RTSIM_SCENE_ROOT");
  run_cmd->add_flag("--quiet", run.quiet, "No progress line and no summary");
  run_cmd->add_option("--trace", run.trace_file,
                      "Write a VCD of FIFO occupancies and unit busy signals");
  run_cmd->add_option("--mem-trace", run.mem_trace_file,
                      "Write a CSV of the memory transactions at the TLM-2.0 boundary (cycle, "
                      "initiator, address, bytes, op, latency)");
  run_cmd->add_option("--trace-window", run.trace_window,
                      "Cycles START:END to trace with --trace and --mem-trace (default 0:100000)");

  rtsim::SweepArgs sweep;
  bool sweep_no_plots = false;
  CLI::App* sweep_cmd = app.add_subcommand(
      "sweep", "Run the points of a sweep file in parallel processes (resumable)");
  sweep_cmd->add_option("sweep", sweep.file, "Sweep description (YAML)");
  sweep_cmd->add_option("--out", sweep.out,
                        "Output directory (results.csv, results.json, points/, plots/)");
  sweep_cmd->add_option("--jobs", sweep.jobs, "Points run at once")->check(CLI::Range(1, 1024));
  sweep_cmd
      ->add_option("--set", sweep.set,
                   "Override a key in every point: hw.PATH=VALUE, scene.PATH=VALUE, run.PATH=VALUE")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  sweep_cmd->add_option("--emit", sweep.emit, "Write a job script and manifest instead of running")
      ->check(CLI::IsMember({"slurm"}));
  sweep_cmd->add_option("--merge", sweep.merge_dir,
                        "Gather the rows of a sweep run elsewhere into DIR/results.csv");
  sweep_cmd->add_option("--point", sweep.point, "Run one point of DIR/manifest.json (array tasks)")
      ->check(CLI::Range(0, 1 << 30));
  sweep_cmd->add_flag("--no-plots", sweep_no_plots, "Skip the figures");

  rtsim::AnimateArgs animate;
  CLI::App* animate_cmd = app.add_subcommand("animate",
                                             "Simulate the frames of an animated scene (kd-tree "
                                             "and LVB rebuilt per frame), as a resumable sweep");
  animate_cmd->add_option("scene", animate.scene, "Scene description (YAML)")->required();
  animate_cmd->add_option("--hw", animate.hw, "Hardware configuration (YAML)")->required();
  animate_cmd
      ->add_option("--times", animate.times,
                   "START:END:STEP in the scene's animation time (END included)")
      ->required();
  animate_cmd->add_option("--out", animate.out, "Output directory")->required();
  animate_cmd->add_option("--lvb", animate.lvb, "Culling on, off or both")
      ->check(CLI::IsMember({"on", "off", "both"}));
  animate_cmd->add_option("--width", animate.width, "Image width")->check(CLI::Range(1, 16384));
  animate_cmd->add_option("--height", animate.height, "Image height")->check(CLI::Range(1, 16384));
  animate_cmd->add_option("--jobs", animate.jobs, "Frames at once")->check(CLI::Range(1, 1024));
  animate_cmd
      ->add_option("--check-every", animate.check_every,
                   "Compare frames 0, K, 2K, ... with the reference tracer (both runs); a mismatch "
                   "fails the frame")
      ->check(CLI::Range(1, 100000));
  animate_cmd
      ->add_option("--emit", animate.emit, "Write a job script and manifest instead of running")
      ->check(CLI::IsMember({"slurm"}));

  CLI::App* params_cmd = app.add_subcommand("params",
                                            "Print every key of a hardware file: default (the "
                                            "paper's T&I engine), range, unit, meaning (markdown)");

  rtsim::ReproduceArgs reproduce;
  CLI::App* reproduce_cmd = app.add_subcommand("reproduce",
                                               "Run the paper's three setups with culling off, "
                                               "paper-style and exact; compare with the paper");
  reproduce_cmd->add_option("--out", reproduce.out, "Output directory")->required();
  reproduce_cmd->add_option("--jobs", reproduce.jobs, "Runs at once")->check(CLI::Range(1, 1024));
  reproduce_cmd->add_option("--width", reproduce.width, "Image width (default: the paper's 1920)")
      ->check(CLI::Range(1, 16384));
  reproduce_cmd
      ->add_option("--height", reproduce.height, "Image height (default: the paper's 1080)")
      ->check(CLI::Range(1, 16384));
  reproduce_cmd->add_option("--scene-root", reproduce.scene_root, "Where the paper's scenes are")
      ->envname("RTSIM_SCENE_ROOT");
  reproduce_cmd->add_flag("--ablation", reproduce.ablation,
                          "Run the contention ablation instead (configs/sweeps/ablation.yaml into "
                          "OUT/ablation; OUT/ablation.md and OUT/ablation.json)");
  reproduce_cmd->add_option("--sweep", reproduce.sweep,
                            "Sweep file to run instead of the shipped one "
                            "(paper-reproduction.yaml, or ablation.yaml with --ablation)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    fmt::print(stderr, "rtsim: error: {} (see rtsim --help)\n", e.what());
    return 2;
  }
  if (render.out.empty()) render.out = default_out(render.scene, "render");
  if (lvb.out.empty()) lvb.out = default_out(lvb.scene, "lvb");
  if (*run_cmd && run.out.empty()) {
    if (!run.sources.config_file.empty()) {
      fmt::print(stderr, "rtsim: error: --out is required with --config (see rtsim --help)\n");
      return 2;
    }
    if (!run.sources.scene_file.empty()) run.out = default_out(run.sources.scene_file, "run");
  }
  lvb.lvb.method = method == "paper" ? rtsim::LvbMethod::kPaper : rtsim::LvbMethod::kHierarchical;
  lvb.lvb.bounds = bounds == "geometry" ? rtsim::LvbBounds::kGeometry : rtsim::LvbBounds::kCell;
  lvb.lvb.self_occlusion = self_occlusion == "ignore" ? rtsim::LvbSelfOcclusion::kIgnore
                                                      : rtsim::LvbSelfOcclusion::kTest;
  try {
    if (*render_cmd) return rtsim::run_render(render);
    if (*info_cmd) return rtsim::run_info(info);
    if (*animate_cmd) return rtsim::run_animate(animate);
    if (*params_cmd) {
      fmt::print("{}", rtsim::hw_params_markdown());
      return 0;
    }
    if (*lvb_cmd) return rtsim::run_lvb(lvb);
    if (*sweep_cmd) {
      sweep.plots = !sweep_no_plots;
      return rtsim::run_sweep_command(sweep);
    }
    if (*reproduce_cmd) return rtsim::run_reproduce(reproduce);
    if (*run_cmd) {
      // Only the flags given: they override a --config file's run section.
      YAML::Node& flags = run.sources.run_flags;
      if (lvb_opt->count()) flags["lvb"] = lvb_switch == "on";
      if (check_opt->count()) flags["check"] = run_check;
      if (refl_opt->count()) flags["reflections"] = run_reflections;
      if (width_opt->count()) flags["width"] = run_width;
      if (height_opt->count()) flags["height"] = run_height;
      if (plots_opt->count()) flags["plots"] = !run_no_plots;
      return rtsim::run_model(run);
    }
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

// SystemC's library owns main(): silence its banner (stdout carries our JSON), then let it set
// up the kernel and call sc_main.
int main(int argc, char** argv) {
  setenv("SYSTEMC_DISABLE_COPYRIGHT_MESSAGE", "DISABLE", 1);
  return sc_core::sc_elab_and_sim(argc, argv);
}
