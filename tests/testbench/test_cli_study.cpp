// rtsim study (testbench/studies/study_command.cpp): a tiny study end to end (a sweep of the city
// at 64x36 with the shipped cache table), its resume, the doc block it writes against the
// results.csv it read; a study of programs (their output kept, a failing one); --list, and the
// one-line error of a bad study file.
#include "tests/test_util.h"
#include "tests/testbench/cli_util.h"

#include <fmt/format.h>
#include <gtest/gtest.h>

#include <cmath>
#include <sstream>

namespace rtsim::cli_test {
namespace {

// The shipped cache-trv-l1 study's table (its renderer, key, baseline and columns), so that the
// test renders what the doc gets.
std::string shipped_cache_table() {
  const std::string text = slurp(test::source_dir() / "configs/studies/cache-trv-l1.yaml");
  const size_t begin = text.find("\ntable:\n"), end = text.find("\nfigure:");
  EXPECT_NE(begin, std::string::npos);
  return text.substr(begin + 1, end - begin);
}

// The study: TRV L1 of 4 and 8 KB on the city at 64x36 (8 KB, the table's baseline), its block in
// a doc beside it.
fs::path tiny_study(const fs::path& dir) {
  const fs::path src = test::source_dir();
  write(dir / "sweep.yaml",
        "name: tiny\nscenes: [" + (src / "configs/scenes/city.yaml").string() +
            "]\nhw: " + (src / "configs/hw/tni-paper.yaml").string() +
            "\nset: {scene.resolution: [64, 36]}\naxes:\n  hw.trv.l1.size_kb: [4, 8]\n"
            "metrics: [cycles_total, trv_l1_hit_rate, ist_l1_hit_rate, ist_l2_hit_rate, "
            "trv_busy, dram_bandwidth_gbps, ist_l2_bank_stall_cycles, trv_reply_queue_cycles, "
            "ist_reply_queue_cycles]\n");
  write(dir / "doc.md",
        "# Doc\n\nbefore\n<!-- generated: tiny -->\nold\n"
        "<!-- end generated: tiny -->\nafter\n");
  write(dir / "tiny.yaml",
        "id: tiny\ndoc: doc.md\nminutes: 1\nruns:\n  - sweep: sweep.yaml\n"
        "    plots: false\n" +
            shipped_cache_table());
  return dir / "tiny.yaml";
}

std::vector<std::string> split(const std::string& line, const std::string& sep) {
  std::vector<std::string> out;
  size_t at = 0;
  for (size_t next; (next = line.find(sep, at)) != std::string::npos; at = next + sep.size())
    out.push_back(line.substr(at, next - at));
  out.push_back(line.substr(at));
  return out;
}

// 1234567 -> "1,234,567".
std::string thousands(long long v) {
  std::string d = std::to_string(v);
  for (int i = int(d.size()) - 3; i > 0; i -= 3) d.insert(size_t(i), ",");
  return d;
}

// The rows the cache table should hold, from the sweep's results.csv (the test's points have no
// quoted cells): scene, TRV L1 KB, cycles as 1,234, the change against the 8 KB point, its TRV
// L1 hit rate as 12.3%.
std::vector<std::string> rows_from_results(const fs::path& run_dir) {
  std::istringstream csv(slurp(run_dir / "results.csv"));
  std::string line;
  std::getline(csv, line);
  const std::vector<std::string> head = split(line, ",");
  auto col = [&](const std::string& name) {
    return size_t(std::find(head.begin(), head.end(), name) - head.begin());
  };
  std::vector<std::vector<std::string>> rows;
  while (std::getline(csv, line)) rows.push_back(split(line, ","));
  double base = 0;
  for (const auto& r : rows)
    if (r.at(col("hw.trv.l1.size_kb")) == "8") base = std::stod(r.at(col("cycles_total")));
  std::vector<std::string> out;
  for (const auto& r : rows) {
    const double cycles = std::stod(r.at(col("cycles_total")));
    out.push_back(fmt::format("| {} | {} | {} | {:+.1f}% | {:.1f}% |", r.at(col("scene")),
                              r.at(col("hw.trv.l1.size_kb")), thousands(std::llround(cycles)),
                              100 * (cycles / base - 1),
                              100 * std::stod(r.at(col("trv_l1_hit_rate")))));
  }
  return out;
}

TEST(Cli, StudyRunsResumesAndWritesItsTableFromTheResults) {
  const fs::path dir = test::temp_dir("cli_study");
  const fs::path study = tiny_study(dir);
  const fs::path out = dir / "out";
  const std::string args = "study " + study.string() + " --out " + out.string() + " --jobs 2";
  RunResult r = run(args + " --write-doc");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  EXPECT_NE(r.out.find("2 points, 0 already done, running 2"), std::string::npos) << r.out;
  const std::string table = slurp(out / "table.md");
  // The table: its header, then a row per point of results.csv in its order, each row's first
  // cells the figures of the file.
  std::vector<std::string> lines = split(table, "\n");
  ASSERT_EQ(lines.size(), 5u) << table;  // header, rule, two points, the final newline
  EXPECT_EQ(lines[0].rfind("| scene | TRV L1 KB | cycles | vs Table 2 | TRV L1 hits |", 0), 0u);
  const std::vector<std::string> want = rows_from_results(out);
  ASSERT_EQ(want.size(), 2u);
  for (size_t i = 0; i < want.size(); ++i)
    EXPECT_EQ(lines[2 + i].rfind(want[i].substr(0, want[i].size() - 1), 0), 0u)
        << lines[2 + i] << "\nexpected to start with " << want[i];
  EXPECT_NE(table.find("| city | 8 | "), std::string::npos) << table;
  EXPECT_NE(table.find(" | +0.0% | "), std::string::npos) << table;
  // The doc: the block replaced by the stamp and the table, the rest as it was.
  const std::string doc = slurp(dir / "doc.md");
  const std::string begin = "before\n<!-- generated: tiny -->\n_Generated by `rtsim study tiny` (";
  EXPECT_EQ(doc.rfind("# Doc\n\n" + begin, 0), 0u) << doc;
  const std::string tail = "\n\n" + table + "<!-- end generated: tiny -->\nafter\n";
  ASSERT_GE(doc.size(), tail.size());
  EXPECT_EQ(doc.substr(doc.size() - tail.size()), tail) << doc;
  EXPECT_EQ(doc.find("old"), std::string::npos);
  // A second sitting runs nothing new and renders the same table.
  const auto stamp = fs::last_write_time(out / "points/p0000/report.json");
  r = run(args);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("2 points, 2 already done, running 0"), std::string::npos) << r.out;
  EXPECT_EQ(fs::last_write_time(out / "points/p0000/report.json"), stamp);
  EXPECT_EQ(slurp(out / "table.md"), table);
  fs::remove_all(dir);
}

// A study of programs: one prints `NAME: N cycles` lines, its working directory on stderr and
// counts its runs; one prints examples/platform's frame lines; a third, when `fail`, exits 3.
fs::path program_study(const fs::path& dir, bool fail) {
  write(dir / "a.sh", "echo x >> '" + (dir / "count").string() +
                          "'\necho 'first: 12345 cycles'\necho ' not: 1 cycles'\necho 'second: 7 "
                          "cycles'\npwd >&2\n");
  write(dir / "b.sh",
        "echo '{\"frame\": 1, \"cycles\": 1000, \"pixels\": 6400, \"interrupt_ns\": 1234.4, "
        "\"wrong_records\": 0}'\n");
  write(dir / "c.sh", "echo 'c: 1 cycles'\necho broken >&2\nexit 3\n");
  write(dir / "doc.md", "<!-- generated: progs -->\n<!-- end generated: progs -->\n");
  std::string runs;
  for (const char* r : {"a", "b", "c"})
    if (*r != 'c' || fail)
      runs +=
          fmt::format("  - dir: {}\n    program: [/bin/sh, {}]\n", r, (dir / r).string() + ".sh");
  write(dir / "progs.yaml",
        "id: progs\ndoc: doc.md\nruns:\n" + runs +
            "table:\n  renderer: integration_table\n  rows:\n"
            "    - {run: a, figure: two lines, cells: named_cycles}\n"
            "    - {run: b, figure: 'examples/platform, city', cells: platform}\n");
  return dir / "progs.yaml";
}

TEST(Cli, AStudyRunsProgramsFromTheSourceTreeOnceAndTabulatesWhatTheyPrint) {
  const fs::path dir = test::temp_dir("cli_study_programs");
  const fs::path out = dir / "out";
  const std::string args = "study " + program_study(dir, false).string() + " --out " + out.string();
  RunResult r = run(args);
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  const std::string a = "/bin/sh " + (dir / "a.sh").string(),
                    b = "/bin/sh " + (dir / "b.sh").string();
  EXPECT_EQ(slurp(out / "table.md"),
            "| figure | cycles | measured by |\n|---|---|---|\n"
            "| two lines: first, second | 12,345, 7 | `" +
                a +
                "` |\n"
                "| examples/platform, city at 6,400 pixels, one camera (interrupt 1,234 ns; wrong "
                "records 0) | 1,000 | `" +
                b + "` |\n");
  EXPECT_EQ(slurp(out / "a/stderr.txt"), test::source_dir().string() + "\n");
  // A second sitting keeps what the programs printed.
  r = run(args);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_EQ(slurp(dir / "count"), "x\n");
  // A program that fails: the study stops with its exit code and names its stderr.txt; no output
  // is kept, so the next sitting runs it again.
  r = run("study " + program_study(dir, true).string() + " --out " + out.string());
  EXPECT_EQ(r.code, 3) << r.err;
  EXPECT_NE(r.err.find((out / "c/stderr.txt").string()), std::string::npos) << r.err;
  EXPECT_FALSE(fs::exists(out / "c/stdout.txt"));
  EXPECT_EQ(slurp(out / "c/stderr.txt"), "broken\n");
  // A row must name a program run.
  std::string text = slurp(dir / "progs.yaml");
  text.replace(text.find("{run: b,"), 8, "{run: z,");
  write(dir / "progs.yaml", text);
  expect_input_error("study " + (dir / "progs.yaml").string() + " --out " + out.string(),
                     {"progs.yaml", "table.rows[1].run", "'z'", "program"});
  fs::remove_all(dir);
}

// A study of a reproduction (a contention ablation of the city at 32x18: two variants, culling
// off and on), a sweep and a program, its table the ablation's report.
fs::path mixed_study(const fs::path& dir) {
  const fs::path src = test::source_dir();
  const std::string city = (src / "configs/scenes/city.yaml").string();
  write(
      dir / "abl.yaml",
      "name: abl\nscenes: [" + city + "]\nhw: " + (src / "configs/hw/ideal.yaml").string() +
          "\nvariants:\n  ideal: {}\n  all: {hw: " + (src / "configs/hw/tni-paper.yaml").string() +
          "}\naxes:\n  run.lvb: [off, on]\nmetrics: [frame_ms_all]\n");
  write(dir / "sw.yaml", "name: sw\nscenes: [" + city +
                             "]\nhw: " + (src / "configs/hw/small.yaml").string() +
                             "\nset: {scene.resolution: [32, 18]}\naxes:\n  hw.trv.l1.size_kb: "
                             "[2, 8]\nmetrics: [cycles_total]\n");
  write(dir / "p.sh", "echo 'a: 42 cycles'\n");
  write(dir / "doc.md", "<!-- generated: mixed -->\n<!-- end generated: mixed -->\n");
  write(dir / "mixed.yaml",
        "id: mixed\ndoc: doc.md\nruns:\n  - dir: abl\n    reproduce: ablation\n    sweep_file: "
        "abl.yaml\n    set: [run.width=32, run.height=18]\n  - dir: sw\n    sweep: sw.yaml\n    "
        "plots: false\n  - dir: p\n    program: [/bin/sh, " +
            (dir / "p.sh").string() +
            "]\ntable:\n  renderer: copy_markdown\n  file: abl/ablation.md\n  from: Sweep\n");
  return dir / "mixed.yaml";
}

TEST(Cli, AStudyEmitsItsRunsJobArraysAndAJobThatGathersThemIntoTheSameTable) {
  const fs::path dir = test::temp_dir("cli_study_slurm");
  const std::string study = mixed_study(dir).string();
  const fs::path out = dir / "slurm";
  ASSERT_EQ(run("study " + study + " --out " + (dir / "local").string() + " --jobs 2").code, 0);
  const RunResult r = run("study " + study + " --out " + out.string() + " --emit slurm");
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  // study.sh submits the reproduction's array and the sweep's, then the gathering job after them.
  const std::string submit = slurp(out / "study.sh");
  const std::string arrays = " '" + (out / "abl/ablation/sweep.sbatch").string() + "' '" +
                             (out / "sw/sweep.sbatch").string() + "'; do";
  EXPECT_NE(submit.find("for array in" + arrays), std::string::npos) << submit;
  EXPECT_NE(submit.find("--dependency=afterok$after} '" + (out / "study.sbatch").string() + "'"),
            std::string::npos)
      << submit;
  EXPECT_NE(slurp(out / "abl/ablation/sweep.sbatch").find("#SBATCH --array=0-3\n"),
            std::string::npos);
  const std::string gather = slurp(out / "study.sbatch");
  EXPECT_NE(gather.find("study '" + study + "' --out '" + out.string() + "' --jobs 1\n"),
            std::string::npos)
      << gather;
  EXPECT_FALSE(fs::exists(out / "table.md"));
  EXPECT_FALSE(fs::exists(out / "p")) << "a program runs in the gathering job";
  // The cluster, played here: each array task, then the gathering job (a bash script whose
  // #SBATCH lines are comments) simulates nothing and writes the local run's table.
  for (const auto& [sub, points] : {std::pair{"abl/ablation", 4}, std::pair{"sw", 2}})
    for (int i = 0; i < points; ++i)
      ASSERT_EQ(run(fmt::format("sweep --out {} --point {}", (out / sub).string(), i)).code, 0);
  const RunResult g = test::run_command("bash " + (out / "study.sbatch").string());
  ASSERT_EQ(g.code, 0) << g.out << g.err;
  EXPECT_NE(g.out.find("4 points, 4 already done, running 0"), std::string::npos) << g.out;
  EXPECT_EQ(slurp(out / "table.md"), slurp(dir / "local/table.md"));
  EXPECT_EQ(slurp(out / "p/stdout.txt"), "a: 42 cycles\n");
  expect_input_error("study " + study + " --out " + out.string() + " --emit slurm --write-doc",
                     {"--emit", "--write-doc"});
  fs::remove_all(dir);
}

TEST(Cli, StudyListNamesEveryShippedStudyWithItsDocAndCost) {
  const RunResult r = run("study --list");
  ASSERT_EQ(r.code, 0) << r.err;
  size_t studies = 0;
  for (const auto& e : fs::directory_iterator(test::source_dir() / "configs/studies")) {
    if (e.path().extension() != ".yaml") continue;
    ++studies;
    const std::string id = e.path().stem().string();
    EXPECT_TRUE(r.out.rfind(id + " ", 0) == 0 || r.out.find("\n" + id + " ") != std::string::npos)
        << id << " not listed:\n"
        << r.out;
  }
  EXPECT_GE(studies, 17u);
  EXPECT_NE(r.out.find("cache-trv-l1         docs/cache-sweeps.md   ~3 min   rtsim sweep "
                       "configs/sweeps/cache-trv-l1.yaml\n"),
            std::string::npos)
      << r.out;
}

TEST(Cli, ABadStudyFileIsOneErrorNamingTheFileAndTheKey) {
  const fs::path dir = test::temp_dir("cli_study_bad");
  const fs::path study = tiny_study(dir);
  const std::string good = slurp(study), out = " --out " + (dir / "out").string();
  auto with = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    write(study, text);
    return "study " + study.string() + out;
  };
  expect_input_error(with("sweep: sweep.yaml", "sweep: missing.yaml"),
                     {study.string(), "runs[0].sweep", "missing.yaml", "not found"});
  expect_input_error(with("renderer: cache_table", "renderer: pie"),
                     {study.string(), "table.renderer", "cache_table"});
  expect_input_error(with("format: pct", "format: percent"),
                     {study.string(), "table.columns[0].format", "pct"});
  expect_input_error(with("minutes: 1", "minutes: 1\nmintues: 2"), {study.string(), "mintues"});
  expect_input_error(with("id: tiny", "id: other"), {study.string(), "'id'", "tiny"});
  expect_input_error("study no-such-study" + out, {"no-such-study.yaml", "--list"});
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rtsim::cli_test
