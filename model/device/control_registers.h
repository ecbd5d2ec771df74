// The accelerator's register block (`<top>.registers`): the device face a platform programs. A
// loosely-timed TLM-2.0 target (b_transport, and transport_dbg for debuggers) holding the
// registers of model/device/register_map.h, an interrupt output, and a port to the frame engine
// it starts. A register access takes no time of its own: a START written at local time t (the
// initiator's time plus the annotated delay) starts the frame at the accelerator's first clock
// edge at or after t. It checks a program at the edge (STATUS error codes, never a report: a
// platform's bad value is the platform's to handle) and hands the engine a validated one.
#pragma once

#include "kernels/memory_image.h"
#include "model/device/register_map.h"
#include "model/sim/systemc_time.h"
#include "model/sim/time.h"
#include "scene/scene.h"

#include <tlm_utils/simple_target_socket.h>
#include <systemc>
#include <tlm>

#include <array>
#include <cstdint>
#include <vector>

namespace rtsim::model {

// A frame as the registers program it.
struct FrameProgram {
  uint64_t image_base = 0, fb_base = 0;
  image::Header header;                 // as in memory: section bases relative to the image's start
  std::vector<uint32_t> light_samples;  // per light, at least 1
  Camera camera;
  int width = 0, height = 0;
  bool lvb_culling = true;
};

// What the configuration fixes and the read-only registers show.
struct DeviceInfo {
  uint32_t record_stride = 64;
  uint32_t levels = 1;  // hit records per pixel (AcceleratorConfig::entries_per_pixel)
  uint32_t order = 1;   // regs::kOrder
  uint32_t tile = 8;
  uint64_t memory_bytes = 0;  // the built-in memory's size; 0: the platform's, not checked
  bool lvb_culling = true;    // CULLING's reset value
  bool bvh = false;           // the traversal units walk a BVH (else a kd-tree)
};

// The frames the register block starts: the accelerator's netlist.
class FrameEngine {
 public:
  virtual ~FrameEngine() = default;
  // Starts `program` at the first clock edge at or after `at` (the engine is idle).
  virtual void begin_frame(const FrameProgram& program, Tick at) = 0;
  // Back to the state after elaboration: caches emptied (the engine is idle).
  virtual void reset() = 0;
};

class ControlRegisters : public sc_core::sc_module {
 public:
  tlm_utils::simple_target_socket_optional<ControlRegisters> socket;  // may stay unbound
  // High while IRQ_ENABLE and IRQ_STATUS are both set; may stay unbound.
  sc_core::sc_port<sc_core::sc_signal_inout_if<bool>, 1, sc_core::SC_ZERO_OR_MORE_BOUND> irq;

  ControlRegisters(sc_core::sc_module_name name, const DeviceInfo& info, FrameEngine& engine);
  const char* kind() const override { return "rtsim_control_registers"; }

  // The engine's frame ended with `cycles` and STATUS error `error` (regs::kNoError, or what the
  // frame met: regs::kBadImage); the registers say so (and the interrupt rises) at model time
  // `at`.
  void frame_ended(uint64_t cycles, Tick at, uint32_t error = regs::kNoError);
  // Writes `value` at `offset` as a b_transport at model time `at` would.
  void write(uint32_t offset, uint32_t value, Tick at);
  uint32_t read(uint32_t offset) const;
  bool busy() const { return busy_; }

 private:
  SC_HAS_PROCESS(ControlRegisters);
  void end_of_elaboration() override { time_ = TimeBase::kernel(); }
  void b_transport(tlm::tlm_generic_payload& p, sc_core::sc_time& delay);
  unsigned int transport_dbg(tlm::tlm_generic_payload& p);
  // Checks a payload: TLM_OK_RESPONSE, or the status to answer with.
  tlm::tlm_response_status check(const tlm::tlm_generic_payload& p) const;
  void access(tlm::tlm_generic_payload& p, Tick at);
  void start(Tick at);
  void reset();
  uint32_t validate(FrameProgram& program) const;  // an error code; fills `program`
  FrameProgram program() const;
  void end_frame();  // at the frame's end time
  void update_irq();
  void drive_irq();

  DeviceInfo info_;
  FrameEngine& engine_;
  TimeBase time_;
  std::array<uint32_t, regs::kMapBytes / 4> reg_{};
  bool busy_ = false;
  uint64_t pending_cycles_ = 0;
  uint32_t pending_error_ = 0;
  sc_core::sc_event ended_, irq_changed_;
};

}  // namespace rtsim::model
