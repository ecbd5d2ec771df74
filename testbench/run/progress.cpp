#include "testbench/run/progress.h"

#include <fmt/format.h>

#include <unistd.h>
#include <algorithm>
#include <cstdio>

namespace rtsim {

ProgressLine::ProgressLine(std::string label, bool enabled)
    : label_(std::move(label)),
      enabled_(enabled && isatty(fileno(stderr))),
      start_(std::chrono::steady_clock::now()),
      phase_start_(start_),
      last_draw_(start_) {}

void ProgressLine::update(const model::Progress& p) {
  if (!enabled_) return;
  const auto now = std::chrono::steady_clock::now();
  if (p.phase != phase_) {
    phase_ = p.phase;
    phase_start_ = now;
  }
  if (now - last_draw_ < std::chrono::milliseconds(500)) return;
  last_draw_ = now;
  // The phase's share done: primary rays retired, or pixels the culling unit has passed scaled by
  // the share of their shadow rays already back.
  double done = p.phase == 1 ? double(p.primaries_retired) / double(std::max<uint64_t>(p.pixels, 1))
                             : p.culling_scanned * double(p.shadows_retired) /
                                   double(std::max<uint64_t>(p.shadows_generated, 1));
  done = std::clamp(done, 0.0, 1.0);
  const double phase_s = std::chrono::duration<double>(now - phase_start_).count();
  const double host_s = std::chrono::duration<double>(now - start_).count();
  const std::string eta = done > 0.01 ? fmt::format("{:.0f} s", phase_s * (1 - done) / done) : "?";
  fmt::print(
      stderr,
      "\r\033[K{}: phase {} ({}) {:.0f}% | rays retired {} | {} cycles | {:.0f} s | phase ETA {}",
      label_, p.phase, p.phase == 1 ? "primary" : "shadow", 100 * done,
      p.primaries_retired + p.shadows_retired, p.cycle, host_s, eta);
  std::fflush(stderr);
  drawn_ = true;
}

void ProgressLine::finish() {
  if (drawn_) fmt::print(stderr, "\r\033[K");
  drawn_ = false;
}

}  // namespace rtsim
