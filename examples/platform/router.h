// The platform's bus: one initiator (the driver) and two address windows, the memory from 0 and
// the accelerator's registers at `register_base`. Loosely timed: b_transport and transport_dbg are
// forwarded with the window's base taken off the address; an address in neither window is
// TLM_ADDRESS_ERROR_RESPONSE.
#pragma once

#include <tlm_utils/simple_initiator_socket.h>
#include <tlm_utils/simple_target_socket.h>
#include <systemc>
#include <tlm>

#include <cstdint>

namespace example {

class Router : public sc_core::sc_module {
 public:
  tlm_utils::simple_target_socket<Router> target{"target"};
  tlm_utils::simple_initiator_socket<Router> memory{"memory"};
  tlm_utils::simple_initiator_socket<Router> registers{"registers"};

  Router(sc_core::sc_module_name name, uint64_t memory_bytes, uint64_t register_base,
         uint64_t register_bytes)
      : sc_core::sc_module(name),
        memory_bytes_(memory_bytes),
        register_base_(register_base),
        register_bytes_(register_bytes) {
    target.register_b_transport(this, &Router::b_transport);
    target.register_transport_dbg(this, &Router::transport_dbg);
  }

 private:
  // The socket serving [address, address + length), with the address made local; null if none.
  tlm_utils::simple_initiator_socket<Router>* decode(tlm::tlm_generic_payload& p) {
    const uint64_t a = p.get_address(), n = p.get_data_length();
    if (a < memory_bytes_ && n <= memory_bytes_ - a) return &memory;
    if (a >= register_base_ && a - register_base_ < register_bytes_ &&
        n <= register_bytes_ - (a - register_base_)) {
      p.set_address(a - register_base_);
      return &registers;
    }
    return nullptr;
  }
  void b_transport(tlm::tlm_generic_payload& p, sc_core::sc_time& delay) {
    const uint64_t a = p.get_address();
    if (auto* s = decode(p))
      (*s)->b_transport(p, delay);
    else
      p.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
    p.set_address(a);
  }
  unsigned int transport_dbg(tlm::tlm_generic_payload& p) {
    const uint64_t a = p.get_address();
    auto* s = decode(p);
    const unsigned int n = s ? (*s)->transport_dbg(p) : 0;
    p.set_address(a);
    return n;
  }

  uint64_t memory_bytes_, register_base_, register_bytes_;
};

}  // namespace example
