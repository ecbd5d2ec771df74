#include "testbench/studies/sweep.h"

#include "common/error.h"
#include "common/utf8.h"
#include "reports/output_files.h"
#include "testbench/run/process_pool.h"
#include "testbench/run/resources.h"
#include "testbench/run/run_command.h"
#include "testbench/studies/slurm.h"
#include "testbench/studies/sweep_merge.h"
#include "testbench/studies/sweep_results.h"

#include <fmt/format.h>

#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <filesystem>
#include <fstream>

namespace fs = std::filesystem;

namespace rtsim {

namespace {

// One sweep at a time in a directory: an exclusive flock on DIR/.lock, held while the sweep runs
// and released by the kernel when its process ends, however it ends (a SIGKILL leaves no stale
// lock). Not inherited by the point processes.
class SweepLock {
 public:
  explicit SweepLock(const std::string& dir) {
    fs::create_directories(dir);
    const std::string file = (fs::path(dir) / ".lock").string();
    fd_ = ::open(file.c_str(), O_RDWR | O_CREAT | O_CLOEXEC, 0644);
    if (fd_ < 0) throw InputError(fmt::format("{}: cannot open the sweep's lock file", file));
    if (::flock(fd_, LOCK_EX | LOCK_NB) != 0) {
      ::close(fd_);
      throw InputError(fmt::format(
          "{}: another sweep is running in this directory; wait for it or use another --out", dir));
    }
  }
  ~SweepLock() { ::close(fd_); }
  SweepLock(const SweepLock&) = delete;
  SweepLock& operator=(const SweepLock&) = delete;

