// The host side of the device, in one place: what a driver writes to put a scene image in memory
// and start a frame (docs/systemc-integration.md, "The register map"). `rtsim run`'s testbench,
// examples/platform and the tests drive the accelerator through it; a platform with a driver of
// its own can read it as the reference sequence.
#pragma once

#include "kernels/memory_image.h"
#include "model/device/register_map.h"
#include "scene/scene.h"

#include <systemc>
#include <tlm>

#include <cstdint>
#include <vector>

namespace rtsim::model {

struct RegisterWrite {
  uint32_t offset, value;
};

// A frame of an image already in memory.
struct FrameSetup {
  uint64_t image_base = 0;  // where the image lies (64-byte aligned)
  uint64_t fb_base = 0;     // where the hit records go (aligned to RECORD_STRIDE)
  Camera camera;
  int width = 0, height = 0;
  bool lvb_culling = true;
};

// The register writes that program `setup` over `image` (START not included): the placement,
// the resolution, the camera, the culling mode, the image's header and its lights' sample counts.
std::vector<RegisterWrite> program_writes(const MemoryImage& image, const FrameSetup& setup);

// The first 4 KiB boundary after an image at `image_base`: where rtsim run puts the frame buffer.
inline uint64_t frame_buffer_after(uint64_t image_base, uint64_t image_bytes) {
  return (image_base + image_bytes + 4095) / 4096 * 4096;
}

// One frame as rtsim run lays it out: the image at address 0, the frame buffer after it.
inline FrameSetup frame_after_image(const MemoryImage& image, const Camera& camera, int width,
                                    int height, bool lvb_culling) {
  FrameSetup s;
  s.fb_base = frame_buffer_after(0, image.bytes().size());
  s.camera = camera;
  s.width = width;
  s.height = height;
  s.lvb_culling = lvb_culling;
  return s;
}

// What STATUS error `code` (regs::Error) means, in words.
const char* status_error_name(uint32_t code);

// A driver over a forward path that reaches the memory and, at `register_base`, the
// accelerator's registers (through a router, or a path to the registers alone with base 0).
// Calls b_transport and waits out the delay each returns, so it runs in an SC_THREAD; an error
// response is an rtsim/device report naming the access. Memory is written and read in pieces of
// `piece_bytes` (default 64 KiB; a platform whose interconnect takes smaller bursts, or splits
// them across channels, sets its own).
class DeviceDriver {
 public:
  static constexpr uint64_t kDefaultPieceBytes = 64 * 1024;

  // Any initiator's forward path: `socket.operator->()` of a bound socket (simple, tagged or
  // multi), or a target's interface called directly.
  DeviceDriver(tlm::tlm_fw_transport_if<>& bus, uint64_t register_base,
               uint64_t piece_bytes = kDefaultPieceBytes);
  // An initiator socket (any kind: it is an sc_port of the forward interface), resolved at each
  // access, so the driver may be made before the socket is bound.
  DeviceDriver(sc_core::sc_port_b<tlm::tlm_fw_transport_if<>>& socket, uint64_t register_base,
               uint64_t piece_bytes = kDefaultPieceBytes);

  // The largest transaction write() and read() make to memory: more than 0, at most 4 GiB - 1
  // (a payload's length); else rtsim/config.
  void set_piece_bytes(uint64_t bytes);
  uint64_t piece_bytes() const { return piece_bytes_; }

  void write(uint64_t addr, const uint8_t* data, uint64_t bytes);  // in pieces
  std::vector<uint8_t> read(uint64_t addr, uint64_t bytes);
  void write_register(uint32_t offset, uint32_t value);
  uint32_t read_register(uint32_t offset);

  // Copies the image into memory at setup.image_base, then programs the frame.
  void load(const MemoryImage& image, uint64_t image_base);
  void program(const MemoryImage& image, const FrameSetup& setup);
  // START with the interrupt enabled; rtsim/device if the device refuses (its error code named).
  void start();
  // After the interrupt: clears it, returns the frame's cycles.
  uint64_t finish();
  // STATUS's error code (0: none); after a frame, regs::kBadImage if it met an unreadable image.
  uint32_t status_error() { return read_register(regs::kStatus) >> regs::kErrorShift; }

 private:
  void transport(tlm::tlm_command cmd, uint64_t addr, uint8_t* data, uint64_t bytes);
  tlm::tlm_fw_transport_if<>& bus() { return bus_ ? *bus_ : *socket_->operator->(); }

  tlm::tlm_fw_transport_if<>* bus_ = nullptr;
  sc_core::sc_port_b<tlm::tlm_fw_transport_if<>>* socket_ = nullptr;
  uint64_t register_base_;
  uint64_t piece_bytes_ = kDefaultPieceBytes;
};

}  // namespace rtsim::model
