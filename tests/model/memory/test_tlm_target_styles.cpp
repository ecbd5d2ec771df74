// The accelerator on memories that answer in every way the TLM-2.0 base protocol allows
// (tests/model/memory/tlm_target_styles.h), each behind the model's protocol checker: the city at
// 160x90 renders with 0 pixels different from the reference tracer, the checker sees no
// violation and every transaction ends, and each target saw its own style's answers. All the
// accelerators run side by side in one simulation (SystemC elaborates once per process), and
// each alone in a child process: the same cycles.
#include "model/accelerator.h"
#include "model/sim/report.h"
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

struct Style {
  const char* name;
  TargetStyle style;
  double accept_ns;
  bool loosely_timed;
};
const Style kStyles[] = {
    {"accept_later", TargetStyle::kAcceptLater, kAcceptNs, false},
    {"end_req_delay", TargetStyle::kEndReqDelay, kAcceptNs, false},
    {"early_completion", TargetStyle::kEarlyCompletion, kAcceptNs, false},
    {"complete_at_once", TargetStyle::kCompleteAtOnce, kAcceptNs, false},
    {"arbiter", TargetStyle::kArbiter, kAcceptNs, false},
    {"at_fixed", TargetStyle::kEndReqDelay, 0, false},  // END_REQ at once: the LT runs' twin
    {"lt", TargetStyle::kLooselyTimed, 0, true},
    {"lt_dmi", TargetStyle::kLooselyTimedDmi, 0, true},
    {"lt_waits", TargetStyle::kLooselyTimedWaits, 0, true},
    // The LT memory bound as an AT one: simple_target_socket's nb-to-b adapter ends each request
    // only with its response, so one transaction is in flight (rtsim/serialised says so)
    {"lt_adapter", TargetStyle::kLooselyTimed, 0, false}};

struct Styled {
  std::string name;
  std::unique_ptr<model::Accelerator> accelerator;
  std::unique_ptr<StyledMemory> memory;
  model::AcceleratorResult result;
};

Styled build(const Style& st, const test::CityFrame& city) {
  model::SimulationHooks hooks;
  hooks.tlm_checks = true;
  Styled s{st.name, nullptr, nullptr, {}};
  s.accelerator = std::make_unique<model::Accelerator>(
      st.name, model::AcceleratorConfig{}, *city.image, model::FrameJob{city.scene.camera, kW, kH},
      hooks,
      st.loosely_timed ? model::MemoryTarget::kLooselyTimed
                       : model::MemoryTarget::kApproximatelyTimed);
  std::vector<uint8_t> bytes(city.image->bytes());
  bytes.resize(s.accelerator->memory_bytes(), 0);
  s.memory = std::make_unique<StyledMemory>(
      (s.name + "_memory").c_str(), st.style, std::move(bytes),
      sc_core::sc_time(kLatencyNs, sc_core::SC_NS), sc_core::sc_time(st.accept_ns, sc_core::SC_NS));
  s.accelerator->memory_socket().bind(s.memory->socket);
  return s;
}