 private:
  int fd_ = -1;
};

// Runs one point in this process and writes its row.
int run_point(const SweepSpec& s, const std::string& dir, const SweepPoint& p) {
  const fs::path out = sweep_point_dir(dir, p);
  if (sweep_point_done(dir, p)) {
    fmt::print("{}: already done\n", p.id);
    return 0;
  }
  RunArgs args;
  args.sources.scene_file = p.scene_file;
  args.sources.hw_file = s.hw_of(p);
  args.sources.set = p.set;
  args.out = out.string();
  args.quiet = true;
  const int code = run_model(args);
  if (code != 0) return code;
  write_json(sweep_row_file(dir, p),
             sweep_row(s, p, read_json((out / output::kReportJson).string())));
  return 0;
}

const SweepPoint& point_by_index(const SweepSpec& s, int index, const std::string& where) {
  if (index < 0 || size_t(index) >= s.points.size())
    throw InputError(
        fmt::format("{}: --point {}: expected 0..{}", where, index, s.points.size() - 1));
  return s.points[size_t(index)];
}

// Each point runs as `rtsim sweep --out DIR --point I`, its output in the point's log.
pid_t spawn_point(const std::string& dir, const SweepPoint& p) {
  const fs::path out = sweep_point_dir(dir, p);
  fs::create_directories(out);
  return spawn_self({"sweep", "--out", dir, "--point", std::to_string(p.index)},
                    (out / output::kLogTxt).string());
}

// The last lines of a point's log, for a failure's record.
std::string log_tail(const fs::path& log, size_t lines = 5) {
  std::ifstream in(log);
  std::deque<std::string> tail;
  for (std::string line; std::getline(in, line);) {
    tail.push_back(line);
    if (tail.size() > lines) tail.pop_front();
  }
  std::string s;
  for (const std::string& l : tail) s += l + "\n";
  return utf8_lossy(s);  // it may quote input that is not UTF-8; it goes into JSON
}

std::string describe(const SweepPoint& p) {
  std::string s = fs::path(p.scene_file).stem().string();
  for (const auto& [k, v] : p.values.items())
    s += ", " + k + "=" + (v.is_string() ? v.get<std::string>() : v.dump());
  return s;
}

}  // namespace

int run_sweep_points(const SweepSpec& s, const std::string& dir, int jobs, bool plots,
                     double point_timeout) {
  const SweepLock lock(dir);
  claim_sweep_directory(s, dir);
  std::vector<const SweepPoint*> missing;
  for (const SweepPoint& p : s.points)
    if (!sweep_point_done(dir, p)) missing.push_back(&p);
  fmt::print("sweep {}: {} points, {} already done, running {} with {} job{}\n", s.name,
             s.points.size(), s.points.size() - missing.size(), missing.size(), jobs,
             jobs == 1 ? "" : "s");
  std::fflush(stdout);
  // Each point's memory check counts on its share of the machine (testbench/run/resources.h)
  const size_t at_once = std::min(missing.size(), size_t(std::max(jobs, 1)));
  setenv(kPointsAtOnceEnv, std::to_string(std::max<size_t>(at_once, 1)).c_str(), 1);
  size_t finished = 0, failed = 0;
  auto last_write = std::chrono::steady_clock::now();
  run_pool(
      missing.size(), jobs, [&](size_t i) { return spawn_point(dir, *missing[i]); },
      [&](size_t i, int status, double secs, bool timed_out) {
        const SweepPoint* p = missing[i];
        ++finished;
        const fs::path failure = sweep_failure_file(dir, *p);
        if (sweep_point_done(dir, *p)) {
          fs::remove(failure);
          fmt::print("[{}/{}] {} done in {:.1f} s ({})\n", finished, missing.size(), p->id, secs,
                     describe(*p));
        } else {
          ++failed;
          const std::string reason =
              timed_out ? fmt::format("timed out after {:.0f} s (point_timeout)", secs)
                        : describe_exit(status);
          const fs::path log = fs::path(sweep_point_dir(dir, *p)) / output::kLogTxt;
          write_json(failure.string(), {{"point", p->id},
                                        {"reason", reason},
                                        {"seconds", secs},
                                        {"log_tail", log_tail(log)}});
          fmt::print("[{}/{}] {} FAILED ({}; {}): see {}\n", finished, missing.size(), p->id,
                     reason, describe(*p), log.string());
        }
        std::fflush(stdout);
        // Keep results current while points finish, but do not reread every row after each point.
        if (std::chrono::steady_clock::now() - last_write > std::chrono::seconds(2)) {
          write_sweep_results(s, dir);
          last_write = std::chrono::steady_clock::now();
        }
      },
      point_timeout);
  const size_t rows = write_sweep_results(s, dir);
  if (const std::string why = write_sweep_reports(s, dir); !why.empty())
    fmt::print(stderr, "rtsim: warning: report not written: {}\n", why);
  std::string note;
  if (plots) note = draw_sweep_figures(s, dir);
  fmt::print("sweep {}: {} of {} points in {}/results.csv{}\n", s.name, rows, s.points.size(), dir,
             plots && note.empty() ? ", figures in plots/" : "");
  if (!note.empty()) fmt::print(stderr, "rtsim: warning: figures not written: {}\n", note);
  return failed || rows != s.points.size() ? 1 : 0;
}

int run_sweep_command(const SweepArgs& a) {
  if (!a.merge_dir.empty()) return merge_sweep(a.merge_dir, a.plots);
  if (a.out.empty()) throw InputError("--out DIR is required");
  if (a.point >= 0) {
    if (!a.file.empty() || !a.set.empty())
      throw InputError("--point runs a point of DIR/manifest.json: give only --out");
    const std::string file = sweep_manifest_file(a.out);
    if (!fs::exists(file))
      throw InputError(file + ": file not found (emit or start the sweep first)");
    const nlohmann::json manifest = read_json(file);
    const SweepSpec s = spec_from_manifest(manifest, file);
    check_sweep_inputs(manifest, a.out);
    return run_point(s, a.out, point_by_index(s, a.point, file));
  }
  if (a.file.empty())
    throw InputError("expected a sweep file (or --merge DIR, or --out DIR --point I)");
  const SweepSpec s = load_sweep(a.file, a.set, a.variants);
  if (a.emit == "slurm") return emit_slurm(s, a.out);
  return run_sweep_points(s, a.out, a.jobs, a.plots,
                          a.point_timeout > 0 ? a.point_timeout : s.point_timeout);
}

}  // namespace rtsim
