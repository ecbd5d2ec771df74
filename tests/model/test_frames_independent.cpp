// Frames do not leak into each other: on a memory with no state (fixed latency, no banks or
// rows), the same camera run three times back to back takes the same cycles each time, whatever
// the idle time between frames, and writes the same records (issue 39).
#include "examples/tlm_memory/fixed_latency_memory.h"
#include "model/accelerator.h"
#include "model/device/device_driver.h"
#include "tests/model/city_frame.h"

#include <gtest/gtest.h>
#include <tlm_utils/simple_initiator_socket.h>

#include <cstdio>
#include <vector>

namespace rtsim::model {
namespace {

constexpr int kWidth = 64, kHeight = 36;

// The driver: programs and starts `frames` frames of the city's camera, `idle` apart.
class Host : public sc_core::sc_module {
 public:
  tlm_utils::simple_initiator_socket<Host> registers{"registers"};
  sc_core::sc_in<bool> irq{"irq"};

  Host(sc_core::sc_module_name name, const test::CityFrame& city, int frames, sc_core::sc_time idle)
      : sc_core::sc_module(name), city_(city), frames_(frames), idle_(idle) {
    SC_THREAD(run);
  }
  std::vector<uint64_t> cycles;

 private:
  SC_HAS_PROCESS(Host);
  void run() {
    DeviceDriver regs(registers, 0);
    const FrameSetup setup =
        frame_after_image(*city_.image, city_.scene.camera, kWidth, kHeight, true);
    for (int k = 0; k < frames_; ++k) {
      regs.program(*city_.image, setup);
      regs.start();
      sc_core::wait(irq.posedge_event());
      cycles.push_back(regs.finish());
      sc_core::wait(idle_);
    }
  }
  const test::CityFrame& city_;
  int frames_;
  sc_core::sc_time idle_;
};

// The device on a fixed-latency memory that holds the image (and room for the frame buffer).
struct Platform {
  Platform(const test::CityFrame& city, int frames, sc_core::sc_time idle)
      : device("device", AcceleratorConfig{}, {}, MemoryTarget::kApproximatelyTimed),
        memory("memory", with_frame_buffer(city), sc_core::sc_time(40, sc_core::SC_NS)),
        host("host", city, frames, idle) {
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

TEST(Frames, TheSameCameraTakesTheSameCyclesEveryFrame) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const test::CityFrame city(kWidth, kHeight);
  Platform p(city, 3, sc_core::sc_time(1, sc_core::SC_US));
  test::simulate();
  ASSERT_EQ(p.host.cycles.size(), 3u);
  for (uint64_t c : p.host.cycles) std::printf("frame cycles %llu\n", (unsigned long long)c);
  EXPECT_EQ(p.host.cycles[1], p.host.cycles[0]);
  EXPECT_EQ(p.host.cycles[2], p.host.cycles[0]);
}

}  // namespace
}  // namespace rtsim::model