// The cycles of a style's accelerator simulated alone, in a child process, at a time resolution
// of `resolution_ps`.
uint64_t alone(const Style& st, const test::CityFrame& city, double resolution_ps = 1) {
  const std::filesystem::path out = test::temp_dir("alone") / "cycles";
  const pid_t pid = fork();
  if (pid == 0) {
    sc_core::sc_set_time_resolution(resolution_ps, sc_core::SC_PS);
    Styled s = build(st, city);
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
    test::ExpectReports serialised({model::kReportSerialised});  // lt_adapter's
    for (const Style& st : kStyles) {
      cycles_alone.push_back(alone(st, city));
      if (st.name == std::string("at_fixed") || st.name == std::string("lt_waits"))
        cycles_at_1ns.push_back(alone(st, city, 1000));
    }
    sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
    for (const Style& st : kStyles) runs.push_back(build(st, city));
    test::simulate();
    serialised_warnings = sc_core::sc_report_handler::get_count(model::kReportSerialised);
    for (Styled& s : runs) {
      s.result = s.accelerator->result();
      std::printf("%s: %llu cycles\n", s.name.c_str(), (unsigned long long)s.result.cycles_total);
    }
  }
  const Styled& of(const std::string& name) const {
    for (const Styled& s : runs)
      if (s.name == name) return s;
    throw std::logic_error("no style " + name);
  }
  test::CityFrame city;
  std::vector<Styled> runs;
  std::vector<uint64_t> cycles_alone;   // by style, each accelerator simulated alone
  std::vector<uint64_t> cycles_at_1ns;  // at_fixed and lt_waits alone at a 1 ns resolution
  int serialised_warnings = 0;          // rtsim/serialised reports in this process
};

const Run& run() {
  static const Run r;
  return r;
}

uint64_t stat(const Styled& s, const char* unit, const char* name) {
  return s.result.stats["memory"][unit][name].get<uint64_t>();
}

// The frame is the reference's and the checker saw every transaction.
void expect_clean(const std::string& name) {
  const Styled& s = run().of(name);
  EXPECT_EQ(run().city.mismatches(s.result.frame), 0) << s.name;
  const uint64_t checked = s.result.stats["tlm_checker"]["transactions"].get<uint64_t>();
  const uint64_t sent = stat(s, "port", "reads") + stat(s, "port", "writes");
  EXPECT_GT(stat(s, "port", "writes"), 0u) << s.name;  // the hit records
  const StyledMemory::Counts& c = s.memory->counts();
  if (s.memory->loosely_timed()) {  // a DMI access makes no call (the adapter makes no DMI)
    const bool lt_port = s.result.stats["memory"]["port"].contains("dmi_accesses");
    EXPECT_EQ(c.b_transports, checked) << s.name;
    EXPECT_EQ(c.b_transports + (lt_port ? stat(s, "port", "dmi_accesses") : 0), sent) << s.name;
  } else {
    EXPECT_EQ(c.requests, checked) << s.name;
    EXPECT_EQ(checked, sent) << s.name;
  }
}

// The target's processes and the other accelerators' do not change a figure: SystemC does not
// order the processes of one time, and the port registers what a target sends.
TEST(TargetStyles, EachAcceleratorGetsTheCyclesItGetsAlone) {
  for (size_t i = 0; i < run().runs.size(); ++i)
    EXPECT_EQ(run().runs[i].result.cycles_total, run().cycles_alone[i]) << run().runs[i].name;
}

// The model's times are picoseconds at any resolution that holds the clock, a platform's memory
// included (it used to read sc_time values as picoseconds).
TEST(TargetStyles, APlatformsMemoryGivesTheSameCyclesAtANanosecondResolution) {
  ASSERT_EQ(run().cycles_at_1ns.size(), 2u);
  EXPECT_EQ(run().cycles_at_1ns[0], run().of("at_fixed").result.cycles_total);
  EXPECT_EQ(run().cycles_at_1ns[1], run().of("lt_waits").result.cycles_total);
}

// Requests reach memory in time order (issue 39): every BEGIN_REQ (b_transport call) timed at or
// after the previous one and after the previous request's END_REQ, which a target that trusts
// annotations (a PEQ) needs; the checker, which checks in call order, would not see it.
TEST(TargetStyles, EveryTargetSeesItsRequestsInTimeOrder) {
  for (const Styled& s : run().runs) {
    const StyledMemory::Counts& c = s.memory->counts();
    std::printf("%s: %llu requests, %llu before the previous, %llu inside its window\n",
                s.name.c_str(), (unsigned long long)(c.requests + c.b_transports),
                (unsigned long long)c.before_previous, (unsigned long long)c.inside_window);
    EXPECT_GT(c.requests + c.b_transports, 0u) << s.name;
    EXPECT_EQ(c.before_previous, 0u) << s.name;
    EXPECT_EQ(c.inside_window, 0u) << s.name;
  }
}

