// A plain TLM-2.0 memory: every read or write is answered a fixed latency after it arrives, with
// no banks, rows or queues. It follows the approximately-timed base protocol as any target must:
// a request is taken at once (END_REQ), its response (BEGIN_RESP) goes from a payload event queue
// at arrival + latency, and a response the initiator accepts without completing waits for its
// END_RESP. transport_dbg reads and writes the bytes without time. Written for this example, as a
// stand-in for any memory model a platform brings (DRAMSys, a vendor model, one's own).
#pragma once

#include <tlm_utils/peq_with_get.h>
#include <tlm_utils/simple_target_socket.h>
#include <systemc>
#include <tlm>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <vector>

namespace example {

class FixedLatencyMemory : public sc_core::sc_module {
 public:
  tlm_utils::simple_target_socket<FixedLatencyMemory> socket;

  SC_HAS_PROCESS(FixedLatencyMemory);
  FixedLatencyMemory(sc_core::sc_module_name name, std::vector<uint8_t> bytes,
                     sc_core::sc_time latency)
      : sc_core::sc_module(name),
        socket("socket"),
        bytes_(std::move(bytes)),
        latency_(latency),
        due_("due") {
    socket.register_nb_transport_fw(this, &FixedLatencyMemory::nb_transport_fw);
    socket.register_transport_dbg(this, &FixedLatencyMemory::transport_dbg);
    SC_METHOD(respond);
    sensitive << due_.get_event();
    dont_initialize();
  }
  uint64_t reads = 0, writes = 0;
  const std::vector<uint8_t>& bytes() const { return bytes_; }  // as the writes left them

 private:
  bool in_range(const tlm::tlm_generic_payload& p) const {
    return p.get_address() <= bytes_.size() &&
           bytes_.size() - p.get_address() >= p.get_data_length();
  }

  tlm::tlm_sync_enum nb_transport_fw(tlm::tlm_generic_payload& p, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay) {
    if (phase == tlm::END_RESP) {  // the held-back responses may go now
      awaiting_end_ = false;
      due_.get_event().notify(sc_core::SC_ZERO_TIME);
      return tlm::TLM_COMPLETED;
    }
    if (phase != tlm::BEGIN_REQ) return tlm::TLM_COMPLETED;
    if (!in_range(p) || p.get_byte_enable_ptr()) {
      p.set_response_status(tlm::TLM_ADDRESS_ERROR_RESPONSE);
      return tlm::TLM_COMPLETED;
    }
    p.acquire();  // held until its response is sent
    due_.notify(p, delay + latency_);
    phase = tlm::END_REQ;
    return tlm::TLM_UPDATED;
  }

  // The due responses, one at a time: after one the initiator accepted without completing, the
  // rest wait for its END_RESP (the base protocol's response exclusion rule).
  void respond() {
    while (!awaiting_end_) {
      tlm::tlm_generic_payload* p = due_.get_next_transaction();
      if (!p) break;
      uint8_t* at = bytes_.data() + p->get_address();
      if (p->is_write()) {
        std::memcpy(at, p->get_data_ptr(), p->get_data_length());
        ++writes;
      } else {
        std::memcpy(p->get_data_ptr(), at, p->get_data_length());
        ++reads;
      }
      p->set_response_status(tlm::TLM_OK_RESPONSE);
      tlm::tlm_phase phase = tlm::BEGIN_RESP;
      sc_core::sc_time delay = sc_core::SC_ZERO_TIME;
      if (socket->nb_transport_bw(*p, phase, delay) == tlm::TLM_ACCEPTED) awaiting_end_ = true;
      p->release();
    }
  }

  unsigned transport_dbg(tlm::tlm_generic_payload& p) {
    if (!in_range(p)) return 0;
    uint8_t* at = bytes_.data() + p.get_address();
    if (p.is_write())
      std::memcpy(at, p.get_data_ptr(), p.get_data_length());
    else
      std::memcpy(p.get_data_ptr(), at, p.get_data_length());
    return p.get_data_length();
  }

  std::vector<uint8_t> bytes_;
  sc_core::sc_time latency_;
  tlm_utils::peq_with_get<tlm::tlm_generic_payload> due_;
  bool awaiting_end_ = false;
};

}  // namespace example
