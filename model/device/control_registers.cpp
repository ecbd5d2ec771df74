#include "model/device/control_registers.h"

#include <glm/geometric.hpp>

#include <cmath>
#include <cstring>

namespace rtsim::model {

namespace {

constexpr int kMaxSide = 16384;

uint64_t wide(uint32_t lo, uint32_t hi) { return uint64_t(hi) << 32 | lo; }

float as_float(uint32_t w) {
  float f;
  std::memcpy(&f, &w, 4);
  return f;
}

bool finite(const Vec3& v) {
  return std::isfinite(v.x) && std::isfinite(v.y) && std::isfinite(v.z);
}

bool camera_ok(const Camera& c) {
  if (!finite(c.dir) || !finite(c.up) || !finite(c.eye) || !std::isfinite(c.vfov_deg)) return false;
  if (glm::length(c.dir) == 0.f || glm::length(c.up) == 0.f) return false;
  if (glm::length(glm::cross(glm::normalize(c.dir), glm::normalize(c.up))) < 1e-6f) return false;
  return c.vfov_deg > 0.f && c.vfov_deg < 180.f;
}

}  // namespace

ControlRegisters::ControlRegisters(sc_core::sc_module_name name, const DeviceInfo& info,
                                   FrameEngine& engine)
    : sc_core::sc_module(name), socket("socket"), irq("irq"), info_(info), engine_(engine) {
  socket.register_b_transport(this, &ControlRegisters::b_transport);
  socket.register_transport_dbg(this, &ControlRegisters::transport_dbg);
  reset();
  SC_METHOD(end_frame);
  sensitive << ended_;
  dont_initialize();
  SC_METHOD(drive_irq);  // the output's one writer, whoever's access changed it
  sensitive << irq_changed_;
  dont_initialize();
}

tlm::tlm_response_status ControlRegisters::check(const tlm::tlm_generic_payload& p) const {
  const uint64_t a = p.get_address(), n = p.get_data_length();
  if (p.get_byte_enable_ptr() || p.get_streaming_width() < n || n == 0 || n % 4 != 0)
    return tlm::TLM_BURST_ERROR_RESPONSE;
  if (a % 4 != 0 || a >= regs::kMapBytes || n > regs::kMapBytes - a)
    return tlm::TLM_ADDRESS_ERROR_RESPONSE;
  if (!p.is_read() && !p.is_write()) return tlm::TLM_COMMAND_ERROR_RESPONSE;
  return tlm::TLM_OK_RESPONSE;
}

void ControlRegisters::access(tlm::tlm_generic_payload& p, Tick at) {
  uint8_t* data = p.get_data_ptr();
  for (uint32_t k = 0; k < p.get_data_length(); k += 4) {
    const uint32_t offset = uint32_t(p.get_address()) + k;
    uint32_t w;
    if (p.is_read()) {
      w = read(offset);
      std::memcpy(data + k, &w, 4);
    } else {
      std::memcpy(&w, data + k, 4);
      write(offset, w, at);
    }
  }
  p.set_response_status(tlm::TLM_OK_RESPONSE);
}

void ControlRegisters::b_transport(tlm::tlm_generic_payload& p, sc_core::sc_time& delay) {
  const tlm::tlm_response_status status = check(p);
  if (status != tlm::TLM_OK_RESPONSE) return p.set_response_status(status);
  access(p, time_.now() + time_.to_tick(delay));
}

unsigned int ControlRegisters::transport_dbg(tlm::tlm_generic_payload& p) {
  if (check(p) != tlm::TLM_OK_RESPONSE || !p.is_read()) return 0;  // a debugger only reads
  access(p, time_.now());
  return p.get_data_length();
}

uint32_t ControlRegisters::read(uint32_t offset) const {
  switch (offset) {
    case regs::kId: return regs::kIdValue;
    case regs::kVersion: return regs::kVersionValue;
    case regs::kControl: return 0;
    case regs::kStatus: return reg_[offset / 4] | (busy_ ? regs::kBusy : 0u);
    default: return reg_[offset / 4];
  }
}

void ControlRegisters::write(uint32_t offset, uint32_t value, Tick at) {
  switch (offset) {
    case regs::kControl:
      if (value & regs::kReset) {
        if (busy_) {
          reg_[regs::kStatus / 4] = regs::kBusyReset << regs::kErrorShift;
          return;
        }
        engine_.reset();
        reset();
      }
      if (value & regs::kStart) start(at);
      return;
    case regs::kIrqStatus: reg_[offset / 4] &= ~value; return update_irq();
    case regs::kIrqEnable: reg_[offset / 4] = value & 1u; return update_irq();
    case regs::kImageBaseLo:
    case regs::kImageBaseHi:
    case regs::kFbBaseLo:
    case regs::kFbBaseHi:
    case regs::kWidth:
    case regs::kHeight:
    case regs::kCulling: reg_[offset / 4] = value; break;
    default:
      if (offset >= regs::kCamera && offset < regs::kCamera + 4 * regs::kCameraWords)
        reg_[offset / 4] = value;
      else if (offset >= regs::kSceneHeader)
        reg_[offset / 4] = value;
      return;  // the read-only ones ignore writes
  }
  // The frame buffer's size follows the resolution.
  const uint64_t bytes = regs::frame_buffer_bytes(reg_[regs::kWidth / 4], reg_[regs::kHeight / 4],
                                                  info_.levels, info_.record_stride);
  reg_[regs::kFbBytesLo / 4] = uint32_t(bytes);
  reg_[regs::kFbBytesHi / 4] = uint32_t(bytes >> 32);
}

void ControlRegisters::reset() {
  reg_.fill(0);
  reg_[regs::kCulling / 4] = info_.lvb_culling ? 1u : 0u;
  reg_[regs::kRecordStride / 4] = info_.record_stride;
  reg_[regs::kLevels / 4] = info_.levels;
  reg_[regs::kOrder / 4] = info_.order;
  reg_[regs::kTile / 4] = info_.tile;
  update_irq();
}

FrameProgram ControlRegisters::program() const {
  FrameProgram p;
  p.image_base = wide(reg_[regs::kImageBaseLo / 4], reg_[regs::kImageBaseHi / 4]);
  p.fb_base = wide(reg_[regs::kFbBaseLo / 4], reg_[regs::kFbBaseHi / 4]);
  uint8_t header[regs::kHeaderBytes];
  std::memcpy(header, &reg_[regs::kSceneHeader / 4], sizeof header);
  p.header = image::decode_header(header);
  for (uint32_t l = 0; l < std::min(p.header.light_count, regs::kMaxLights); ++l)
    p.light_samples.push_back(std::max(1u, reg_[regs::kLightSamples / 4 + l]));
  const uint32_t* c = &reg_[regs::kCamera / 4];
  p.camera.eye = Vec3(as_float(c[0]), as_float(c[1]), as_float(c[2]));
  p.camera.dir = Vec3(as_float(c[3]), as_float(c[4]), as_float(c[5]));
  p.camera.up = Vec3(as_float(c[6]), as_float(c[7]), as_float(c[8]));
  p.camera.vfov_deg = as_float(c[9]);
  p.width = int(std::min<uint32_t>(reg_[regs::kWidth / 4], kMaxSide + 1));
  p.height = int(std::min<uint32_t>(reg_[regs::kHeight / 4], kMaxSide + 1));
  p.lvb_culling = reg_[regs::kCulling / 4] & 1u;
  return p;
}

uint32_t ControlRegisters::validate(FrameProgram& p) const {
  p = program();
  if (p.header.magic != image::kMagic || p.header.version != image::kVersion ||
      !known_accel(p.header.accel))
    return regs::kBadHeader;
  if (is_bvh(p.header.accel) != info_.bvh) return regs::kBadStructure;
  if (p.width < 1 || p.height < 1 || p.width > kMaxSide || p.height > kMaxSide)
    return regs::kBadResolution;
  if (!camera_ok(p.camera)) return regs::kBadCamera;
  if (p.header.light_count > regs::kMaxLights) return regs::kTooManyLights;
  if (p.header.lights.count < p.header.light_count) return regs::kBadHeader;  // reads past it
  const uint64_t image_end = p.image_base + p.header.image_bytes;
  const uint64_t fb_end = p.fb_base + wide(reg_[regs::kFbBytesLo / 4], reg_[regs::kFbBytesHi / 4]);
  const bool aligned =
      p.image_base % image::kSectionAlign == 0 && p.fb_base % info_.record_stride == 0;
  const bool apart = image_end <= p.fb_base || fb_end <= p.image_base;
  // Section addresses are 32-bit: the image lies in the first 4 GiB.
  const bool inside = image_end <= (uint64_t(1) << 32) &&
                      (info_.memory_bytes == 0 ||
                       (image_end <= info_.memory_bytes && fb_end <= info_.memory_bytes));
  if (!aligned || !apart || !inside) return regs::kBadPlacement;
  return regs::kNoError;
}

void ControlRegisters::start(Tick at) {
  uint32_t& status = reg_[regs::kStatus / 4];
  if (busy_) {
    status = regs::kBusyStart << regs::kErrorShift;
    return;
  }
  FrameProgram p;
  if (const uint32_t error = validate(p)) {
    status = error << regs::kErrorShift;
    return;
  }
  status = 0;
  busy_ = true;
  engine_.begin_frame(p, at);
}

void ControlRegisters::frame_ended(uint64_t cycles, Tick at, uint32_t error) {
  pending_cycles_ = cycles;
  pending_error_ = error;
  ended_.notify(time_.delay_until(at));
}

void ControlRegisters::end_frame() {
  busy_ = false;
  reg_[regs::kStatus / 4] = regs::kDone | pending_error_ << regs::kErrorShift;
  reg_[regs::kCyclesLo / 4] = uint32_t(pending_cycles_);
  reg_[regs::kCyclesHi / 4] = uint32_t(pending_cycles_ >> 32);
  ++reg_[regs::kFrames / 4];
  reg_[regs::kIrqStatus / 4] |= 1u;
  update_irq();
}

void ControlRegisters::update_irq() { irq_changed_.notify(sc_core::SC_ZERO_TIME); }

void ControlRegisters::drive_irq() {
  if (irq.size() > 0)
    irq->write((reg_[regs::kIrqEnable / 4] & reg_[regs::kIrqStatus / 4] & 1u) != 0);
}

}  // namespace rtsim::model
