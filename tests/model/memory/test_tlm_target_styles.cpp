// The accelerator on memories that answer in every way the TLM-2.0 base protocol allows
// (tests/model/memory/tlm_target_styles.h), each behind the model's protocol checker: the city at
// 160x90 renders with 0 pixels different from the reference tracer, the checker sees no
// violation and every transaction ends, and each target saw its own style's answers. All the
// accelerators run side by side in one simulation (SystemC elaborates once per process), and
// each alone in a child process: the same cycles.
#include "model/accelerator.h"
#include "tests/model/city_frame.h"
#include "tests/model/memory/tlm_target_styles.h"

#include <gtest/gtest.h>
#include <systemc>

#include <sys/wait.h>
#include <unistd.h>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <memory>
#include <vector>

namespace rtsim {
namespace {

using test::StyledMemory;
using test::TargetStyle;

constexpr int kW = 160, kH = 90;
constexpr double kLatencyNs = 40, kAcceptNs = 2;

struct Styled {
  const char* name;
  TargetStyle style;
  std::unique_ptr<model::Accelerator> accelerator;
  std::unique_ptr<StyledMemory> memory;
  model::AcceleratorResult result;
};

Styled build(const char* name, TargetStyle style, const test::CityFrame& city) {
  model::SimulationHooks hooks;
  hooks.tlm_checks = true;
  Styled s{name, style, nullptr, nullptr, {}};
  s.accelerator = std::make_unique<model::Accelerator>(
      name, model::AcceleratorConfig{}, *city.image, model::FrameJob{city.scene.camera, kW, kH},
      hooks, false);
  std::vector<uint8_t> bytes(city.image->bytes());
  bytes.resize(s.accelerator->memory_bytes(), 0);
  s.memory = std::make_unique<StyledMemory>(
      (std::string(name) + "_memory").c_str(), style, std::move(bytes),
      sc_core::sc_time(kLatencyNs, sc_core::SC_NS), sc_core::sc_time(kAcceptNs, sc_core::SC_NS));
  s.accelerator->memory_socket().bind(s.memory->socket);
  return s;
}

// The cycles of `style`'s accelerator simulated alone, in a child process.
uint64_t alone(const char* name, TargetStyle style, const test::CityFrame& city) {
  const std::filesystem::path out = test::temp_dir("alone") / "cycles";
  const pid_t pid = fork();
  if (pid == 0) {
    sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
    Styled s = build(name, style, city);
    sc_core::sc_start();
    std::ofstream(out) << s.accelerator->result().cycles_total;
    _exit(0);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  EXPECT_TRUE(WIFEXITED(status) && WEXITSTATUS(status) == 0);
  return std::stoull(test::slurp(out));
}

struct Run {
  Run() : city(kW, kH) {
    const std::pair<const char*, TargetStyle> styles[] = {
        {"accept_later", TargetStyle::kAcceptLater},
        {"end_req_delay", TargetStyle::kEndReqDelay},
        {"early_completion", TargetStyle::kEarlyCompletion},
        {"complete_at_once", TargetStyle::kCompleteAtOnce},
        {"arbiter", TargetStyle::kArbiter}};
    for (const auto& [name, style] : styles) cycles_alone.push_back(alone(name, style, city));
    sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
    for (const auto& [name, style] : styles) runs.push_back(build(name, style, city));
    test::simulate();
    for (Styled& s : runs) {
      s.result = s.accelerator->result();
      std::printf("%s: %llu cycles\n", s.name, (unsigned long long)s.result.cycles_total);
    }
  }
  const Styled& of(TargetStyle style) const {
    for (const Styled& s : runs)
      if (s.style == style) return s;
    throw std::logic_error("no such style");
  }
  test::CityFrame city;
  std::vector<Styled> runs;
  std::vector<uint64_t> cycles_alone;  // by style, each accelerator simulated alone
};

const Run& run() {
  static const Run r;
  return r;
}

// The frame is the reference's and the checker saw every transaction.
void expect_clean(TargetStyle style) {
  const Styled& s = run().of(style);
  EXPECT_EQ(run().city.mismatches(s.result.frame), 0) << s.name;
  const nlohmann::json& checker = s.result.stats["tlm_checker"];
  const nlohmann::json& port = s.result.stats["memory"]["port"];
  EXPECT_EQ(checker["transactions"].get<uint64_t>(),
            port["reads"].get<uint64_t>() + port["writes"].get<uint64_t>())
      << s.name;
  EXPECT_EQ(s.memory->counts().requests, checker["transactions"].get<uint64_t>()) << s.name;
  EXPECT_GT(port["writes"].get<uint64_t>(), 0u) << s.name;  // the hit records
}

// The target's processes and the other accelerators' do not change a figure: SystemC does not
// order the processes of one time, and the port takes nothing from a target at an edge's time.
TEST(TargetStyles, EachAcceleratorGetsTheCyclesItGetsAlone) {
  for (size_t i = 0; i < run().runs.size(); ++i)
    EXPECT_EQ(run().runs[i].result.cycles_total, run().cycles_alone[i]) << run().runs[i].name;
}

TEST(TargetStyles, AcceptLaterHoldsTheNextRequestUntilEndReq) {
  expect_clean(TargetStyle::kAcceptLater);
  const Styled& s = run().of(TargetStyle::kAcceptLater);
  EXPECT_GT(s.result.stats["memory"]["port"]["refused"].get<uint64_t>(), 0u);
  EXPECT_EQ(s.memory->counts().end_resp_returned, s.memory->counts().requests);
}

// The checker reports a BEGIN_REQ timed inside the previous request's BEGIN_REQ-to-END_REQ window.
TEST(TargetStyles, EndReqWithADelayIsHonoured) { expect_clean(TargetStyle::kEndReqDelay); }

TEST(TargetStyles, EarlyCompletionGetsItsEndResp) {
  expect_clean(TargetStyle::kEarlyCompletion);
  const StyledMemory::Counts& c = run().of(TargetStyle::kEarlyCompletion).memory->counts();
  EXPECT_GT(c.end_resp_forward, 0u);   // early completions, each ended on the forward path
  EXPECT_GT(c.end_resp_returned, 0u);  // and the other path, when a response was due
}

TEST(TargetStyles, CompletedAtOnceIsDeliveredAtItsTime) {
  expect_clean(TargetStyle::kCompleteAtOnce);
}

TEST(TargetStyles, AnArbiterThatWaitsForEndRespGoesOn) {
  expect_clean(TargetStyle::kArbiter);
  const StyledMemory::Counts& c = run().of(TargetStyle::kArbiter).memory->counts();
  EXPECT_EQ(c.completed_returned, 0u);
  EXPECT_EQ(c.end_resp_returned, c.requests);
}

}  // namespace
}  // namespace rtsim
