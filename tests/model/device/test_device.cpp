// The accelerator as a device: frames programmed through the registers, back to back in one
// elaboration, the interrupt, and the register block's answers to bad programs and accesses.
#include "model/accelerator.h"
#include "model/device/device_driver.h"
#include "model/units/ray_generator.h"
#include "tests/model/city_frame.h"

#include <gtest/gtest.h>
#include <tlm_utils/simple_initiator_socket.h>
#include <glm/geometric.hpp>

#include <cstdio>
#include <cstring>
#include <functional>

namespace rtsim::model {
namespace {

// A host: a thread that runs `script` with a driver on the registers and one on the memory.
class Host : public sc_core::sc_module {
 public:
  tlm_utils::simple_initiator_socket<Host> registers{"registers"};
  tlm_utils::simple_initiator_socket<Host> memory{"memory"};
  sc_core::sc_in<bool> irq{"irq"};
  using Script = std::function<void(Host&, DeviceDriver& regs, DeviceDriver& mem)>;

  Host(sc_core::sc_module_name name, Script script)
      : sc_core::sc_module(name), script_(std::move(script)) {
    SC_THREAD(run);
  }
  // The interrupt's rising edge (its level may not have fallen yet in this delta cycle).
  void wait_for_irq() { sc_core::wait(irq.posedge_event()); }

 private:
  SC_HAS_PROCESS(Host);
  void run() {
    DeviceDriver regs(registers, 0), mem(memory, 0);
    script_(*this, regs, mem);
  }
  Script script_;
};

// The device, a host and the interrupt between them.
struct Platform {
  Platform(const AcceleratorConfig& config, Host::Script script)
      : device("device", config), host("host", std::move(script)) {
    host.registers.bind(device.register_socket());
    host.memory.bind(device.memory_host_socket());
    device.irq.bind(irq);
    host.irq.bind(irq);
  }
  Accelerator device;
  Host host;
  sc_core::sc_signal<bool> irq{"irq"};
};

// Primary hit records in `records` (slot order) that differ from the reference's hits.
int wrong_records(const std::vector<uint8_t>& records, const TraceResult& ref,
                  const AcceleratorConfig& cfg, uint32_t stride) {
  const std::vector<uint32_t> pixel_at = issue_order(ref.width, ref.height, cfg.order, cfg.tile);
  int wrong = 0;
  for (size_t slot = 0; slot < pixel_at.size(); ++slot) {
    const uint8_t* r = &records[slot * stride];
    const PixelRecord& want = ref.pixels[pixel_at[slot]];
    const bool hit = (image::load_u32(r + 28) & 1u) != 0;
    float t;
    std::memcpy(&t, r + 52, 4);
    if (hit != (want.hit.tri != kNoHit) ||
        (hit && (image::load_u32(r + 48) != want.hit.tri || t != want.hit.t ||
                 image::load_u32(r + 24) != want.lvb)))
      ++wrong;
  }
  return wrong;
}

TEST(Device, FramesRunBackToBackThroughTheRegistersAndTheFirstIsTheConstructorsFrame) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const test::CityFrame city(160, 90);
  const AcceleratorConfig cfg;
  const Camera cameras[] = {city.scene.camera, test::turned(city.scene.camera, 20.f),
                            city.scene.camera};
  struct Frame {
    uint64_t cycles = 0;
    std::vector<uint8_t> records;
    bool irq_low_after = false;
  };
  std::vector<Frame> frames;
  uint32_t frames_register = 0, stride = 0;
  // The same frame programmed at construction, side by side (each accelerator has its own
  // calendar and memory: test_two_accelerators).
  Accelerator reference("by_constructor", cfg, *city.image, FrameJob{cameras[0], 160, 90});
  Platform p(cfg, [&](Host& host, DeviceDriver& regs, DeviceDriver& mem) {
    mem.load(*city.image, 0);
    FrameSetup setup;
    setup.fb_base = frame_buffer_after(0, city.image->bytes().size());
    setup.width = 160;
    setup.height = 90;
    for (const Camera& c : cameras) {
      setup.camera = c;
      regs.program(*city.image, setup);
      const uint64_t fb_bytes = regs.read_register(regs::kFbBytesLo);
      const std::vector<uint8_t> zeros(fb_bytes, 0);
      mem.write(setup.fb_base, zeros.data(), fb_bytes);  // only hits are written
      regs.start();
      EXPECT_EQ(regs.read_register(regs::kStatus) & regs::kBusy, regs::kBusy);
      host.wait_for_irq();
      Frame f;
      f.cycles = regs.finish();
      sc_core::wait(1, sc_core::SC_NS);  // the output follows IRQ_STATUS (deltas later)
      f.irq_low_after = !host.irq.read();
      stride = regs.read_register(regs::kRecordStride);
      f.records = mem.read(setup.fb_base, uint64_t(160 * 90) * stride);
      frames.push_back(std::move(f));
    }
    frames_register = regs.read_register(regs::kFrames);
  });
  test::simulate();
  for (size_t k = 0; k < frames.size(); ++k)  // docs/systemc-integration.md quotes them
    std::printf("frame %zu: %llu cycles\n", k + 1,
                static_cast<unsigned long long>(frames[k].cycles));
  ASSERT_EQ(frames.size(), 3u);
  EXPECT_EQ(frames_register, 3u);
  EXPECT_EQ(frames[0].cycles, reference.result().cycles_total);
  TracerOptions opt;
  opt.width = 160;
  opt.height = 90;
  opt.cull_with_lvb = true;
  const TraceResult turned_ref = ReferenceTracer(*city.image).trace_frame(cameras[1], opt);
  EXPECT_EQ(wrong_records(frames[0].records, city.reference, cfg, stride), 0);
  EXPECT_EQ(wrong_records(frames[1].records, turned_ref, cfg, stride), 0);
  EXPECT_EQ(wrong_records(frames[2].records, city.reference, cfg, stride), 0);
  EXPECT_GT(wrong_records(frames[1].records, city.reference, cfg, stride), 1000);  // it turned
  EXPECT_EQ(frames[2].records, frames[0].records);
  for (const Frame& f : frames) EXPECT_TRUE(f.irq_low_after);
  // The last frame's figures are the device's result, as for one frame.
  EXPECT_EQ(p.device.result().cycles_total, frames[2].cycles);
}

TEST(Device, RegistersRefuseABadProgramWithAnErrorCode) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const test::CityFrame city(16, 9);
  const AcceleratorConfig cfg;
  std::map<std::string, uint32_t> got;
  Platform p(cfg, [&](Host& host, DeviceDriver& regs, DeviceDriver& mem) {
    got["id"] = regs.read_register(regs::kId);
    got["version"] = regs.read_register(regs::kVersion);
    regs.write_register(regs::kRecordStride, 7);  // read-only: ignored
    got["stride"] = regs.read_register(regs::kRecordStride);
    auto start = [&] {
      regs.write_register(regs::kControl, regs::kStart);
      return regs.read_register(regs::kStatus) >> regs::kErrorShift;
    };
    got["no header"] = start();
    mem.load(*city.image, 0);
    FrameSetup s;
    s.fb_base = frame_buffer_after(0, city.image->bytes().size());
    s.camera = city.scene.camera;
    s.width = 0;
    s.height = 9;
    regs.program(*city.image, s);
    got["width 0"] = start();
    s.width = 16;
    s.camera.dir = Vec3(0.f);
    regs.program(*city.image, s);
    got["no direction"] = start();
    s.camera = city.scene.camera;
    s.fb_base = 0;
    regs.program(*city.image, s);
    got["overlap"] = start();
    s.fb_base = uint64_t(cfg.memory_dram().capacity_mib) << 20;
    regs.program(*city.image, s);
    got["outside"] = start();
    s.fb_base = frame_buffer_after(0, city.image->bytes().size());
    regs.program(*city.image, s);
    regs.write_register(regs::kIrqEnable, 0);  // polled, not interrupted
    got["good"] = start();
    got["busy start"] = start();
    regs.write_register(regs::kControl, regs::kReset);
    got["busy reset"] = regs.read_register(regs::kStatus) >> regs::kErrorShift;
    while (regs.read_register(regs::kStatus) & regs::kBusy) sc_core::wait(1, sc_core::SC_US);
    got["done"] = regs.read_register(regs::kStatus);
    got["irq status"] = regs.read_register(regs::kIrqStatus);
    got["irq"] = host.irq.read();
    regs.write_register(regs::kControl, regs::kReset);
    got["frames after reset"] = regs.read_register(regs::kFrames);
  });
  test::simulate();
  EXPECT_EQ(got["id"], regs::kIdValue);
  EXPECT_EQ(got["version"], regs::kVersionValue);
  EXPECT_EQ(got["stride"], 64u);
  EXPECT_EQ(got["no header"], regs::kBadHeader);
  EXPECT_EQ(got["width 0"], regs::kBadResolution);
  EXPECT_EQ(got["no direction"], regs::kBadCamera);
  EXPECT_EQ(got["overlap"], regs::kBadPlacement);
  EXPECT_EQ(got["outside"], regs::kBadPlacement);
  EXPECT_EQ(got["good"], regs::kNoError);
  EXPECT_EQ(got["busy start"], regs::kBusyStart);
  EXPECT_EQ(got["busy reset"], regs::kBusyReset);
  EXPECT_EQ(got["done"], regs::kDone);
  EXPECT_EQ(got["irq status"], 1u);
  EXPECT_EQ(got["irq"], 0u);  // IRQ_ENABLE was 0
  EXPECT_EQ(got["frames after reset"], 0u);
}

