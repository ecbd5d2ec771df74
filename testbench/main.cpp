// rtsim: the command-line front end. Input errors print one line and exit with code 2.
#include "common/error.h"
#include "config_loader/hw_config.h"
#include "kernels/bvh_image.h"
#include "testbench/commands.h"
#include "testbench/run/resources.h"
#include "testbench/studies/sweep.h"

#include <fmt/format.h>
#include <CLI/CLI.hpp>
#include <systemc>

#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <filesystem>
#include <string>
#include <type_traits>

namespace {

// Where render, lvb and run write without --out: out/<scene file's stem>-<command>, relative to
// the working directory (each command names the files it wrote).
std::string default_out(const std::string& scene, const char* command) {
  return (std::filesystem::path("out") /
          fmt::format("{}-{}", std::filesystem::path(scene).stem().string(), command))
      .string();
}

// --accel NAME: the acceleration structure in the memory image (run.accel): the kd-tree or a
// registered BVH node format.
CLI::Option* add_accel_option(CLI::App* cmd, std::function<void(const std::string&)> set) {
  std::vector<std::string> names;
  for (const rtsim::RegisteredName& n : rtsim::accel_names()) names.push_back(n.name);
  return cmd
      ->add_option_function<std::string>(
          "--accel", std::move(set),
          "Acceleration structure: " + rtsim::quoted_names(rtsim::accel_names()) +
              " (default: kdtree, the paper's)")
      ->check(CLI::IsMember(names));
}

void add_prepare_options(CLI::App* cmd, rtsim::PrepareOptions& p) {
  cmd->add_option("--scene-root", p.scene_root,
                  "Directory that relative geometry paths resolve against")
      ->envname("RTSIM_SCENE_ROOT");
  cmd->add_option("--width", p.width, "Override the scene's image width")
      ->check(CLI::Range(1, 16384));
  cmd->add_option("--height", p.height, "Override the scene's image height")
      ->check(CLI::Range(1, 16384));
  add_accel_option(cmd, [&p](const std::string& v) { p.accel = rtsim::parse_accel(v); });
}

// Every subcommand's options, and the flags of `run` that override a --config file only when given.
struct Commands {
  rtsim::RenderArgs render;
  rtsim::InfoArgs info;
  rtsim::LvbArgs lvb;
  std::string method = "hierarchical", bounds = "cell", self_occlusion = "test",
              frustum_test = "overlap";
  rtsim::RunArgs run;
  std::string lvb_switch = "on";
  int run_width = 0, run_height = 0, run_reflections = 0;
  std::string run_sample;  // checked as run.sample
  bool run_check = false, run_no_plots = false;
  CLI::Option *lvb_opt = nullptr, *check_opt = nullptr, *refl_opt = nullptr, *width_opt = nullptr,
              *height_opt = nullptr, *plots_opt = nullptr, *sample_opt = nullptr;
  rtsim::SweepArgs sweep;
  bool sweep_no_plots = false;
  rtsim::AnimateArgs animate;
  rtsim::ReproduceArgs reproduce;
  rtsim::StudyArgs study;
  CLI::App *render_cmd = nullptr, *info_cmd = nullptr, *lvb_cmd = nullptr, *run_cmd = nullptr,
           *sweep_cmd = nullptr, *animate_cmd = nullptr, *params_cmd = nullptr,
           *reproduce_cmd = nullptr, *study_cmd = nullptr;
};

// --integrator and the path's settings (render, lvb, run): `set(key, value)` with the run
// settings' key (run.integrator, run.spp, run.max_depth, run.roulette_depth).
template <class Set>
void add_integrator_options(CLI::App* cmd, Set set) {
  cmd->add_option_function<std::string>(
         "--integrator", [set](const std::string& v) { set("integrator", v); },
         "whitted (one ray a pixel, shadow rays, mirrors) or path (diffuse and mirror bounces "
         "with shadow rays at every hit)")
      ->check(CLI::IsMember({"whitted", "path"}));
  cmd->add_option_function<int>(
         "--spp", [set](int v) { set("spp", v); }, "Path: paths per pixel")
      ->check(CLI::Range(1, 65536));
  cmd->add_option_function<int>(
         "--max-depth", [set](int v) { set("max_depth", v); },
         "Path: bounces after the primary hit")
      ->check(CLI::Range(0, 64));
  cmd->add_option_function<int>(
         "--roulette-depth", [set](int v) { set("roulette_depth", v); },
         "Path: Russian roulette on the bounces from this one on")
      ->check(CLI::Range(1, 65));
}

void add_integrator_options(CLI::App* cmd, rtsim::IntegratorArgs& a) {
  add_integrator_options(cmd, [&a](const std::string& key, const auto& v) {
    if constexpr (std::is_same_v<std::decay_t<decltype(v)>, std::string>) {
      a.integrator = v;
    } else {
      int& to = key == "spp"         ? a.path.spp
                : key == "max_depth" ? a.path.max_depth
                                     : a.path.roulette_depth;
      to = v;
    }
  });
}

void add_render(CLI::App& app, Commands& c) {
  c.render_cmd = app.add_subcommand("render", "Render a scene with the reference tracer");
  c.render_cmd->add_option("scene", c.render.scene, "Scene description (YAML)")->required();
  c.render_cmd->add_option("--out", c.render.out, "Output directory (default: out/SCENE-render)");
  c.render_cmd->add_option("--threads", c.render.threads, "Host threads (0 = all cores)")
      ->check(CLI::Range(0, 1024));
  c.render_cmd->add_option("--reflections", c.render.reflection_depth, "Mirror reflection depth")
      ->check(CLI::Range(0, 16));
  add_integrator_options(c.render_cmd, c.render.integrator);
  add_prepare_options(c.render_cmd, c.render.prepare);
}

void add_info(CLI::App& app, Commands& c) {
  c.info_cmd = app.add_subcommand("info", "Print scene and kd-tree statistics");
  c.info_cmd->add_option("scene", c.info.scene, "Scene description (YAML)")->required();
  c.info_cmd->add_flag("--json", c.info.json, "Print JSON");
  add_prepare_options(c.info_cmd, c.info.prepare);
}

void add_lvb(CLI::App& app, Commands& c) {
  c.lvb_cmd =
      app.add_subcommand("lvb", "Compute the LVB words and measure culling (Tables 4 and 5)");
  c.lvb_cmd->add_option("scene", c.lvb.scene, "Scene description (YAML)")->required();
  c.lvb_cmd->add_option("--out", c.lvb.out, "Output directory (default: out/SCENE-lvb)");
  c.lvb_cmd->add_option("--method", c.method, "paper (all pairs) or hierarchical (kd-tree walk)")
      ->check(CLI::IsMember({"paper", "hierarchical"}));
  c.lvb_cmd->add_option("--bounds", c.bounds, "cell (the paper) or geometry (clipped to the cell)")
      ->check(CLI::IsMember({"cell", "geometry"}));
  c.lvb_cmd
      ->add_option("--self-occlusion", c.self_occlusion,
                   "test (exact, never wrong) or ignore (the paper)")
      ->check(CLI::IsMember({"test", "ignore"}));
  c.lvb_cmd
      ->add_option("--frustum-test", c.frustum_test,
                   "overlap (a box reaching into a frustum counts) or contained (only a box "
                   "wholly inside; the paper's words); --self-occlusion ignore only")
      ->check(CLI::IsMember({"overlap", "contained"}));
  c.lvb_cmd->add_flag("--verify", c.lvb.verify,
                      "Also trace culled rays and count those that were occluded");
  c.lvb_cmd->add_option("--threads", c.lvb.threads, "Host threads for tracing (0 = all cores)")
      ->check(CLI::Range(0, 1024));
  c.lvb_cmd->add_option("--lvb-threads", c.lvb.lvb.threads, "Host threads for preprocessing")
      ->check(CLI::Range(1, 1024));
  add_integrator_options(c.lvb_cmd, c.lvb.integrator);
  c.lvb_cmd->add_option("--culled-rays", c.lvb.culled_rays,
                        "Write every culled shadow ray (origin, light sample point, light, bounce) "
                        "to this .npy");
  add_prepare_options(c.lvb_cmd, c.lvb.prepare);
}

void add_run(CLI::App& app, Commands& c) {
  c.run_cmd = app.add_subcommand("run", "Simulate a frame on the SystemC model of the accelerator");
  c.run_cmd->add_option("scene", c.run.sources.scene_file, "Scene description (YAML)");
  c.run_cmd->add_option("--hw", c.run.sources.hw_file, "Hardware configuration (YAML)");
  c.run_cmd->add_option("--config", c.run.sources.config_file,
                        "Repeat a run from its config.json (instead of SCENE --hw)");
  c.run_cmd
      ->add_option("--set", c.run.sources.set,
                   "Override a key: hw.PATH=VALUE, scene.PATH=VALUE or run.PATH=VALUE")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  c.run_cmd->add_option("--out", c.run.out,
                        "Output directory (default: out/SCENE-run; required with --config)");
  c.lvb_opt = c.run_cmd->add_option("--lvb", c.lvb_switch, "LVB shadow-ray culling: on or off")
                  ->check(CLI::IsMember({"on", "off"}));
  c.check_opt =
      c.run_cmd->add_flag("--check", c.run_check,
                          "Compare every pixel with the reference tracer (exit 1 on a difference)");
  c.refl_opt = c.run_cmd->add_option("--reflections", c.run_reflections, "Mirror reflection depth")
                   ->check(CLI::Range(0, 8));
  c.width_opt = c.run_cmd->add_option("--width", c.run_width, "Override the scene's image width")
                    ->check(CLI::Range(1, 16384));
  c.height_opt =
      c.run_cmd->add_option("--height", c.run_height, "Override the scene's image height")
          ->check(CLI::Range(1, 16384));
  c.plots_opt = c.run_cmd->add_flag("--no-plots", c.run_no_plots, "Skip the PNG figures");
  c.sample_opt = c.run_cmd->add_option(
      "--sample", c.run_sample,
      "Simulate this fraction of the frame's units in detail and estimate its cycles with 95% "
      "intervals (run.sample; docs/sampling.md)");
  add_accel_option(c.run_cmd, [&c](const std::string& v) { c.run.sources.run_flags["accel"] = v; });
  add_integrator_options(
      c.run_cmd, [&c](const std::string& key, const auto& v) { c.run.sources.run_flags[key] = v; });
  c.run_cmd
      ->add_option("--scene-root", c.run.sources.scene_root,
                   "Directory that relative geometry paths resolve against")
      ->envname("RTSIM_SCENE_ROOT");
  c.run_cmd->add_flag("--quiet", c.run.quiet, "No progress line and no summary");
  // run.sample_grow's attempts share their functional pass through this file (no help line: it
  // is the attempts' own).
  c.run_cmd->add_option("--sample-pass", c.run.sample_pass)->group("");
  c.run_cmd->add_option("--trace", c.run.trace_file,
                        "Write a VCD of FIFO occupancies and unit busy signals");
  c.run_cmd->add_option("--mem-trace", c.run.mem_trace_file,
                        "Write a CSV of the memory transactions at the TLM-2.0 boundary (cycle, "
                        "initiator, address, bytes, op, latency)");
  c.run_cmd->add_option("--culled-rays", c.run.culled_rays,
                        "Write every shadow ray the culling unit culled (origin, light sample "
                        "point, light, bounce) to this .npy");
  c.run_cmd->add_option("--dram-commands", c.run.dram_commands,
                        "Write a CSV of every DRAM command (time_ps, channel, bank, command, row, "
                        "column, request) over the whole frame, or --trace-window's cycles");
  c.run_cmd->add_option("--trace-window", c.run.trace_window,
                        "Cycles START:END to trace with --trace, --mem-trace and --dram-commands "
                        "(default 0:100000; --dram-commands: the whole frame)");
}

void add_sweep(CLI::App& app, Commands& c) {
  c.sweep_cmd = app.add_subcommand(
      "sweep", "Run the points of a sweep file in parallel processes (resumable)");
  c.sweep_cmd->add_option("sweep", c.sweep.file, "Sweep description (YAML)");
  c.sweep_cmd->add_option("--out", c.sweep.out,
                          "Output directory (results.csv, results.json, points/, plots/)");
  c.sweep_cmd->add_option("--jobs", c.sweep.jobs, "Points run at once")->check(CLI::Range(1, 1024));
  c.sweep_cmd
      ->add_option("--variants", c.sweep.variants, "Only these of the file's variants (a,b,...)")
      ->delimiter(',');
  c.sweep_cmd
      ->add_option("--set", c.sweep.set,
                   "Override a key in every point: hw.PATH=VALUE, scene.PATH=VALUE, run.PATH=VALUE")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  c.sweep_cmd
      ->add_option("--emit", c.sweep.emit, "Write a job script and manifest instead of running")
      ->check(CLI::IsMember({"slurm"}));
  c.sweep_cmd->add_option("--merge", c.sweep.merge_dir,
                          "Gather the rows of a sweep run elsewhere into DIR/results.csv");
  c.sweep_cmd
      ->add_option("--point", c.sweep.point, "Run one point of DIR/manifest.json (array tasks)")
      ->check(CLI::Range(0, 1 << 30));
  c.sweep_cmd->add_flag("--no-plots", c.sweep_no_plots, "Skip the figures");
  add_accel_option(c.sweep_cmd,
                   [&c](const std::string& v) { c.sweep.set.push_back("run.accel=" + v); });
  c.sweep_cmd
      ->add_option("--point-timeout", c.sweep.point_timeout,
                   "Seconds a point may run before it is killed and recorded as failed "
                   "(default: the sweep file's point_timeout; none)")
      ->check(CLI::Range(0.0, 1e7));
}

void add_animate(CLI::App& app, Commands& c) {
  c.animate_cmd = app.add_subcommand("animate",
                                     "Simulate the frames of an animated scene (kd-tree "
                                     "and LVB rebuilt per frame), as a resumable sweep");
  c.animate_cmd->add_option("scene", c.animate.scene, "Scene description (YAML)")->required();
  c.animate_cmd->add_option("--hw", c.animate.hw, "Hardware configuration (YAML)")->required();
  c.animate_cmd
      ->add_option("--times", c.animate.times,
                   "START:END:STEP in the scene's animation time (END included)")
      ->required();
  c.animate_cmd->add_option("--out", c.animate.out, "Output directory")->required();
  c.animate_cmd->add_option("--lvb", c.animate.lvb, "Culling on, off or both")
      ->check(CLI::IsMember({"on", "off", "both"}));
  c.animate_cmd->add_option("--width", c.animate.width, "Image width")->check(CLI::Range(1, 16384));
  c.animate_cmd->add_option("--height", c.animate.height, "Image height")
      ->check(CLI::Range(1, 16384));
  c.animate_cmd->add_option("--jobs", c.animate.jobs, "Frames at once")->check(CLI::Range(1, 1024));
  c.animate_cmd->add_option(
      "--sample", c.animate.sample,
      "Sampled frames: this fraction of each frame's units in detail, the cycles "
      "estimated with 95% intervals (run.sample; docs/sampling.md)");
  add_accel_option(c.animate_cmd, [&c](const std::string& v) { c.animate.accel = v; });
  c.animate_cmd
      ->add_option("--check-every", c.animate.check_every,
                   "Compare frames 0, K, 2K, ... with the reference tracer (both runs); a mismatch "
                   "fails the frame")
      ->check(CLI::Range(1, 100000));
  c.animate_cmd
      ->add_option("--emit", c.animate.emit, "Write a job script and manifest instead of running")
      ->check(CLI::IsMember({"slurm"}));
}

void add_params_and_reproduce(CLI::App& app, Commands& c) {
  c.params_cmd = app.add_subcommand("params",
                                    "Print every key of a hardware file: default (the "
                                    "paper's T&I engine), range, unit, meaning (markdown)");

  c.reproduce_cmd = app.add_subcommand("reproduce",
                                       "Run the paper's three setups with culling off, "
                                       "paper-style and exact; compare with the paper");
  c.reproduce_cmd->add_option("--out", c.reproduce.out, "Output directory")->required();
  c.reproduce_cmd->add_option("--jobs", c.reproduce.jobs, "Runs at once")
      ->check(CLI::Range(1, 1024));
  c.reproduce_cmd
      ->add_option("--width", c.reproduce.width, "Image width (default: the paper's 1920)")
      ->check(CLI::Range(1, 16384));
  c.reproduce_cmd
      ->add_option("--height", c.reproduce.height, "Image height (default: the paper's 1080)")
      ->check(CLI::Range(1, 16384));
  c.reproduce_cmd->add_option("--sample", c.reproduce.sample,
                              "Sampled runs: this fraction of each frame's units in detail, the "
                              "cycles estimated with 95% intervals (run.sample; docs/sampling.md)");
  c.reproduce_cmd
      ->add_option("--set", c.reproduce.set,
                   "Override a key of every run: hw.PATH=VALUE, scene.PATH=VALUE or "
                   "run.PATH=VALUE (run.sample_seed=2)")
      ->expected(1)
      ->multi_option_policy(CLI::MultiOptionPolicy::TakeAll);
  c.reproduce_cmd
      ->add_option("--scene-root", c.reproduce.scene_root, "Where the paper's scenes are")
      ->envname("RTSIM_SCENE_ROOT");
  c.reproduce_cmd->add_flag(
      "--ablation", c.reproduce.ablation,
      "Run the contention ablation instead (configs/sweeps/ablation.yaml into "
      "OUT/ablation; OUT/ablation.md and OUT/ablation.json)");
  c.reproduce_cmd->add_flag(
      "--bvh", c.reproduce.bvh,
      "Run the BVH study instead (configs/sweeps/bvh-study.yaml into OUT/bvh: the setups on the "
      "kd-tree and on BVH machines, culling off, paper's and exact; OUT/bvh.md and OUT/bvh.json)");
  c.reproduce_cmd->add_option("--sweep", c.reproduce.sweep,
                              "Sweep file to run instead of the shipped one "
                              "(paper-reproduction.yaml, ablation.yaml with --ablation, "
                              "bvh-study.yaml with --bvh)");
  c.reproduce_cmd
      ->add_option("--variants", c.reproduce.variants,
                   "Only these of the sweep's variants (off,paper,exact: the paper's 9 runs)")
      ->delimiter(',');
  c.reproduce_cmd
      ->add_option("--emit", c.reproduce.emit,
                   "Write the sweep's job script and manifest instead of running; this command "
                   "again without it writes the report")
      ->check(CLI::IsMember({"slurm"}));
}

void add_study(CLI::App& app, Commands& c) {
  c.study_cmd = app.add_subcommand(
      "study",
      "Run the study behind a generated table of docs/ (configs/studies/NAME.yaml; "
      "resumable) and render its table");
  c.study_cmd->add_option("name", c.study.name, "Study id (see --list) or study file");
  c.study_cmd->add_option("--out", c.study.out, "Output directory (table.md, a directory per run)");
  c.study_cmd->add_option("--jobs", c.study.jobs, "Points run at once (unless the study says)")
      ->check(CLI::Range(1, 1024));
  c.study_cmd->add_option("--emit", c.study.emit, "Write the runs' job scripts instead of running")
      ->check(CLI::IsMember({"slurm"}));
  c.study_cmd->add_flag("--list", c.study.list, "Print the studies, their docs and costs");
  c.study_cmd->add_flag(
      "--write-doc", c.study.write_doc,
      "Replace the study's block in its doc with the table (and copy its figure)");
  c.study_cmd->add_flag("--table-only", c.study.table_only,
                        "Render the table from the runs already in --out; run nothing");
}

// The defaults that depend on what was given; false when a combination is refused.
bool finish(Commands& c) {
  if (c.render.out.empty()) c.render.out = default_out(c.render.scene, "render");
  if (c.lvb.out.empty()) c.lvb.out = default_out(c.lvb.scene, "lvb");
  if (*c.run_cmd && c.run.out.empty()) {
    if (!c.run.sources.config_file.empty()) {
      fmt::print(stderr, "rtsim: error: --out is required with --config (see rtsim --help)\n");
      return false;
    }
    if (!c.run.sources.scene_file.empty()) c.run.out = default_out(c.run.sources.scene_file, "run");
  }
  c.lvb.lvb.method =
      c.method == "paper" ? rtsim::LvbMethod::kPaper : rtsim::LvbMethod::kHierarchical;
  c.lvb.lvb.bounds = c.bounds == "geometry" ? rtsim::LvbBounds::kGeometry : rtsim::LvbBounds::kCell;
  c.lvb.lvb.self_occlusion = c.self_occlusion == "ignore" ? rtsim::LvbSelfOcclusion::kIgnore
                                                          : rtsim::LvbSelfOcclusion::kTest;
  c.lvb.lvb.frustum_test = c.frustum_test == "contained" ? rtsim::LvbFrustumTest::kContained
                                                         : rtsim::LvbFrustumTest::kOverlap;
  return true;
}

// Runs the subcommand that was given.
int dispatch(Commands& c) {
  if (*c.render_cmd) return rtsim::run_render(c.render);
  if (*c.info_cmd) return rtsim::run_info(c.info);
  if (*c.animate_cmd) return rtsim::run_animate(c.animate);
  if (*c.params_cmd) {
    fmt::print("{}", rtsim::hw_params_markdown());
    return 0;
  }
  if (*c.lvb_cmd) return rtsim::run_lvb(c.lvb);
  if (*c.sweep_cmd) {
    c.sweep.plots = !c.sweep_no_plots;
    return rtsim::run_sweep_command(c.sweep);
  }
  if (*c.reproduce_cmd) return rtsim::run_reproduce(c.reproduce);
  if (*c.study_cmd) return rtsim::run_study_command(c.study);
  if (*c.run_cmd) {
    // Only the flags given: they override a --config file's run section.
    YAML::Node& flags = c.run.sources.run_flags;
    if (c.lvb_opt->count()) flags["lvb"] = c.lvb_switch == "on";
    if (c.check_opt->count()) flags["check"] = c.run_check;
    if (c.refl_opt->count()) flags["reflections"] = c.run_reflections;
    if (c.sample_opt->count()) flags["sample"] = YAML::Node(c.run_sample);
    if (c.width_opt->count()) flags["width"] = c.run_width;
    if (c.height_opt->count()) flags["height"] = c.run_height;
    if (c.plots_opt->count()) flags["plots"] = !c.run_no_plots;
    return rtsim::run_model(c.run);
  }
  return 2;
}

}  // namespace

