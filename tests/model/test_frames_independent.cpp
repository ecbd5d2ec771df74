// Frames do not leak into each other: on a memory with no state (fixed latency, no banks or
// rows), the same camera takes the same cycles every frame, whatever the idle time and the frames
// before it, and each frame's statistics are its own (issue 39).
#include "examples/tlm_memory/fixed_latency_memory.h"
#include "model/accelerator.h"
#include "model/device/device_driver.h"
#include "tests/model/city_frame.h"

#include <gtest/gtest.h>
#include <tlm_utils/simple_initiator_socket.h>
#include <glm/geometric.hpp>

#include <nlohmann/json.hpp>

#include <cmath>
#include <cstdio>
#include <functional>
#include <string>
#include <vector>

namespace rtsim::model {
namespace {

constexpr int kWidth = 160, kHeight = 90;

// A frame as the driver runs it: its camera, then the idle time before the next START. Another
// camera's frame has a frame buffer of its own, 8 MiB on: the culling unit reads the records
// back, and this driver has no way to memory to clear them (docs/systemc-integration.md, step 3).
struct Run {
  Camera camera;
  sc_core::sc_time idle_after;
  bool other_buffer = false;
};

// The driver: programs, starts and waits out each run in turn.
class Host : public sc_core::sc_module {
 public:
  tlm_utils::simple_initiator_socket<Host> registers{"registers"};
  sc_core::sc_in<bool> irq{"irq"};

  Host(sc_core::sc_module_name name, const test::CityFrame& city, std::vector<Run> runs)
      : sc_core::sc_module(name), city_(city), runs_(std::move(runs)) {
    SC_THREAD(run);
  }
  std::vector<uint64_t> cycles;
  std::function<void()> after_frame;  // called after each frame's interrupt, the device idle

