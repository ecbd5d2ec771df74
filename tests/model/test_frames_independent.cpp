// Frames do not leak into each other: on a memory with no state (fixed latency, no banks or
// rows), the same camera run three times back to back takes the same cycles each time, whatever
// the idle time between frames, and writes the same records (issue 39).
#include "examples/tlm_memory/fixed_latency_memory.h"
#include "model/accelerator.h"
#include "model/device/device_driver.h"
#include "tests/model/city_frame.h"

#include <gtest/gtest.h>
#include <tlm_utils/simple_initiator_socket.h>

#include <vector>

namespace rtsim::model {
namespace {

constexpr int kWidth = 160, kHeight = 90;

// The driver: programs and starts a frame of the city's camera, waits `idle[k]` after frame k,
// and so on for every idle time, then one frame more.
class Host : public sc_core::sc_module {
 public:
  tlm_utils::simple_initiator_socket<Host> registers{"registers"};
  sc_core::sc_in<bool> irq{"irq"};

  Host(sc_core::sc_module_name name, const test::CityFrame& city,
       std::vector<sc_core::sc_time> idle)
      : sc_core::sc_module(name), city_(city), idle_(std::move(idle)) {
    SC_THREAD(run);
  }
  std::vector<uint64_t> cycles;

 private:
  SC_HAS_PROCESS(Host);
  void run() {
    DeviceDriver regs(registers, 0);
    const FrameSetup setup =
        frame_after_image(*city_.image, city_.scene.camera, kWidth, kHeight, true);
    for (size_t k = 0; k <= idle_.size(); ++k) {
      regs.program(*city_.image, setup);
      regs.start();
      sc_core::wait(irq.posedge_event());
      cycles.push_back(regs.finish());
      if (k < idle_.size()) sc_core::wait(idle_[k]);
    }
  }
  const test::CityFrame& city_;
  std::vector<sc_core::sc_time> idle_;
};

// The device on a fixed-latency memory that holds the image (and room for the frame buffer).
struct Platform {
  Platform(const test::CityFrame& city, std::vector<sc_core::sc_time> idle)
      : device("device", AcceleratorConfig{}, {}, MemoryTarget::kApproximatelyTimed),
        memory("memory", with_frame_buffer(city), sc_core::sc_time(40, sc_core::SC_NS)),
        host("host", city, std::move(idle)) {
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
// frames 2 to 5 took 74,058, 74,106, 74,064 and 73,942 cycles here against frame 1's 73,488. The
// last idle time is not a whole number of cycles.
TEST(Frames, TheSameCameraTakesTheSameCyclesEveryFrameWhateverTheIdleTime) {
  using sc_core::sc_time;
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const test::CityFrame city(kWidth, kHeight);
  Platform p(city, {sc_core::SC_ZERO_TIME, sc_time(1, sc_core::SC_US), sc_time(100, sc_core::SC_US),
                    sc_time(1.3, sc_core::SC_NS)});
  test::simulate();
  ASSERT_EQ(p.host.cycles.size(), 5u);
  for (size_t k = 1; k < p.host.cycles.size(); ++k)
    EXPECT_EQ(p.host.cycles[k], p.host.cycles[0]) << "frame " << k + 1;
}

}  // namespace
}  // namespace rtsim::model
