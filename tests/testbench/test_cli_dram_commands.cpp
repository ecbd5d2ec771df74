// rtsim run --dram-commands: every command the DRAM controllers issued, one CSV row each, over the
// span the report's dram.* statistics count (its ACT rows are stats.dram.activates, and so on),
// each channel's in time order; --trace-window keeps a window; an observer that changes no figure;
// bad input is one line and exit 2.
#include "tests/test_util.h"
#include "tests/testbench/cli_util.h"

#include <gtest/gtest.h>

#include <nlohmann/json.hpp>

#include <map>
#include <sstream>

namespace rtsim::cli_test {
namespace {

struct Command {
  uint64_t time_ps;
  uint32_t channel, bank;
  std::string command, row, column, request;
};

// The rows after the header, which must be `header`; empty fields kept.
std::vector<Command> read_commands(const fs::path& csv, const std::string& header) {
  std::istringstream in(slurp(csv));
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, header);
  std::vector<Command> rows;
  while (std::getline(in, line)) {
    std::vector<std::string> f(1);
    for (char c : line) {
      if (c == ',')
        f.emplace_back();
      else
        f.back().push_back(c);
    }
    EXPECT_EQ(f.size(), 7u) << line;
    if (f.size() != 7) continue;
    rows.push_back({std::stoull(f[0]), uint32_t(std::stoul(f[1])), uint32_t(std::stoul(f[2])), f[3],
                    f[4], f[5], f[6]});
  }
  return rows;
}

const char* const kHeader = "time_ps,channel,bank,command,row,column,request";

// Per preset (GDDR3: no refresh; LPDDR4: all-bank refresh, so REF rows): the trace's commands by
// kind are the report's DRAM counters, on the command clock's edges, each channel's in time order.
TEST(Cli, DramCommandsAreTheCommandsTheReportCounts) {
  for (const std::string preset : {"gddr3-gt200-1ghz", "lpddr4-3200"}) {
    const fs::path out = test::temp_dir("cli_dram_commands_" + preset);
    const fs::path csv = out / "trace" / "cmds.csv";  // a directory the run makes
    const RunResult r = run(city_run(
        out, "--quiet --set hw.dram.preset=" + preset + " --dram-commands " + csv.string()));
    ASSERT_EQ(r.code, 0) << r.err;
    const nlohmann::json rep = nlohmann::json::parse(slurp(out / "report.json"));
    const nlohmann::json& dram = rep["stats"]["dram"];
    const nlohmann::json& hw = rep["config"]["hw"]["dram"];
    const std::vector<Command> rows = read_commands(csv, kHeader);
    std::map<std::string, uint64_t> count;
    std::map<uint32_t, uint64_t> last;  // by channel
    for (const Command& c : rows) {
      ++count[c.command];
      EXPECT_EQ(c.time_ps % hw["tCK_ps"].get<uint64_t>(), 0u) << c.time_ps;
      EXPECT_LT(c.channel, hw["channels"].get<uint32_t>());
      EXPECT_LT(c.bank, hw["banks"].get<uint32_t>());
      EXPECT_GE(c.time_ps, last[c.channel]) << "channel " << c.channel << " at " << c.time_ps;
      last[c.channel] = std::max(last[c.channel], c.time_ps);
      const bool column = c.command == "RD" || c.command == "WR";
      EXPECT_EQ(c.column.empty(), !column) << c.command;
      EXPECT_EQ(c.row.empty(), c.command == "REF");
      if (c.command == "REF") {
        EXPECT_TRUE(c.request.empty());
      }
      if (column || c.command == "ACT") {
        EXPECT_FALSE(c.request.empty()) << c.command;
      }
    }
    EXPECT_GT(count["ACT"], 0u);
    EXPECT_EQ(count["ACT"], dram["activates"].get<uint64_t>()) << preset;
    EXPECT_EQ(count["PRE"], dram["precharges"].get<uint64_t>()) << preset;
    EXPECT_EQ(count["RD"], dram["bursts"].get<uint64_t>()) << preset;
    EXPECT_EQ(count["WR"], dram["write_bursts"].get<uint64_t>()) << preset;
    const uint64_t refreshes = dram.contains("refreshes") ? dram["refreshes"].get<uint64_t>() : 0;
    EXPECT_EQ(count["REF"], refreshes) << preset;
    EXPECT_EQ(refreshes > 0, preset == "lpddr4-3200");
    EXPECT_EQ(rows.size(), count["ACT"] + count["PRE"] + count["RD"] + count["WR"] + count["REF"]);
    EXPECT_FALSE(fs::exists(csv.string() + ".part"));
    fs::remove_all(out);
  }
}

// A window keeps the commands whose edge is in its accelerator cycles (1 GHz: time_ps / 1000);
// the trace changes no figure of the report.
TEST(Cli, DramCommandsKeepTheWindowAndChangeNoFigure) {
  const fs::path a = test::temp_dir("cli_dram_window_a"), b = test::temp_dir("cli_dram_window_b");
  ASSERT_EQ(run(city_run(a, "--quiet")).code, 0);
  const RunResult r = run(city_run(
      b, "--quiet --dram-commands " + (b / "c.csv").string() + " --trace-window 1000:1300"));
  ASSERT_EQ(r.code, 0) << r.err;
  const nlohmann::json rep = nlohmann::json::parse(slurp(b / "report.json"));
  EXPECT_EQ(without_host(nlohmann::json::parse(slurp(a / "report.json"))).dump(),
            without_host(rep).dump());
  const std::vector<Command> rows = read_commands(b / "c.csv", kHeader);
  for (const Command& c : rows) EXPECT_TRUE(c.time_ps >= 1000000 && c.time_ps < 1300000);
  EXPECT_GT(rows.size(), 0u);
  EXPECT_LT(rows.size(), rep["stats"]["dram"]["activates"].get<uint64_t>() +
                             rep["stats"]["dram"]["bursts"].get<uint64_t>());
  fs::remove_all(a);
  fs::remove_all(b);
}

TEST(Cli, DramCommandsRefuseWhatTheyCannotWriteOrASampledFrame) {
  const fs::path dir = test::temp_dir("cli_dram_bad");
  write(dir / "file", "x");
  expect_input_error(city_run(dir / "out", "--dram-commands " + (dir / "file" / "c.csv").string()),
                     {"--dram-commands", "cannot write there"});
  expect_input_error(
      city_run(dir / "out", "--sample 0.5 --dram-commands " + (dir / "c.csv").string()),
      {"--dram-commands", "sampled"});
  EXPECT_FALSE(fs::exists(dir / "out"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace rtsim::cli_test