 private:
  SC_HAS_PROCESS(Host);
  void run() {
    DeviceDriver regs(registers, 0);
    for (const Run& r : runs_) {
      FrameSetup setup = frame_after_image(*city_.image, r.camera, kWidth, kHeight, true);
      if (r.other_buffer) setup.fb_base += uint64_t(8) << 20;
      regs.program(*city_.image, setup);
      regs.start();
      sc_core::wait(irq.posedge_event());
      cycles.push_back(regs.finish());
      if (after_frame) after_frame();
      sc_core::wait(r.idle_after);
    }
  }
  const test::CityFrame& city_;
  std::vector<Run> runs_;
};

// The device on a fixed-latency memory that holds the image (and room for two frame buffers);
// its blocks named <name>_device, ... so that several share one simulation.
struct Platform {
  Platform(const test::CityFrame& city, std::vector<Run> runs, const std::string& name = "p",
           const SimulationHooks& hooks = {})
      : device((name + "_device").c_str(), AcceleratorConfig{}, hooks,
               MemoryTarget::kApproximatelyTimed),
        memory((name + "_memory").c_str(), with_frame_buffer(city),
               sc_core::sc_time(40, sc_core::SC_NS)),
        host((name + "_host").c_str(), city, std::move(runs)),
        irq((name + "_irq").c_str()) {
    device.memory_socket().bind(memory.socket);
    host.registers.bind(device.register_socket());
    device.irq.bind(irq);
    host.irq.bind(irq);
  }
  static std::vector<uint8_t> with_frame_buffer(const test::CityFrame& city) {
    std::vector<uint8_t> bytes = city.image->bytes();
    bytes.resize(frame_buffer_after(0, bytes.size()) + (uint64_t(16) << 20), 0);
    return bytes;
  }
  Accelerator device;
  example::FixedLatencyMemory memory;
  Host host;
  sc_core::sc_signal<bool> irq;
};

// The statistics of a frame: the named ones and the result's ray counts.
nlohmann::json figures(Accelerator& device) {
  const AcceleratorResult r = device.result();
  return {{"stats", r.stats},
          {"cycles", r.cycles_total},
          {"primary_rays", r.primary_rays},
          {"shadow_rays", r.shadow_rays},
          {"shadow_generated", r.shadow_generated},
          {"shadow_culled", r.shadow_culled}};
}

// The counters of `a` that differ from `b`'s (dotted names): what a failure names.
void differing(const nlohmann::json& a, const nlohmann::json& b, const std::string& at,
               std::vector<std::string>& out) {
  if (a.is_object() && b.is_object()) {
    for (const auto& [k, v] : a.items())
      differing(v, b.contains(k) ? b[k] : nlohmann::json(), at + "." + k, out);
  } else if (a != b) {
    out.push_back(at + ": " + a.dump() + " vs " + b.dump());
  }
}

// Before each frame began from the first frame's state (RayPool::begin_frame, RoundRobin::restart)
// frames 2 to 5 of the city's camera took 74,058, 74,106, 74,064 and 73,942 cycles here against
// frame 1's 73,488. One idle time is not a whole number of cycles; a frame of another camera
// comes between the last two.
TEST(Frames, TheSameCameraTakesTheSameCyclesEveryFrameWhateverCameBefore) {
  using sc_core::sc_time;
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const test::CityFrame city(kWidth, kHeight);
  const Camera same = city.scene.camera;
  Platform p(city, {{same, sc_core::SC_ZERO_TIME},
                    {same, sc_time(1, sc_core::SC_US)},
                    {same, sc_time(100, sc_core::SC_US)},
                    {same, sc_time(1.3, sc_core::SC_NS)},
                    {test::turned(same, 20.f), sc_core::SC_ZERO_TIME, true},
                    {same, sc_core::SC_ZERO_TIME}});
  test::simulate();
  for (size_t k = 0; k < p.host.cycles.size(); ++k)  // docs/systemc-integration.md quotes them
    std::printf("frame %zu: %llu cycles\n", k + 1,
                static_cast<unsigned long long>(p.host.cycles[k]));
  ASSERT_EQ(p.host.cycles.size(), 6u);
  EXPECT_NE(p.host.cycles[4], p.host.cycles[0]);  // the turned camera's frame
  for (size_t k : {1, 2, 3, 5}) EXPECT_EQ(p.host.cycles[k], p.host.cycles[0]) << "frame " << k + 1;
}

// Per-frame statistics (the default): frame 2's are those of a device that ran that one frame,
// although 1 us of idle time and a whole frame came before it. Accumulated ones add up.
TEST(Frames, EachFramesStatisticsAreItsOwnOrAddUpWhenAskedTo) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const test::CityFrame city(kWidth, kHeight);
  const Camera same = city.scene.camera;
  const sc_core::sc_time idle(1, sc_core::SC_US);
  Platform two(city, {{same, idle}, {same, idle}}, "two");
  Platform one(city, {{same, idle}}, "one");
  SimulationHooks all;
  all.statistics = SimulationHooks::Statistics::kAllFrames;
  Platform summed(city, {{same, idle}, {same, idle}}, "summed", all);
  std::vector<nlohmann::json> per_frame, one_frame, added;
  two.host.after_frame = [&] { per_frame.push_back(figures(two.device)); };
  one.host.after_frame = [&] { one_frame.push_back(figures(one.device)); };
  summed.host.after_frame = [&] { added.push_back(figures(summed.device)); };
  test::simulate();
  ASSERT_EQ(per_frame.size(), 2u);
  ASSERT_EQ(one_frame.size(), 1u);
  ASSERT_EQ(added.size(), 2u);
  std::vector<std::string> diff;
  differing(per_frame[1], one_frame[0], "frame 2", diff);
  std::string listed;
  for (const std::string& d : diff) listed += "\n  " + d;
  EXPECT_TRUE(diff.empty()) << diff.size() << " differ:" << listed;
  EXPECT_GT(per_frame[1]["primary_rays"].get<uint64_t>(), 0u);
  // Counted over both frames: twice the rays, the idle microsecond in the units' idle cycles.
  EXPECT_EQ(added[1]["primary_rays"], 2 * one_frame[0]["primary_rays"].get<uint64_t>());
  EXPECT_EQ(added[1]["stats"]["memory"]["port"]["reads"],
            2 * one_frame[0]["stats"]["memory"]["port"]["reads"].get<uint64_t>());
  EXPECT_GT(added[1]["stats"]["trv0"]["idle_cycles"].get<uint64_t>(),
            2 * one_frame[0]["stats"]["trv0"]["idle_cycles"].get<uint64_t>());
  EXPECT_EQ(added[1]["cycles"], one_frame[0]["cycles"]);  // cycles are the frame's either way
}

}  // namespace
}  // namespace rtsim::model
