// The studies the rtsim command runs: sweeps past their time limit, animations as resumable sweeps,
// and the ablation of the contention limits (area lights: test_cli_area.cpp).
#include "tests/test_util.h"
#include "tests/testbench/cli_util.h"

#include <gtest/gtest.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <algorithm>
#include <cctype>
#include <map>
#include <sstream>

namespace rtsim::cli_test {
namespace {

// A CSV file's rows by column name (quoted cells as results.csv writes them: "" is a quote).
std::vector<std::map<std::string, std::string>> csv_rows(const fs::path& file) {
  std::istringstream csv(slurp(file));
  auto split = [](const std::string& line) {
    std::vector<std::string> f(1);
    bool quoted = false;
    for (size_t i = 0; i < line.size(); ++i) {
      const char c = line[i];
      if (quoted && c == '"' && i + 1 < line.size() && line[i + 1] == '"')
        f.back() += line[++i];
      else if (c == '"')
        quoted = !quoted;
      else if (c == ',' && !quoted)
        f.emplace_back();
      else
        f.back() += c;
    }
    return f;
  };
  std::string line;
  std::getline(csv, line);
  const std::vector<std::string> header = split(line);
  std::vector<std::map<std::string, std::string>> rows;
  while (std::getline(csv, line)) {
    const std::vector<std::string> f = split(line);
    EXPECT_EQ(f.size(), header.size()) << line;
    std::map<std::string, std::string> row;
    for (size_t i = 0; i < f.size() && i < header.size(); ++i) row[header[i]] = f[i];
    rows.push_back(row);
  }
  return rows;
}

// A point past its time limit is killed and recorded as failed with the reason and its log's
// tail (failure.json, results.json's "failed", results.csv's `failure` column); the same command
// without the limit finishes it.
TEST(Cli, APointPastItsTimeLimitFailsWithItsReasonAndTheNextRunFinishesIt) {
  const fs::path dir = test::temp_dir("cli_sweep_timeout");
  write(dir / "sweep.yaml",
        "name: slow\nscenes: [" + (test::source_dir() / "configs/scenes/city.yaml").string() +
            "]\nhw: " + (test::source_dir() / "configs/hw/tni-paper.yaml").string() +
            "\npoint_timeout: 0.2\naxes:\n  run.width: [640]\n  run.height: [360]\n");
  const std::string cmd =
      "sweep " + (dir / "sweep.yaml").string() + " --out " + (dir / "out").string() + " --no-plots";
  RunResult r = run(cmd);
  EXPECT_EQ(r.code, 1) << r.out << r.err;
  EXPECT_NE(r.out.find("FAILED (timed out after"), std::string::npos) << r.out;
  const nlohmann::json failed = nlohmann::json::parse(slurp(dir / "out/results.json"))["failed"];
  ASSERT_EQ(failed.size(), 1u);
  EXPECT_EQ(failed[0]["point"], "p0000");
  EXPECT_NE(failed[0]["reason"].get<std::string>().find("point_timeout"), std::string::npos);
  EXPECT_TRUE(failed[0].contains("log_tail"));
  std::vector<std::map<std::string, std::string>> csv = csv_rows(dir / "out/results.csv");
  ASSERT_EQ(csv.size(), 1u);  // the failed point is listed, its metrics empty
  EXPECT_EQ(csv[0]["id"], "p0000");
  EXPECT_EQ(csv[0]["run.width"], "640");
  EXPECT_EQ(csv[0]["cycles_total"], "");
  EXPECT_EQ(csv[0]["failure"].rfind(failed[0]["reason"].get<std::string>(), 0), 0u)
      << csv[0]["failure"];               // the reason first, then the log's last line
  r = run(cmd + " --point-timeout 600");  // the command line's limit over the file's
  EXPECT_EQ(r.code, 0) << r.out << r.err;
  const nlohmann::json res = nlohmann::json::parse(slurp(dir / "out/results.json"));
  EXPECT_EQ(res["rows"].size(), 1u);
  EXPECT_TRUE(res["failed"].empty());
  csv = csv_rows(dir / "out/results.csv");
  ASSERT_EQ(csv.size(), 1u);
  EXPECT_EQ(csv[0]["failure"], "");
  EXPECT_NE(csv[0]["cycles_total"], "");
  EXPECT_FALSE(fs::exists(dir / "out/points/p0000/failure.json"));
  fs::remove_all(dir);
}

// Each frame's figures agree with one another; the LVB's work and a lazy rebuild's are counted.
void expect_consistent_frames(std::vector<std::map<std::string, std::string>>& rows) {
  ASSERT_EQ(rows.size(), 2u);
  EXPECT_EQ(rows[0]["time"], "0");
  EXPECT_EQ(rows[1]["time"], "1");
  for (auto& f : rows) {
    EXPECT_EQ(f["triangles"], "71708");
    const double off = std::stod(f["frame_ms_off"]), on = std::stod(f["frame_ms_on"]);
    EXPECT_NEAR(std::stod(f["saved_ms"]), off - on, 1e-6);
    const double rays = std::stod(f["shadow_rays"]), culled = std::stod(f["shadow_rays_culled"]);
    EXPECT_NEAR(std::stod(f["culled_share"]), culled / rays, 1e-6);
    double per_light = 0;
    for (int l = 0; l < 6; ++l) per_light += std::stod(f["culled_rays_l" + std::to_string(l)]);
    EXPECT_EQ(per_light, culled);
    EXPECT_LE(std::stod(f["culled_leaves_l1"]), std::stod(f["nonempty_leaves"]));
    EXPECT_GT(std::stod(f["lvb_nodes_visited"]), 0);
    EXPECT_GT(std::stod(f["lvb_region_tests"]), 0);
    EXPECT_EQ(f["check_mismatched_pixels"], "0")
        << "both runs of every frame checked against the reference";
  }
  EXPECT_NE(rows[0]["cycles_on"], rows[1]["cycles_on"])
      << "the robots walk: another frame, other cycles";
  // A lazy rebuild's share: after the first frame only, against the frame before.
  EXPECT_EQ(rows[0]["lazy_pairs"], "");
  EXPECT_GT(std::stod(rows[1]["moved_triangles"]), 0);
  EXPECT_GT(std::stod(rows[1]["lazy_dirty_pairs"]), 0);
  EXPECT_LT(std::stod(rows[1]["lazy_dirty_pairs"]), std::stod(rows[1]["lazy_pairs"]));
  EXPECT_LT(std::stod(rows[1]["lazy_region_tests"]), std::stod(rows[1]["lvb_region_tests"]));
}

void expect_animation_outputs(const fs::path& out) {
  EXPECT_TRUE(fs::exists(out / "host.csv"));
  EXPECT_TRUE(fs::exists(out / "frames/frame_0000.png"));
  EXPECT_TRUE(fs::exists(out / "frames/frame_0001.png"));
  for (const char* f :
       {"plots/animate_cycles.png", "plots/animate_culled.png", "plots/animate_preprocessing.png"})
    EXPECT_TRUE(fs::exists(out / f)) << f;
  EXPECT_TRUE(fs::exists(out / "summary.md"));
  const std::string gif = slurp(out / "frames.gif");
  EXPECT_EQ(gif.substr(0, 6), "GIF89a");
}

std::string robots_animation(const std::string& times) {
  return "animate " + (test::source_dir() / "configs/scenes/robots.yaml").string() + " --hw " +
         (test::source_dir() / "configs/hw/small.yaml").string() + " --times " + times;
}

// On a cluster: --emit slurm writes the job; its array tasks run the points; the command again
// writes the tables.
void expect_animation_on_a_cluster() {
  const fs::path cluster = test::temp_dir("cli_animate_slurm");
  const std::string emit =
      robots_animation("0:1:1") + " --width 32 --height 18 --lvb on --out " + cluster.string();
  RunResult r = run(emit + " --emit slurm");
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_TRUE(fs::exists(cluster / "sweep.sbatch"));
  EXPECT_FALSE(fs::exists(cluster / "frames.csv"));
  for (int i = 0; i < 2; ++i)
    ASSERT_EQ(run("sweep --out " + cluster.string() + " --point " + std::to_string(i)).code, 0);
  r = run(emit);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("2 already done, running 0"), std::string::npos) << r.out;
  EXPECT_TRUE(fs::exists(cluster / "frames.csv"));
  fs::remove_all(cluster);
}

// rtsim animate: the frames of BART's robots as a sweep; frames.csv pairs culling off and on per
// time, the robots move so the frames differ, a rerun runs nothing again, and a bad --times is an
// input error.
TEST(Cli, AnimateRunsTheFramesAsAResumableSweep) {
  RTSIM_REQUIRE_SHARED_SCENES();
  const fs::path out = test::temp_dir("cli_animate");
  const std::string args = robots_animation("0:1:1") +
                           " --width 32 --height 18 --lvb both --jobs 2 --check-every 1 --out " +
                           out.string();
  RunResult r = run(args);
  ASSERT_EQ(r.code, 0) << r.err;
  std::vector<std::map<std::string, std::string>> rows = csv_rows(out / "frames.csv");
  expect_consistent_frames(rows);
  expect_animation_outputs(out);
  const std::string first = slurp(out / "frames.csv");
  r = run(args);
  ASSERT_EQ(r.code, 0) << r.err;
  EXPECT_NE(r.out.find("4 already done, running 0"), std::string::npos) << r.out;
  EXPECT_EQ(slurp(out / "frames.csv"), first) << "frames.csv is deterministic";
  expect_animation_on_a_cluster();
  // Another --check-every is another set of points: the directory is not reused for it.
  expect_input_error(robots_animation("0:1:1") + " --width 32 --height 18 --out " + out.string(),
                     {"manifest", "another --out"});
  expect_input_error(robots_animation("2:1:1") + " --out " + out.string(),
                     {"--times 2:1:1", "increasing"});
  fs::remove_all(out);
}

// rtsim reproduce --ablation on a small sweep of the city: one row per variant in ablation.md and
// ablation.json, the `ideal` row is a plain run on ideal.yaml, the `all` row (the variant's own
// hardware file) a plain run on tni-paper.yaml, and a rerun runs nothing again.
using Variants = std::vector<std::pair<std::string, std::string>>;

// The variants of configs/sweeps/ablation.yaml.
Variants ablation_variants() {
  const std::string link = "{latency: 2, bytes_per_cycle: 32, header_bytes: 8}";
  return {{"ideal", "{}"},
          {"l1-ports",
           "{hw.trv.l1.ports: 1, hw.list.l1.ports: 1, hw.ist.l1.ports: 1, hw.shading.l1.ports: 1}"},
          {"l2-banks",
           "{hw.trv.l2.banks: 8, hw.trv.l2.ports: 1, hw.list.l2.banks: 8, hw.list.l2.ports: 1, "
           "hw.ist.l2.banks: 8, hw.ist.l2.ports: 1}"},
          {"l2-fill-port-separate",
           "{hw.trv.l2.banks: 8, hw.trv.l2.ports: 1, hw.trv.l2.fill_port: separate, "
           "hw.list.l2.banks: 8, hw.list.l2.ports: 1, hw.list.l2.fill_port: separate, "
           "hw.ist.l2.banks: 8, hw.ist.l2.ports: 1, hw.ist.l2.fill_port: separate}"},
          {"links",
           "{hw.trv.link: " + link + ", hw.list.link: " + link + ", hw.ist.link: " + link + "}"},
          {"memory-link", "{hw.memory_link: " + link + "}"},
          {"l2-private",
           "{hw.trv.l2.sharing: unit, hw.list.l2.sharing: unit, hw.ist.l2.sharing: unit}"},
          {"dram-cycles", "{hw.dram.preset: gddr3-gt200-1ghz-cycles}"},
          {"culling-rate", "{hw.culling.records_per_cycle: 1, hw.shading.write_records: true}"},
          {"frame-writes", "{hw.shading.write_records: true}"},
          {"all", "{hw: " + (test::source_dir() / "configs/hw/tni-paper.yaml").string() + "}"},
          {"queues", "{hw: " + (test::source_dir() / "configs/hw/tni-paper.yaml").string() +
                         ", hw.shading.write_buffer: 0, hw.dram.input_queue: 0, "
                         "hw.trv.l1.max_merge: 0, hw.trv.l2.max_merge: 0, hw.list.l1.max_merge: 0, "
                         "hw.list.l2.max_merge: 0, hw.ist.l1.max_merge: 0, hw.ist.l2.max_merge: 0, "
                         "hw.shading.l1.max_merge: 0, hw.trv.link.buffer_flits: 0, "
                         "hw.list.link.buffer_flits: 0, hw.ist.link.buffer_flits: 0, "
                         "hw.memory_link.buffer_flits: 0}"}};
}

void write_ablation_sweep(const fs::path& file, const std::string& scene,
                          const Variants& variants) {
  std::string yaml = "name: ablation-test\nscenes: [" + scene +
                     "]\nhw: " + (test::source_dir() / "configs/hw/ideal.yaml").string() +
                     "\nvariants:\n";
  for (const auto& [name, set] : variants) yaml += "  " + name + ": " + set + "\n";
  yaml +=
      "axes:\n  run.lvb: [off, on]\nmetrics: [cycles_total, frame_ms_all, frame_ms_shadow, "
      "trv_busy, stats.trv.l2.bank.stall_cycles, stats.memory.icnt.reply.avg_queue_cycles, "
      "dram_bandwidth_gbps, stats.dram.bytes_written]\n";
  write(file, yaml);
}

// Markdown: a frame-time row and a statistics row per variant, each with numbers.
void expect_two_rows_per_variant(const std::string& md, const Variants& variants) {
  for (const auto& [name, set] : variants) {
    size_t rows = 0, pos = 0;
    const std::string head = "\n| " + name + " | ";
    while ((pos = md.find(head, pos)) != std::string::npos) {
      const std::string line = md.substr(pos + 1, md.find('\n', pos + 1) - pos - 1);
      if (line.find(".yaml") == std::string::npos) {  // not the list of variants
        ++rows;
        EXPECT_TRUE(std::any_of(line.begin() + long(head.size()), line.end(), ::isdigit)) << line;
      }
      pos += head.size();
    }
    EXPECT_EQ(rows, 2u) << name << " in:\n" << md;
  }
  EXPECT_NE(md.find("the single limit that moves the frame time most is `"), std::string::npos)
      << md;
  // A unit type's metrics are titled by the label its points' reports give it.
  for (const char* title : {" TRV busy |", " TRV L2 bank stall cycles |"})
    EXPECT_NE(md.find(title), std::string::npos) << title << " in:\n" << md;
}

// JSON: one entry per variant with both culling settings' metrics; by name.
std::map<std::string, nlohmann::json> expect_an_entry_per_variant(const nlohmann::json& j,
                                                                  const Variants& variants) {
  EXPECT_EQ(j["schema"], "rtsim-ablation/1");
  EXPECT_EQ(j["missing_points"], 0);
  // Which variants tni-paper.yaml (the `all` variant's hardware) already holds.
  std::map<std::string, nlohmann::json> in_all;
  for (const auto& v : j["variants"]) in_all[v["name"]] = v["in_all"];
  for (const char* v :
       {"l1-ports", "l2-banks", "links", "memory-link", "culling-rate", "frame-writes"})
    EXPECT_EQ(in_all[v], true) << v;
  for (const char* v : {"l2-fill-port-separate", "l2-private", "dram-cycles", "queues"})
    EXPECT_EQ(in_all[v], false) << v;
  EXPECT_TRUE(in_all["ideal"].is_null());
  std::map<std::string, nlohmann::json> by_name;
  if (j["scenes"].size() != 1u || j["scenes"][0]["variants"].size() != variants.size()) {
    ADD_FAILURE() << "one scene with a row per variant: " << j.dump();
    return by_name;
  }
  const nlohmann::json& sc = j["scenes"][0];
  for (size_t i = 0; i < variants.size(); ++i) {
    const nlohmann::json& v = sc["variants"][i];
    EXPECT_EQ(v["name"], variants[i].first);
    for (const char* lvb : {"off", "on"}) {
      EXPECT_TRUE(v[lvb]["frame_ms_all"].is_number()) << v.dump();
      EXPECT_GT(v[lvb]["cycles_total"].get<uint64_t>(), 0u);
    }
    EXPECT_TRUE(v["reduction_pct"].is_number());
    by_name[v["name"]] = v;
  }
  EXPECT_EQ(sc["facts"]["largest_single_limit_off"]["variant"].is_string(), true);
  for (const char* lvb : {"off", "on"})  // not a variant with a hardware file of its own
    for (const char* own : {"all", "queues"})
      EXPECT_NE(sc["facts"][std::string("largest_single_limit_") + lvb]["variant"], own);
  EXPECT_TRUE(sc["facts"]["all_off_pct"].is_number());
  return by_name;
}

// The ideal and all rows are plain runs on ideal.yaml and tni-paper.yaml.
void expect_plain_runs(const fs::path& dir, const std::string& scene,
                       std::map<std::string, nlohmann::json>& by_name) {
  for (const auto& [variant, hw] :
       {std::pair<std::string, std::string>{"ideal", "ideal.yaml"}, {"all", "tni-paper.yaml"}})
    for (const char* lvb : {"off", "on"}) {
      const fs::path out = dir / ("plain-" + variant + "-" + lvb);
      const RunResult p =
          run("run " + scene + " --hw " + (test::source_dir() / "configs/hw" / hw).string() +
              " --width 32 --height 18 --no-plots --quiet --lvb " + lvb + " --out " + out.string());
      ASSERT_EQ(p.code, 0) << p.err;
      const nlohmann::json rep = nlohmann::json::parse(slurp(out / "report.json"));
      EXPECT_EQ(by_name[variant][lvb]["cycles_total"], rep["cycles_total"])
          << variant << ", culling " << lvb;
    }
}

// Bad ablation sweeps: a variant's missing hardware file; no run.lvb axis.
void expect_bad_ablation_sweeps_refused(const fs::path& dir, const std::string& scene) {
  const std::string ideal = (test::source_dir() / "configs/hw/ideal.yaml").string();
  write(dir / "nohw.yaml", "scenes: [" + scene + "]\nhw: " + ideal +
                               "\nvariants:\n  all: {hw: nowhere.yaml}\naxes:\n  run.lvb: [off, "
                               "on]\n");
  expect_input_error("reproduce --ablation --sweep " + (dir / "nohw.yaml").string() + " --out " +
                         (dir / "o").string(),
                     {"nohw.yaml", "nowhere.yaml", "not found"});
  write(dir / "noaxis.yaml",
        "scenes: [" + scene + "]\nhw: " + ideal + "\nvariants:\n  ideal: {}\n");
  expect_input_error("reproduce --ablation --sweep " + (dir / "noaxis.yaml").string() + " --out " +
                         (dir / "o").string(),
                     {"noaxis.yaml", "run.lvb"});
  EXPECT_FALSE(fs::exists(dir / "o"));
}

TEST(Cli, AblationHasARowPerVariantAndItsIdealAndAllRowsArePlainRuns) {
  const fs::path dir = test::temp_dir("cli_ablation");
  const std::string scene = (test::source_dir() / "configs/scenes/city.yaml").string();
  const Variants variants = ablation_variants();
  write_ablation_sweep(dir / "ablation.yaml", scene, variants);
  const std::string cmd = "reproduce --ablation --sweep " + (dir / "ablation.yaml").string() +
                          " --out " + (dir / "out").string() + " --width 32 --height 18 --jobs 2";
  const RunResult r = run(cmd);
  ASSERT_EQ(r.code, 0) << r.out << r.err;
  ASSERT_TRUE(fs::exists(dir / "out/ablation/results.json"));
  const std::string md = slurp(dir / "out/ablation.md");
  expect_two_rows_per_variant(md, variants);
  std::map<std::string, nlohmann::json> by_name = expect_an_entry_per_variant(
      nlohmann::json::parse(slurp(dir / "out/ablation.json")), variants);
  EXPECT_EQ(by_name["ideal"]["change_vs_ideal_off_pct"].get<double>(), 0.0);
  EXPECT_TRUE(by_name["ideal"]["off"]["stats.trv.l2.bank.stall_cycles"].is_null())
      << "ideal L2s have no banks";
  EXPECT_GT(by_name["l2-banks"]["off"]["stats.trv.l2.bank.stall_cycles"].get<uint64_t>(), 0u);
  EXPECT_EQ(by_name["ideal"]["off"]["stats.dram.bytes_written"], 0);
  EXPECT_GT(by_name["frame-writes"]["off"]["stats.dram.bytes_written"].get<uint64_t>(), 0u);
  expect_plain_runs(dir, scene, by_name);
  // A rerun runs no point again and writes the same report.
  const RunResult again = run(cmd);
  ASSERT_EQ(again.code, 0) << again.err;
  EXPECT_NE(again.out.find("24 points, 24 already done, running 0"), std::string::npos)
      << again.out;
  EXPECT_EQ(slurp(dir / "out/ablation.md"), md);
  expect_bad_ablation_sweeps_refused(dir, scene);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rtsim::cli_test
