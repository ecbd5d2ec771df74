// rtsim run with run.sample_grow (docs/sampling.md): a sampled frame whose 95% interval is wider
// than run.sample_target_pct runs again with the fraction its interval asks for. SystemC
// elaborates once per process, so each attempt is a sampled run of its own in a child process,
// in OUT/.sample-attempts/K; the first that meets the target, or the last of kSampleAttempts,
// becomes the run's output, its report.json listing every attempt. The attempts share the first's
// functional pass (OUT/.sample-attempts/pass.bin, testbench/sampling/sample_pass_file.h).
#include "common/error.h"
#include "reports/output_files.h"
#include "reports/plots.h"
#include "testbench/run/process_pool.h"
#include "testbench/run/run_command.h"
#include "testbench/run/sampled_frame.h"

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <filesystem>
#include <fstream>
#include <sstream>

namespace rtsim {

namespace fs = std::filesystem;

namespace {

std::string slurp(const fs::path& file) {
  std::ifstream in(file);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

// One attempt at `fraction` in `dir`: its report.json, or an error with the child's log.
nlohmann::json run_attempt(const fs::path& config, const fs::path& pass, const fs::path& dir,
                           double fraction, bool check) {
  fs::create_directories(dir);
  std::vector<std::string> cmd = {"run",
                                  "--config",
                                  config.string(),
                                  "--sample-pass",
                                  pass.string(),
                                  "--set",
                                  fmt::format("run.sample={}", fraction),
                                  "--set",
                                  "run.sample_grow=false",
                                  "--set",
                                  "run.plots=false",
                                  "--out",
                                  dir.string()};
  const fs::path log = dir / "log.txt";
  int status = 0;
  waitpid(spawn_self(cmd, log.string()), &status, 0);
  // Exit 1 is --check's verdict on a frame that ran: its report stands.
  const bool ran =
      WIFEXITED(status) && (WEXITSTATUS(status) == 0 || (check && WEXITSTATUS(status) == 1));
  // Bad input is the child's to name (exit 2): its message is ours.
  if (WIFEXITED(status) && WEXITSTATUS(status) == 2) {
    std::string message = slurp(log);
    const std::string prefix = "rtsim: error: ";
    if (message.rfind(prefix, 0) == 0) message.erase(0, prefix.size());
    while (!message.empty() && message.back() == '\n') message.pop_back();
    throw InputError(message);
  }
  if (!ran || !fs::exists(dir / "report.json"))
    throw std::runtime_error(
        fmt::format("run.sample_grow: the attempt at a fraction of {} ended "
                    "with {}:\n{}",
                    fraction, describe_exit(status), slurp(log)));
  return read_json((dir / "report.json").string());
}

}  // namespace

int run_grown(const RunArgs& args, const RunConfig& c, const nlohmann::json& config) {
  const fs::path out(args.out), work = out / ".sample-attempts";
  fs::remove_all(work);
  fs::create_directories(work);
  // The attempts' directory goes whatever happens (a failed attempt's log is in its error).
  struct Cleanup {
    fs::path dir;
    ~Cleanup() {
      std::error_code ec;
      fs::remove_all(dir, ec);
    }
  } cleanup{work};
  write_file_atomic((work / "config.json").string(), config.dump(2));
  nlohmann::json attempts = nlohmann::json::array(), report;
  std::vector<SampleAttempt> tried;
  double fraction = c.run.sample.fraction;
  fs::path last;
  for (int k = 0;; ++k) {
    last = work / std::to_string(k);
    // The first attempt keeps its functional pass for the others (it does not depend on the
    // sample): they simulate their windows alone.
    report = run_attempt(work / "config.json", work / "pass.bin", last, fraction, c.run.check);
    const nlohmann::json& s = report["sample"];
    attempts.push_back({{"fraction", fraction},
                        {"measured_units", s["measured_units"]},
                        {"ci95_pct", s["cycles_total"]["ci95_pct"]},
                        {"pass_reused", s["pass_reused"]},
                        {"host_seconds", report["host"]["seconds"]["total"]}});
    tried.push_back({fraction, s["cycles_total"]["ci95_pct"].get<double>(),
                     s["measured_units"].get<uint64_t>()});
    if (s["target_met"].get<bool>()) break;
    // The next fraction from every attempt's interval, not the last one's alone.
    report["sample"]["fraction_needed"] = fraction_for_target(tried, c.run.sample.target_pct);
    if (k + 1 == kSampleAttempts) break;
    fraction = report["sample"]["fraction_needed"].get<double>();
  }
  // The last attempt's outputs become the run's; config.json stays the settings as asked.
  for (const fs::directory_entry& e : fs::directory_iterator(last))
    if (e.path().filename() != "log.txt" && e.path().filename() != "config.json")
      fs::rename(e.path(), out / e.path().filename());
  report["sample"]["grow"] = true;
  report["sample"]["attempts"] = attempts;
  write_file_atomic((out / "report.json").string(), report.dump(2));
  write_file_atomic((out / "config.json").string(), config.dump(2));
  const std::string log = slurp(last / "log.txt");
  std::string plots_note;
  if (c.run.plots) plots_note = make_plots("run", out.string());
  if (!args.quiet) {
    // The attempt's summary, naming the run's directory, without its warning about the target.
    std::string text;
    std::istringstream lines(log);
    for (std::string line; std::getline(lines, line);)
      if (line.rfind("rtsim: warning: run.sample_target_pct", 0) != 0) text += line + "\n";
    for (size_t at; (at = text.find(last.string())) != std::string::npos;)
      text.replace(at, last.string().size(), out.string());
    fmt::print("{}  grown over {} attempt(s):", text, attempts.size());
    for (const nlohmann::json& a : attempts)
      fmt::print(" {:g} ({:.2f}%)", a["fraction"].get<double>(), a["ci95_pct"].get<double>());
    fmt::print("\n");
  }
  if (!plots_note.empty())
    fmt::print(stderr, "rtsim: warning: figures not written: {}\n", plots_note);
  if (!report["sample"]["target_met"].get<bool>())
    fmt::print(stderr,
               "rtsim: warning: run.sample_target_pct: the frame's 95% interval is {:.2f}%, "
               "wider than the target {:g}% after {} attempts; a fraction of about {:g} would "
               "meet it\n",
               attempts.back()["ci95_pct"].get<double>(), c.run.sample.target_pct, attempts.size(),
               report["sample"]["fraction_needed"].get<double>());
  const nlohmann::json& check = report["reference_check"];
  return check.is_object() && check.value("mismatched_pixels", uint64_t(0)) > 0 ? 1 : 0;
}

}  // namespace rtsim
