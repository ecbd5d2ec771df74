// The accelerator's TLM-2.0 boundary: a LineSource for the memory crossbar whose far side is a
// tlm_utils initiator socket (`socket`) speaking the approximately-timed base protocol to any
// TLM-2.0 memory target (our GDDR3 controller, model/memory/dram.h, or a platform's own memory).
//
// A line read or a posted line write becomes one generic payload from a pool (a memory manager),
// sent with BEGIN_REQ and a delay annotation = the time it arrives at memory minus now (delays
// are counted from the calendar's time, which is the kernel's at every accelerator edge). The
// port follows the base protocol with every legal target (IEEE 1666-2011, 15.2):
//  - time order: a platform's memory gets its requests in the order they reach memory (then the
//    order they were made), each sent when the calendar reaches that time, so every BEGIN_REQ
//    (b_transport call) is timed at or after the previous one, as a target that trusts annotations
//    (a PEQ) needs. A request made later may arrive earlier (a shorter latency ahead of it), so
//    sending as made would not do that. Our GDDR3 (PortTarget::kOwnCalendar) orders requests by
//    their arrival itself: each is sent as it is made, annotated with its arrival.
//  - requests: TLM_ACCEPTED holds further requests back until END_REQ (they wait here and go at
//    the first accelerator clock edge at or after it); END_REQ returned with TLM_UPDATED and a
//    delay, or sent with one, frees the request channel from that time on: the next BEGIN_REQ is
//    annotated not to arrive before it. A BEGIN_RESP stands for a missing END_REQ; a request
//    answered with its response in the call was taken at its own time.
//  - responses: a BEGIN_RESP on the backward path is answered TLM_UPDATED with END_RESP (taken
//    at once, at its time), so a target that waits for END_RESP before its next response goes
//    on; an early completion (BEGIN_REQ answered TLM_UPDATED with BEGIN_RESP) gets its END_RESP
//    on the forward path right after the call; TLM_COMPLETED needs nothing more.
// Responses are not acted on inside the target's call: each is queued and handed to the
// calendar at the first accelerator clock edge after its time (registered: a response exactly at
// an edge waits for the next one, since SystemC does not order the processes of one time and the
// figures would otherwise depend on whether the calendar had run yet), where the requester is told
// (FillListener::on_fill) in the order the requests were made (the order the responses came
// would be the order SystemC runs the target's processes of one time, which it does not fix). So
// the calendar's fixed order holds whatever the target's processes do. A response that comes from a
// block of this calendar while it runs, for this very edge, with none queued before it (our
// GDDR3's, model/memory/dram.h, a block of the accelerator's clock domain), is already in that
// order: it is handed over at once. A response's error status is rtsim/memory; a protocol answer
// the base protocol does not allow is rtsim/tlm.
//
// The data come with the response and only with it: a cache asks line_data() for the line being
// delivered and gets the payload's bytes (the caches keep what they hand on, model/memory/cache.h,
// so nothing is read outside a response and no target needs the debug transport).
//
// Statistics: reads, writes, latency_cycles (sum over reads, request to response), refused
// (requests sent after they were due: held back by the target).
#pragma once

#include "model/memory/dram_config.h"
#include "model/memory/line_source.h"
#include "model/memory/loosely_timed_path.h"
#include "model/sim/calendar.h"
#include "model/sim/stats_description.h"
#include "model/sim/stats_registry.h"
#include "model/sim/time.h"
#include "model/sim/trace_request.h"

#include <tlm_utils/simple_initiator_socket.h>
#include <systemc>
#include <tlm>

#include <cstdint>
#include <fstream>
#include <functional>
#include <memory>
#include <queue>
#include <string>
#include <vector>

