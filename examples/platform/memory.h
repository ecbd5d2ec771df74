// One memory for the whole platform: a byte array behind a multi-initiator target socket (the
// driver through the router, the accelerator's memory port directly). Loosely timed: b_transport
// answers any access inside the array after a fixed latency (added to the annotated delay) and
// grants no DMI; the accelerator keeps many calls in flight (MemoryTarget::kLooselyTimed).
#pragma once

#include <tlm_utils/multi_passthrough_target_socket.h>
#include <systemc>
#include <tlm>

#include <cstdint>
#include <cstring>
#include <vector>

namespace example {

class Memory : public sc_core::sc_module {
 public:
  tlm_utils::multi_passthrough_target_socket<Memory> socket{"socket"};

  Memory(sc_core::sc_module_name name, uint64_t bytes, sc_core::sc_time latency)
      : sc_core::sc_module(name), bytes_(bytes, 0), latency_(latency) {
    socket.register_b_transport(this, &Memory::b_transport);
    socket.register_transport_dbg(this, &Memory::transport_dbg);
  }
  uint64_t size() const { return bytes_.size(); }

 private:
  bool access(tlm::tlm_generic_payload& p) {
    const uint64_t a = p.get_address(), n = p.get_data_length();
    if (p.get_byte_enable_ptr() || p.get_streaming_width() < n) {
      p.set_response_status(tlm::TLM_BURST_ERROR_RESPONSE);
      return false;
    }
    if (a > bytes_.size() || n > bytes_.size() - a) {
      p.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
      return false;
    }
    if (p.is_write())
      std::memcpy(&bytes_[a], p.get_data_ptr(), n);
    else if (p.is_read())
      std::memcpy(p.get_data_ptr(), &bytes_[a], n);
    p.set_response_status(tlm::TLM_OK_RESPONSE);
    return true;
  }
  void b_transport(int, tlm::tlm_generic_payload& p, sc_core::sc_time& delay) {
    if (access(p)) delay += latency_;
  }
  unsigned int transport_dbg(int, tlm::tlm_generic_payload& p) {
    return access(p) ? p.get_data_length() : 0;
  }

  std::vector<uint8_t> bytes_;
  sc_core::sc_time latency_;
};

}  // namespace example
