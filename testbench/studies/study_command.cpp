// rtsim study: the runs behind a generated block of a doc (a study file,
// testbench/studies/study_file.h) and the table they give. Each run is the command it names, called
// in this process (a sweep's points, a reproduction, an animation, a program of the build), so a
// study resumes as they do: a second sitting runs only what has no result yet. With --emit slurm,
// each run's job array and a job that gathers them (testbench/studies/slurm.h). The table comes
// from the report layer (reports/study_tables.h).
#include "common/error.h"
#include "kernels/names.h"
#include "reports/output_files.h"
#include "reports/study_files.h"
#include "reports/study_tables.h"
#include "testbench/run/process_pool.h"
#include "testbench/studies/slurm.h"
#include "testbench/studies/study_commands.h"
#include "testbench/studies/study_file.h"
#include "testbench/studies/sweep.h"

#include <fmt/format.h>

#include <chrono>
#include <cstdio>
#include <ctime>
#include <filesystem>

#include <sys/wait.h>

namespace fs = std::filesystem;

namespace rtsim {

namespace {

std::string describe(const StudySpec& s) {
  std::string d;
  for (const StudyRun& r : s.runs) d += (d.empty() ? "" : "; ") + describe_run(r);
  return d;
}

int list_studies() {
  for (const std::string& file : study_files()) {
    const StudySpec s = load_study(file);
    fmt::print("{:20} {:22} ~{:g} min   {}\n", s.id, source_relative(s.doc), s.minutes,
               describe(s));
  }
  return 0;
}

// A program of the build (its path in the source tree) run from the source tree, its output in
// DIR/stdout.txt (kept: a second sitting does not run it again), its errors in DIR/stderr.txt.
int run_program(const StudyRun& r, const std::string& dir) {
  // Absolute: the program runs elsewhere.
  const fs::path out = fs::absolute(fs::path(dir) / "stdout.txt");
  if (fs::exists(out)) return 0;
  std::vector<std::string> argv = r.program;
  argv[0] = (fs::path(RTSIM_DEFAULT_SOURCE_DIR) / argv[0]).string();
  if (!fs::exists(argv[0]))
    throw InputError(fmt::format("{}: not found (build it first)", argv[0]));
  fs::create_directories(dir);
  const std::string tmp = out.string() + ".tmp";
  const std::string err = (out.parent_path() / "stderr.txt").string();
  int status = 0;
  waitpid(spawn_program(argv, RTSIM_DEFAULT_SOURCE_DIR, tmp, err), &status, 0);
  if (!WIFEXITED(status) || WEXITSTATUS(status) != 0) {
    fmt::print(stderr, "rtsim: error: {} ended with {}; {} says why\n", describe_run(r),
               describe_exit(status), err);
    return WIFEXITED(status) && WEXITSTATUS(status) != 0 ? WEXITSTATUS(status) : 1;
  }
  fs::rename(tmp, out);
  return 0;
}

// The run's directory: OUT/DIR, or OUT itself.
std::string run_dir(const StudyRun& r, const std::string& out) {
  return r.dir.empty() ? out : (fs::path(out) / r.dir).string();
}

ReproduceArgs reproduce_args(const StudyRun& r, const std::string& dir, int jobs,
                             const std::string& emit) {
  ReproduceArgs a;
  a.out = dir;
  a.sweep = r.file;
  a.variants = r.variants;
  a.ablation = r.reproduce == "ablation";
  a.bvh = r.reproduce == kBvhFamily;
  a.jobs = jobs;
  a.sample = r.sample;
  a.set = r.set;
  a.emit = emit;
  return a;
}

// One run of the study in OUT/DIR (a sweep or animation with --emit slurm: its job script).
int run_one(const StudyRun& r, const std::string& out, int jobs, const std::string& emit) {
  const std::string dir = run_dir(r, out);
  if (r.kind == "program") return run_program(r, dir);
  if (r.kind == "sweep") {
    const SweepSpec spec = load_sweep(r.file, r.set, r.variants);
    if (emit == "slurm") return emit_slurm(spec, dir);
    return run_sweep_points(spec, dir, jobs, r.plots, spec.point_timeout);
  }
  if (r.kind == "animate") {
    AnimateArgs a;
    a.scene = r.file;
    a.hw = r.hw;
    a.times = r.times;
    a.out = dir;
    a.emit = emit;
    a.lvb = r.lvb;
    a.width = r.width;
    a.height = r.height;
    a.jobs = jobs;
    a.check_every = r.check_every;
    a.sample = r.sample;
    return run_animate(a);
  }
  return run_reproduce(reproduce_args(r, dir, jobs, emit));
}

// Where a run's job array is written with --emit slurm.
std::string job_dir(const StudyRun& r, const std::string& out) {
  const std::string dir = run_dir(r, out);
  return r.kind == "reproduce" ? reproduce_sweep_dir(reproduce_args(r, dir, 1, "")) : dir;
}

std::string shell_line(const std::string& command) {
  std::string line;
  if (FILE* p = ::popen(command.c_str(), "r")) {
    char buf[256];
    while (std::fgets(buf, sizeof buf, p)) line += buf;
    if (::pclose(p) != 0) return "";
  }
  while (!line.empty() && (line.back() == '\n' || line.back() == ' ')) line.pop_back();
  return line;
}

// The commit of the source tree, "-dirty" when files outside docs/ differ from it (a refresh
// rewrites docs/ itself); "an unknown commit" outside a git checkout.
std::string source_commit() {
  const std::string git = fmt::format("git -C '{}' ", RTSIM_DEFAULT_SOURCE_DIR);
  const std::string head = shell_line(git + "rev-parse --short=7 HEAD 2>/dev/null");
  if (head.empty()) return "an unknown commit";
  const std::string dirty =
      shell_line(git + "status --porcelain --untracked-files=no -- . ':(exclude)docs' 2>/dev/null");
  return head + (dirty.empty() ? "" : "-dirty");
}

std::string today() {
  const std::time_t t = std::time(nullptr);
  char buf[16];
  std::strftime(buf, sizeof buf, "%Y-%m-%d", std::localtime(&t));
  return buf;
}

// Replaces what lies between the doc's markers of block `id` with `body`.
void replace_block(const std::string& doc, const std::string& id, const std::string& body) {
  std::string s = report::read_text_file(doc);
  const std::string begin = "<!-- generated: " + id + " -->";
  const std::string end = "<!-- end generated: " + id + " -->";
  const size_t i = s.find(begin), j = s.find(end);
  if (i == std::string::npos || j == std::string::npos || j < i)
    throw InputError(fmt::format("{}: has no block '{}' ... '{}'", doc, begin, end));
  s = s.substr(0, i + begin.size()) + "\n" + report::strip(body) + "\n" + s.substr(j);
  write_file_atomic(doc, s);
}

// OUT/table.md, and with `write_doc` the doc's block (stamped) and the figure's copy.
void write_table(const StudySpec& s, const StudyArgs& a, int jobs, double minutes) {
  const std::string table = report::render_study_table(s.table, a.out);
  write_file_atomic((fs::path(a.out) / "table.md").string(), table + "\n");
  fmt::print("study {}: table in {}/table.md\n", s.id, a.out);
  if (!a.write_doc) return;
  // A table of runs made earlier (--table-only: elsewhere, on a cluster) has no sitting to time.
  const std::string sitting =
      a.table_only ? ""
                   : fmt::format("; this sitting took {:.0f} min with --jobs {}", minutes, jobs);
  const std::string note =
      fmt::format("_Generated by `rtsim study {}` (`{}`) from commit {} on {}{}._", s.id,
                  describe(s), source_commit(), today(), sitting);
  replace_block(s.doc, s.id, note + "\n\n" + table);
  if (!s.figure_from.empty())
    fs::copy_file(fs::path(a.out) / s.figure_from, s.figure_to,
                  fs::copy_options::overwrite_existing);
  fmt::print("study {}: {} rewritten\n", s.id, source_relative(s.doc));
}

}  // namespace

int run_study_command(const StudyArgs& a) {
  if (a.list) return list_studies();
  if (a.name.empty()) throw InputError("expected a study name (rtsim study --list) or file");
  if (a.out.empty()) throw InputError("--out DIR is required");
  if (!a.emit.empty() && (a.table_only || a.write_doc))
    throw InputError("--emit writes job scripts: without --table-only and --write-doc");
  const StudySpec s = load_study(study_file_of(a.name));
  const int jobs = s.jobs ? s.jobs : a.jobs;
  const auto start = std::chrono::steady_clock::now();
  std::vector<std::string> arrays;  // with --emit: the runs' job arrays
  if (!a.table_only) {
    fs::create_directories(a.out);
    for (const StudyRun& r : s.runs) {
      if (!a.emit.empty() && r.kind == "program") continue;  // it runs in the gathering job
      fmt::print("study {}: {}\n", s.id, describe_run(r));
      std::fflush(stdout);
      const int code = run_one(r, a.out, jobs, a.emit);
      if (code != 0) {
        fmt::print(stderr, "rtsim: error: study {}: {} failed (exit {}){}\n", s.id, describe_run(r),
                   code, r.kind == "program" ? "" : "; its points' log.txt say why");
        return code;
      }
      if (!a.emit.empty()) arrays.push_back(job_dir(r, a.out));
    }
  }
  if (!a.emit.empty()) return emit_study_slurm(s.id, s.file, a.out, arrays);
  const double minutes =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count() / 60;
  write_table(s, a, jobs, minutes);
  return 0;
}

}  // namespace rtsim
