// The memory a frame needs, known before elaboration ends (memory_layout): the same bytes the
// device reports once programmed (FB_BYTES, RECORD_STRIDE) and the accelerator asks of its memory
// (memory_bytes()), for each number of reflection levels.
#include "model/accelerator.h"
#include "model/device/register_map.h"
#include "tests/model/city_frame.h"

#include <gtest/gtest.h>
#include <tlm_utils/simple_initiator_socket.h>

#include <memory>
#include <vector>

namespace rtsim::model {
namespace {

// Reads registers with the debug transport: no time passes.
struct RegisterProbe : sc_core::sc_module {
  tlm_utils::simple_initiator_socket<RegisterProbe> socket{"socket"};
  explicit RegisterProbe(sc_core::sc_module_name name) : sc_core::sc_module(name) {}
  uint32_t read(uint32_t offset) {
    uint32_t value = 0;
    tlm::tlm_generic_payload p;
    p.set_command(tlm::TLM_READ_COMMAND);
    p.set_address(offset);
    p.set_data_ptr(reinterpret_cast<unsigned char*>(&value));
    p.set_data_length(4);
    p.set_streaming_width(4);
    EXPECT_EQ(socket->transport_dbg(p), 4u);
    return value;
  }
};

TEST(MemoryLayout, IsWhatTheProgrammedDeviceReportsAndAsks) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const test::CityFrame city(96, 54);
  struct Case {
    AcceleratorConfig cfg;
    MemoryLayout layout;
    std::unique_ptr<Accelerator> device;
    std::unique_ptr<RegisterProbe> probe;
  };
  std::vector<Case> cases(3);
  for (int depth = 0; depth < 3; ++depth) {
    Case& c = cases[depth];
    c.cfg.reflection_depth = depth;
    // Before any module exists: from the configuration, the image and the resolution alone.
    c.layout = memory_layout(c.cfg, city.image->bytes().size(), 96, 54);
    c.device = std::make_unique<Accelerator>(("device" + std::to_string(depth)).c_str(), c.cfg,
                                             *city.image, FrameJob{city.scene.camera, 96, 54});
    c.probe = std::make_unique<RegisterProbe>(("probe" + std::to_string(depth)).c_str());
    c.probe->socket.bind(c.device->register_socket());
  }
  sc_core::sc_start(sc_core::SC_ZERO_TIME);  // the frames given at construction are programmed
  for (Case& c : cases) {
    SCOPED_TRACE("reflection_depth " + std::to_string(c.cfg.reflection_depth));
    const uint64_t fb_bytes =
        uint64_t(c.probe->read(regs::kFbBytesHi)) << 32 | c.probe->read(regs::kFbBytesLo);
    EXPECT_EQ(c.layout.fb_bytes, fb_bytes);
    EXPECT_EQ(c.layout.record_stride, c.probe->read(regs::kRecordStride));
    EXPECT_EQ(c.layout.fb_base,
              uint64_t(c.probe->read(regs::kFbBaseHi)) << 32 | c.probe->read(regs::kFbBaseLo));
    EXPECT_EQ(c.layout.image_bytes, city.image->bytes().size());
    EXPECT_GE(c.layout.fb_base, c.layout.image_bytes);
    EXPECT_EQ(c.layout.fb_base % 4096, 0u);
    EXPECT_EQ(c.layout.end(), c.device->memory_bytes());
  }
  // One more level, one more record per pixel.
  EXPECT_EQ(cases[2].layout.fb_bytes - cases[1].layout.fb_bytes, cases[1].layout.fb_bytes / 2);
}

}  // namespace
}  // namespace rtsim::model