extern "C" int sc_main(int argc, char** argv) {
  // stdout carries reports
  sc_core::sc_report_handler::set_actions(sc_core::SC_INFO, sc_core::SC_DO_NOTHING);
  CLI::App app{"rtsim: a ray-tracing accelerator model with LVB shadow-ray culling"};
  app.require_subcommand(1);
  Commands c;
  add_render(app, c);
  add_info(app, c);
  add_lvb(app, c);
  add_run(app, c);
  add_sweep(app, c);
  add_animate(app, c);
  add_params_and_reproduce(app, c);
  add_study(app, c);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    fmt::print(stderr, "rtsim: error: {} (see rtsim --help)\n", e.what());
    return 2;
  }
  if (!finish(c)) return 2;
  try {
    return dispatch(c);
  } catch (const rtsim::InputError& e) {
    fmt::print(stderr, "rtsim: error: {}\n", e.what());
    return 2;
  } catch (const std::filesystem::filesystem_error& e) {
    fmt::print(stderr, "rtsim: error: {}\n", e.what());
    return 2;
  } catch (const std::bad_alloc&) {
    const std::string doing = rtsim::Activity::current();
    fmt::print(stderr, "rtsim: error: out of memory{}: lower the resolution or free memory\n",
               doing.empty() ? "" : " while " + doing);
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
  // Past a file-size limit (ulimit -f) a write fails with EFBIG, which the writers report,
  // instead of the signal killing the process with a half-written file.
  std::signal(SIGXFSZ, SIG_IGN);
  return sc_core::sc_elab_and_sim(argc, argv);
}
