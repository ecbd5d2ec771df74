// Frames do not leak into each other: on a memory with no state (fixed latency, no banks or
// rows), the same camera takes the same cycles every frame, whatever the idle time and the frames
// before it (issue 39).
#include "examples/tlm_memory/fixed_latency_memory.h"
#include "model/accelerator.h"
#include "model/device/device_driver.h"
#include "tests/model/city_frame.h"

#include <gtest/gtest.h>
#include <tlm_utils/simple_initiator_socket.h>
#include <glm/geometric.hpp>

#include <cmath>

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
      sc_core::wait(r.idle_after);
    }
  }
  const test::CityFrame& city_;
  std::vector<Run> runs_;
};

// The device on a fixed-latency memory that holds the image (and room for two frame buffers).
struct Platform {
  Platform(const test::CityFrame& city, std::vector<Run> runs)
      : device("device", AcceleratorConfig{}, {}, MemoryTarget::kApproximatelyTimed),
        memory("memory", with_frame_buffer(city), sc_core::sc_time(40, sc_core::SC_NS)),
        host("host", city, std::move(runs)) {
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
  sc_core::sc_signal<bool> irq{"irq"};
};

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
  ASSERT_EQ(p.host.cycles.size(), 6u);
  EXPECT_NE(p.host.cycles[4], p.host.cycles[0]);  // the turned camera's frame
  for (size_t k : {1, 2, 3, 5}) EXPECT_EQ(p.host.cycles[k], p.host.cycles[0]) << "frame " << k + 1;
}

}  // namespace
}  // namespace rtsim::model