TEST(TargetStyles, AcceptLaterHoldsTheNextRequestUntilEndReq) {
  expect_clean("accept_later");
  EXPECT_GT(stat(run().of("accept_later"), "port", "refused"), 0u);
  const StyledMemory::Counts& c = run().of("accept_later").memory->counts();
  EXPECT_EQ(c.end_resp_returned, c.requests);
}

// The checker reports a BEGIN_REQ timed inside the previous request's BEGIN_REQ-to-END_REQ window.
TEST(TargetStyles, EndReqWithADelayIsHonoured) {
  expect_clean("end_req_delay");
  expect_clean("at_fixed");
}

TEST(TargetStyles, EarlyCompletionGetsItsEndResp) {
  expect_clean("early_completion");
  const StyledMemory::Counts& c = run().of("early_completion").memory->counts();
  EXPECT_GT(c.end_resp_forward, 0u);   // early completions, each ended on the forward path
  EXPECT_GT(c.end_resp_returned, 0u);  // and the other path, when a response was due
}

TEST(TargetStyles, CompletedAtOnceIsDeliveredAtItsTime) { expect_clean("complete_at_once"); }

TEST(TargetStyles, AnArbiterThatWaitsForEndRespGoesOn) {
  expect_clean("arbiter");
  const StyledMemory::Counts& c = run().of("arbiter").memory->counts();
  EXPECT_EQ(c.completed_returned, 0u);
  EXPECT_EQ(c.end_resp_returned, c.requests);
}

// b_transport calls overlap (as many threads as calls in flight), so a loosely-timed memory is
// as fast as an approximately-timed one of the same latency: within 1%, the same pixels.
TEST(TargetStyles, ALooselyTimedMemoryRunsAtFullSpeed) {
  const uint64_t at = run().of("at_fixed").result.cycles_total;
  for (const char* name : {"lt", "lt_dmi", "lt_waits"}) {
    expect_clean(name);
    const Styled& s = run().of(name);
    EXPECT_NEAR(double(s.result.cycles_total), double(at), 0.01 * double(at)) << name;
    EXPECT_EQ(s.memory->counts().requests, 0u) << name;  // no nb_transport_fw
  }
  EXPECT_GT(stat(run().of("lt"), "port", "lt_threads"), 1u);
  EXPECT_GT(stat(run().of("lt_waits"), "port", "lt_threads"), 1u);
  EXPECT_EQ(stat(run().of("lt"), "port", "dmi_accesses"), 0u);
}

// An LT memory behind Accellera's adapter runs one access at a time, and the port says so once
// for the accelerator (not once per request); no other style is serialised.
TEST(TargetStyles, AnLtMemoryBehindTheAdapterIsSerialisedAndWarnedOnce) {
  expect_clean("lt_adapter");
  const uint64_t adapter = run().of("lt_adapter").result.cycles_total;
  const uint64_t lt = run().of("lt").result.cycles_total;
  std::printf("lt_adapter %llu / lt %llu = %.1fx\n", (unsigned long long)adapter,
              (unsigned long long)lt, double(adapter) / double(lt));
  EXPECT_GT(adapter, 10 * lt);
  EXPECT_EQ(run().serialised_warnings, 1);
}

TEST(TargetStyles, DmiReadsAndWritesStayTimed) {
  const Styled& s = run().of("lt_dmi");
  EXPECT_EQ(s.memory->counts().dmi_grants, 1u);
  EXPECT_GT(stat(s, "port", "dmi_accesses"), stat(s, "port", "lt_calls"));
  EXPECT_GT(stat(s, "port", "lt_calls"), 0u);  // the first, which brought the hint
}

}  // namespace
}  // namespace rtsim
