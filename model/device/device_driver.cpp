#include "model/device/device_driver.h"

#include "model/sim/report.h"

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>

namespace rtsim::model {

namespace {

uint32_t word(float f) {
  uint32_t w;
  std::memcpy(&w, &f, 4);
  return w;
}

}  // namespace

const char* status_error_name(uint32_t code) {
  switch (code) {
    case regs::kBadHeader: return "the image header's magic or version is wrong";
    case regs::kBadResolution: return "the resolution is 0 or above 16384";
    case regs::kBadCamera: return "the camera is degenerate";
    case regs::kTooManyLights: return "the scene has more than 32 lights";
    case regs::kBadPlacement:
      return "the image or the frame buffer is unaligned, overlapping or outside memory (the "
             "built-in one holds hw.dram.capacity_mib)";
    case regs::kBusyStart: return "a frame is running";
    case regs::kBusyReset: return "a reset while a frame runs";
    case regs::kBadStructure:
      return "the image's acceleration structure is not the one the traversal units walk "
             "(hw.structure: kdtree for a kd-tree image, bvh for any BVH node format)";
    case regs::kBadImage:
      return "the memory does not hold a readable image (an index outside its section, or a "
             "walk deeper than its stack or longer than its tree; statistics faults.*)";
    default: return "unknown error";
  }
}

DeviceDriver::DeviceDriver(tlm::tlm_fw_transport_if<>& bus, uint64_t register_base,
                           uint64_t piece_bytes)
    : bus_(&bus), register_base_(register_base) {
  set_piece_bytes(piece_bytes);
}

DeviceDriver::DeviceDriver(sc_core::sc_port_b<tlm::tlm_fw_transport_if<>>& socket,
                           uint64_t register_base, uint64_t piece_bytes)
    : socket_(&socket), register_base_(register_base) {
  set_piece_bytes(piece_bytes);
}

void DeviceDriver::set_piece_bytes(uint64_t bytes) {
  if (bytes == 0 || bytes > UINT32_MAX)
    return report_error(kReportConfig, "driver: a load piece of " + std::to_string(bytes) +
                                           " bytes (expected 1 to 4294967295)");
  piece_bytes_ = bytes;
}

std::vector<RegisterWrite> program_writes(const MemoryImage& image, const FrameSetup& s) {
  std::vector<RegisterWrite> w = {{regs::kImageBaseLo, uint32_t(s.image_base)},
                                  {regs::kImageBaseHi, uint32_t(s.image_base >> 32)},
                                  {regs::kFbBaseLo, uint32_t(s.fb_base)},
                                  {regs::kFbBaseHi, uint32_t(s.fb_base >> 32)},
                                  {regs::kWidth, uint32_t(s.width)},
                                  {regs::kHeight, uint32_t(s.height)},
                                  {regs::kCulling, s.lvb_culling ? 1u : 0u}};
  const Camera& c = s.camera;
  const float cam[regs::kCameraWords] = {c.eye.x, c.eye.y, c.eye.z, c.dir.x, c.dir.y,
                                         c.dir.z, c.up.x,  c.up.y,  c.up.z,  c.vfov_deg};
  for (uint32_t k = 0; k < regs::kCameraWords; ++k)
    w.push_back({regs::kCamera + 4 * k, word(cam[k])});
  for (uint32_t k = 0; k < regs::kHeaderBytes; k += 4)
    w.push_back({regs::kSceneHeader + k, image::load_u32(&image.bytes()[k])});
  const uint32_t lights = std::min(image.header().light_count, regs::kMaxLights);
  for (uint32_t l = 0; l < lights; ++l)
    w.push_back({regs::kLightSamples + 4 * l, image.light(l).samples});
  return w;
}

void DeviceDriver::transport(tlm::tlm_command cmd, uint64_t addr, uint8_t* data, uint64_t bytes) {
  tlm::tlm_generic_payload p;
  p.set_command(cmd);
  p.set_address(addr);
  p.set_data_ptr(data);
  p.set_data_length(uint32_t(bytes));
  p.set_streaming_width(uint32_t(bytes));
  p.set_response_status(tlm::TLM_INCOMPLETE_RESPONSE);
  sc_core::sc_time delay = sc_core::SC_ZERO_TIME;
  bus().b_transport(p, delay);
  if (p.is_response_error()) {
    char where[24];
    std::snprintf(where, sizeof where, "0x%llx", static_cast<unsigned long long>(addr));
    report_error(kReportDevice, std::string("driver: ") +
                                    (cmd == tlm::TLM_READ_COMMAND ? "read" : "write") + " of " +
                                    std::to_string(bytes) + " bytes at " + where + ": " +
                                    p.get_response_string());
  }
  if (delay > sc_core::SC_ZERO_TIME) sc_core::wait(delay);
}

void DeviceDriver::write(uint64_t addr, const uint8_t* data, uint64_t bytes) {
  std::vector<uint8_t> chunk;
  for (uint64_t at = 0; at < bytes; at += piece_bytes_) {
    const uint64_t n = std::min(piece_bytes_, bytes - at);
    chunk.assign(data + at, data + at + n);
    transport(tlm::TLM_WRITE_COMMAND, addr + at, chunk.data(), n);
  }
}

std::vector<uint8_t> DeviceDriver::read(uint64_t addr, uint64_t bytes) {
  std::vector<uint8_t> out(bytes);
  for (uint64_t at = 0; at < bytes; at += piece_bytes_)
    transport(tlm::TLM_READ_COMMAND, addr + at, out.data() + at,
              std::min(piece_bytes_, bytes - at));
  return out;
}

void DeviceDriver::write_register(uint32_t offset, uint32_t value) {
  uint8_t b[4];
  std::memcpy(b, &value, 4);
  transport(tlm::TLM_WRITE_COMMAND, register_base_ + offset, b, 4);
}

uint32_t DeviceDriver::read_register(uint32_t offset) {
  uint8_t b[4];
  transport(tlm::TLM_READ_COMMAND, register_base_ + offset, b, 4);
  return image::load_u32(b);
}

void DeviceDriver::load(const MemoryImage& image, uint64_t image_base) {
  write(image_base, image.bytes().data(), image.bytes().size());
}

void DeviceDriver::program(const MemoryImage& image, const FrameSetup& setup) {
  for (const RegisterWrite& w : program_writes(image, setup)) write_register(w.offset, w.value);
}

void DeviceDriver::start() {
  write_register(regs::kIrqEnable, 1);
  write_register(regs::kControl, regs::kStart);
  if (const uint32_t code = status_error())
    report_error(kReportDevice, "the accelerator refused the frame (STATUS error " +
                                    std::to_string(code) + ": " + status_error_name(code) + ")");
}

uint64_t DeviceDriver::finish() {
  write_register(regs::kIrqStatus, 1);
  return uint64_t(read_register(regs::kCyclesHi)) << 32 | read_register(regs::kCyclesLo);
}

}  // namespace rtsim::model