// Accesses the register block cannot serve get a TLM error status, which the driver reports.
TEST(Device, ABadRegisterAccessIsAnErrorResponse) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  std::vector<tlm::tlm_response_status> got;
  Platform p(AcceleratorConfig{}, [&](Host& host, DeviceDriver&, DeviceDriver&) {
    auto access = [&](uint64_t addr, uint32_t bytes) {
      uint8_t data[8] = {};
      tlm::tlm_generic_payload t;
      t.set_read();
      t.set_address(addr);
      t.set_data_ptr(data);
      t.set_data_length(bytes);
      t.set_streaming_width(bytes);
      sc_core::sc_time delay = sc_core::SC_ZERO_TIME;
      host.registers->b_transport(t, delay);
      got.push_back(t.get_response_status());
    };
    access(2, 4);                // unaligned
    access(regs::kMapBytes, 4);  // past the window
    access(0, 3);                // not whole registers
    access(regs::kCyclesLo, 8);  // a burst of two: fine
  });
  test::simulate();
  ASSERT_EQ(got.size(), 4u);
  EXPECT_EQ(got[0], tlm::TLM_ADDRESS_ERROR_RESPONSE);
  EXPECT_EQ(got[1], tlm::TLM_ADDRESS_ERROR_RESPONSE);
  EXPECT_EQ(got[2], tlm::TLM_BURST_ERROR_RESPONSE);
  EXPECT_EQ(got[3], tlm::TLM_OK_RESPONSE);
}

}  // namespace
}  // namespace rtsim::model