namespace rtsim::model {

// What the port's socket is bound to.
enum class PortTarget {
  kPlatform,      // a platform's memory, nb_transport: requests in time order
  kLooselyTimed,  // a platform's b_transport-only memory (loosely_timed_path.h): the same
  kOwnCalendar,   // the built-in GDDR3, a block of this calendar that orders requests by their
                  // arrival itself: each is sent as it is made (its figures, the goldens)
};

struct MemoryPortStats {
  uint64_t reads = 0, writes = 0, refused = 0;
  uint64_t responses = 0;  // reads delivered and writes completed (progress; not reported)
  uint64_t latency_cycles = 0;
};

// Every reported MemoryPortStats field, once (model/sim/stats_description.h).
template <class V>
void describe_stats(V& v, const MemoryPortStats& s) {
  v.counter("reads", s.reads, "count", "line reads sent to memory");
  v.counter("writes", s.writes, "count", "line writes sent to memory");
  v.counter("refused", s.refused, "count",
            "requests held back until the memory took the previous one");
  v.counter("latency_cycles", s.latency_cycles, "cycles",
            "sum over reads of request-to-response cycles");
  v.formula(
      "avg_latency_cycles",
      [&s] { return s.reads ? double(s.latency_cycles) / double(s.reads) : 0.0; }, "cycles",
      "mean read latency at the memory boundary");
}

class MemoryPort : public sc_core::sc_module,
                   public LineSource,
                   public Calendar::Client,
                   public tlm::tlm_mm_interface {
 public:
  tlm_utils::simple_initiator_socket<MemoryPort> socket;

  // Transactions sent and not answered yet.
  // (From counts a statistics reset leaves alone: every request made, every response.)
  uint64_t in_flight() const { return requests_made_ - stats_.responses; }
  // Called when the last transaction in flight is answered (the accelerator's end of a frame
  // waits for its hit records' writes).
  void on_drained(std::function<void()> f) { drained_ = std::move(f); }

  // `line_bytes`: the size of every transaction; `mapping`: the memory's channel decode (the
  // crossbar's destination ports); `clock`: the accelerator's, on whose edges responses land;
  // `target`: what the socket is bound to.
  MemoryPort(sc_core::sc_module_name name, uint32_t line_bytes, const DramConfig& mapping,
             const Clock& clock, Calendar& calendar, PortTarget target = PortTarget::kPlatform);
  ~MemoryPort() override;

  Tick fetch_line(uint64_t line_addr, Tick now, FillListener* listener, uint64_t cookie) override;
  // A posted write of line_bytes from `data` (copied), by `initiator` (for the trace). With a
  // `listener`, its acknowledgement (memory has taken its last data beat) is told through
  // on_fill(line, cookie, when) at the accelerator clock edge after it, as a read's response is.
  void write_line(uint64_t line_addr, const uint8_t* data, Tick now, const std::string& initiator,
                  FillListener* listener = nullptr, uint64_t cookie = 0);
  const uint8_t* line_data(uint64_t line_addr) const override;
  uint32_t line_bytes() const override { return line_bytes_; }
  uint32_t port_of(uint64_t line_addr) const override { return mapping_.channel(line_addr); }
  uint32_t port_count() const override { return channels_; }

  // The trace's name for the requests of `listener` (default "?").
  void name_requester(const FillListener* listener, const std::string& name);
  // Opens a CSV of every transaction whose request reaches memory inside the window: request
  // cycle, initiator, address, bytes, R or W, latency in cycles. close_trace() moves it to its
  // name (rtsim/trace if that fails).
  void open_trace(const TraceRequest& request);
  void close_trace();

  const MemoryPortStats& stats() const { return stats_; }
  void register_stats(StatsRegistry& r, const std::string& prefix) const;

 private:
  struct Transaction;
  struct Queued {  // a request waiting for its time, or a response for its edge
    Tick when;
    uint64_t order;  // the request's: what falls at one time goes in request order
    Transaction* t;
    bool operator>(const Queued& o) const {
      return when != o.when ? when > o.when : order > o.order;
    }
  };
  using TimeOrder = std::priority_queue<Queued, std::vector<Queued>, std::greater<Queued>>;

  Transaction* make(uint64_t line, Tick arrival, bool write);
  void send(Transaction* t);  // now, or queued until it is due (send_due)
  void send_due();            // the requests due by now, while the request channel is free
  void send_now(Transaction* t, Tick due);
  tlm::tlm_sync_enum nb_transport_bw(tlm::tlm_generic_payload& p, tlm::tlm_phase& phase,
                                     sc_core::sc_time& delay);
  void invalidate_direct_mem_ptr(sc_dt::uint64 start, sc_dt::uint64 end);
  void warn_serialised();  // a request ended only by its response
  // A response arrived (at `at`); from the target's own call (nb_transport_bw), it may be handed
  // over at once (above).
  void response(Transaction* t, Tick at, bool may_deliver_now);
  void deliver(Transaction* t);  // tells its requester, now
  // On the calendar: deliver due responses, send held requests
  void activate() override;
  void free(tlm::tlm_generic_payload* p) override;  // the memory manager: back to the pool
  void trace(const Transaction& t, Tick done);
  [[noreturn]] void failed(const Transaction& t) const;

  uint32_t line_bytes_;
  uint32_t channels_;
  AddressMapping mapping_;
  Clock clock_;
  Calendar& calendar_;
  std::vector<std::unique_ptr<Transaction>> all_;  // the pool
  std::vector<Transaction*> free_;
  const Transaction* open_ = nullptr;  // the BEGIN_REQ awaiting its END_REQ
  Tick open_at_ = 0;                   // its BEGIN_REQ's time
  struct Window {
    Tick from = 0, until = 0;
  };
  Window taking_;        // the last request's BEGIN_REQ to END_REQ: the target taking it
  bool in_time_order_;   // a platform's memory: each request due at its arrival, not when made
  TimeOrder requests_;   // not sent yet: by the time they are due, then the order made
  TimeOrder responses_;  // by the edge they are handed over at
  uint64_t requests_made_ = 0;
  const Transaction* delivering_ = nullptr;  // the response being handed over
  bool sending_ = false;                     // inside a call of the target's nb_transport_fw
  bool warned_serialised_ = false;           // rtsim/serialised, once
  std::unique_ptr<LooselyTimedPath> lt_;     // to a loosely-timed memory
  std::vector<std::pair<const FillListener*, std::string>> names_;
  TraceRequest trace_request_;
  std::unique_ptr<std::ofstream> trace_;
  std::function<void()> drained_;
  MemoryPortStats stats_;
};

}  // namespace rtsim::model
