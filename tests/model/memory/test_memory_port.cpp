// The accelerator's TLM-2.0 initiator (model/memory/memory_port.h) against targets that use the
// base protocol's other answers: one that takes a request only later (TLM_ACCEPTED, then END_REQ),
// so the port must hold the following requests back, in order; and one that completes a request
// inside the call (TLM_COMPLETED), whose response must still reach the requester at a clock edge
// after the call, never inside fetch_line; and requests made out of the order they reach memory,
// which must reach it in time order. The bytes come with the responses.
#include "model/memory/memory_port.h"

#include "tests/test_util.h"

#include <gtest/gtest.h>
#include <tlm_utils/peq_with_get.h>
#include <tlm_utils/simple_target_socket.h>
#include <systemc>

#include <memory>
#include <vector>

namespace rtsim::model {
namespace {

constexpr Tick kNs = 1000;
constexpr uint32_t kLine = 64;

// Fills a read's bytes with the line address's low byte.
void fill(tlm::tlm_generic_payload& p) {
  for (uint32_t i = 0; i < p.get_data_length(); ++i)
    p.get_data_ptr()[i] = uint8_t(p.get_address() + i);
  p.set_response_status(tlm::TLM_OK_RESPONSE);
}

// END_REQ `accept` after BEGIN_REQ, BEGIN_RESP `latency` after END_REQ.
class AcceptLater : public sc_core::sc_module {
 public:
  tlm_utils::simple_target_socket<AcceptLater> socket;
  SC_HAS_PROCESS(AcceptLater);
  AcceptLater(sc_core::sc_module_name n, sc_core::sc_time accept, sc_core::sc_time latency)
      : sc_module(n),
        socket("socket"),
        accept_(accept),
        latency_(latency),
        accepting_("accepting"),
        done_("done") {
    socket.register_nb_transport_fw(this, &AcceptLater::fw);
    SC_METHOD(end_request);
    sensitive << accepting_.get_event();
    dont_initialize();
    SC_METHOD(respond);
    sensitive << done_.get_event();
    dont_initialize();
  }
  std::vector<Tick> begin_req;

 private:
  tlm::tlm_sync_enum fw(tlm::tlm_generic_payload& p, tlm::tlm_phase& phase,
                        sc_core::sc_time& delay) {
    if (phase != tlm::BEGIN_REQ) return tlm::TLM_COMPLETED;
    begin_req.push_back(Tick((sc_core::sc_time_stamp() + delay).value()));
    accepting_.notify(p, delay + accept_);
    return tlm::TLM_ACCEPTED;
  }
  void end_request() {
    while (tlm::tlm_generic_payload* p = accepting_.get_next_transaction()) {
      tlm::tlm_phase phase = tlm::END_REQ;
      sc_core::sc_time t = sc_core::SC_ZERO_TIME;
      socket->nb_transport_bw(*p, phase, t);
      done_.notify(*p, latency_);
    }
  }
  void respond() {
    while (tlm::tlm_generic_payload* p = done_.get_next_transaction()) {
      fill(*p);
      tlm::tlm_phase phase = tlm::BEGIN_RESP;
      sc_core::sc_time t = sc_core::SC_ZERO_TIME;
      socket->nb_transport_bw(*p, phase, t);
    }
  }
  sc_core::sc_time accept_, latency_;
  tlm_utils::peq_with_get<tlm::tlm_generic_payload> accepting_, done_;
};

// Completes every request inside the call, its response annotated `latency` later.
class CompleteAtOnce : public sc_core::sc_module {
 public:
  tlm_utils::simple_target_socket<CompleteAtOnce> socket;
  CompleteAtOnce(sc_core::sc_module_name n, sc_core::sc_time latency)
      : sc_module(n), socket("socket"), latency_(latency) {
    socket.register_nb_transport_fw(this, &CompleteAtOnce::fw);
  }
  std::vector<std::pair<Tick, uint64_t>> begin_req;  // time, line

 private:
  tlm::tlm_sync_enum fw(tlm::tlm_generic_payload& p, tlm::tlm_phase& phase,
                        sc_core::sc_time& delay) {
    if (phase != tlm::BEGIN_REQ) return tlm::TLM_COMPLETED;
    begin_req.push_back({Tick((sc_core::sc_time_stamp() + delay).value()), p.get_address()});
    fill(p);
    delay += latency_;
    return tlm::TLM_COMPLETED;
  }
  sc_core::sc_time latency_;
};

struct Fill {
  uint64_t line;
  Tick when, sim_time;
  uint8_t first_byte;
  bool inside_fetch;
};

class Recorder : public FillListener {
 public:
  explicit Recorder(const LineSource& port) : port_(port) {}
  void on_fill(uint64_t line, uint64_t, Tick when) override {
    fills.push_back(
        {line, when, Tick(sc_core::sc_time_stamp().value()), port_.line_data(line)[0], fetching});
  }
  std::vector<Fill> fills;
  bool fetching = false;

 private:
  const LineSource& port_;
};

// `reads` reads made at 0 ns on `port`, read k reaching memory at arrivals[k] (0 if none).
class Driver : public sc_core::sc_module {
 public:
  SC_HAS_PROCESS(Driver);
  Driver(sc_core::sc_module_name n, MemoryPort& port, Recorder& rec, int reads,
         std::vector<Tick> arrivals = {})
      : sc_module(n), port_(port), rec_(rec), reads_(reads), arrivals_(std::move(arrivals)) {
    SC_THREAD(run);
  }
  std::vector<Tick> returned;

 private:
  void run() {
    for (int k = 0; k < reads_; ++k) {
      rec_.fetching = true;
      const Tick at = arrivals_.empty() ? 0 : arrivals_[k];
      returned.push_back(port_.fetch_line(uint64_t(k + 1) * kLine, at, &rec_, uint64_t(k)));
      rec_.fetching = false;
    }
  }
  MemoryPort& port_;
  Recorder& rec_;
  int reads_;
  std::vector<Tick> arrivals_;
};

struct Scenario {
  Scenario() {
    sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
    DramConfig mapping = dram_preset("gddr3-gt200-1ghz");
    mapping.request_bytes = kLine;
    calendar = std::make_unique<Calendar>("calendar");
    slow_port = std::make_unique<MemoryPort>("slow_port", kLine, mapping, Clock(1.0), *calendar);
    slow = std::make_unique<AcceptLater>("slow", sc_core::sc_time(10, sc_core::SC_NS),
                                         sc_core::sc_time(50, sc_core::SC_NS));
    slow_port->socket.bind(slow->socket);
    slow_rec = std::make_unique<Recorder>(*slow_port);
    slow_driver = std::make_unique<Driver>("slow_driver", *slow_port, *slow_rec, 3);
    quick_port = std::make_unique<MemoryPort>("quick_port", kLine, mapping, Clock(1.0), *calendar);
    quick = std::make_unique<CompleteAtOnce>("quick", sc_core::sc_time(5.5, sc_core::SC_NS));
    quick_port->socket.bind(quick->socket);
    quick_rec = std::make_unique<Recorder>(*quick_port);
    quick_driver = std::make_unique<Driver>("quick_driver", *quick_port, *quick_rec, 2);
    late_port = std::make_unique<MemoryPort>("late_port", kLine, mapping, Clock(1.0), *calendar);
    late = std::make_unique<CompleteAtOnce>("late", sc_core::sc_time(5, sc_core::SC_NS));
    late_port->socket.bind(late->socket);
    late_rec = std::make_unique<Recorder>(*late_port);
    late_driver = std::make_unique<Driver>("late_driver", *late_port, *late_rec, 3,
                                           std::vector<Tick>{30 * kNs, 20 * kNs, 10 * kNs});
    test::simulate();
  }
  std::unique_ptr<Calendar> calendar;
  std::unique_ptr<MemoryPort> slow_port, quick_port, late_port;
  std::unique_ptr<AcceptLater> slow;
  std::unique_ptr<CompleteAtOnce> quick, late;
  std::unique_ptr<Recorder> slow_rec, quick_rec, late_rec;
  std::unique_ptr<Driver> slow_driver, quick_driver, late_driver;
};

Scenario& scenario() {
  static Scenario s;  // one elaboration per process
  return s;
}

TEST(MemoryPort, HoldsRequestsBackUntilTheTargetTakesThePreviousOne) {
  Scenario& s = scenario();
  EXPECT_EQ(s.slow_driver->returned, std::vector<Tick>(3, kUnknown));
  // Request k goes when request k - 1 is taken (10 ns each), its response 50 ns after it is taken,
  // exactly at an edge: the port takes it at the next one.
  EXPECT_EQ(s.slow->begin_req, (std::vector<Tick>{0, 10 * kNs, 20 * kNs}));
  ASSERT_EQ(s.slow_rec->fills.size(), 3u);
  for (int k = 0; k < 3; ++k) {
    const Fill& f = s.slow_rec->fills[k];
    EXPECT_EQ(f.line, uint64_t(k + 1) * kLine);
    EXPECT_EQ(f.when, Tick(61 + 10 * k) * kNs);
    EXPECT_EQ(f.sim_time, f.when);
    EXPECT_EQ(f.first_byte, uint8_t(f.line)) << "the bytes come with the response";
  }
  EXPECT_EQ(s.slow_port->stats().refused, 2u);
  EXPECT_EQ(s.slow_port->stats().responses, 3u);
}

TEST(MemoryPort, AResponseGivenInsideTheCallReachesTheRequesterAtTheNextEdgeAfterIt) {
  Scenario& s = scenario();
  ASSERT_EQ(s.quick_rec->fills.size(), 2u);
  for (const Fill& f : s.quick_rec->fills) {
    EXPECT_FALSE(f.inside_fetch);
    EXPECT_EQ(f.when, 6 * kNs);  // 5.5 ns, at the next 1 GHz edge
    EXPECT_EQ(f.sim_time, 6 * kNs);
    EXPECT_EQ(f.first_byte, uint8_t(f.line));
  }
  EXPECT_EQ(s.quick_port->stats().refused, 0u);
  EXPECT_EQ(s.quick_port->stats().latency_cycles, 12u);  // 6 cycles each
}

// Reads made in one order that reach memory in the other go in the order they reach it, each
// when it does (issue 39): a target that trusts annotations sees time go forward.
TEST(MemoryPort, RequestsGoInTheOrderTheyReachMemory) {
  Scenario& s = scenario();
  EXPECT_EQ(s.late->begin_req,
            (std::vector<std::pair<Tick, uint64_t>>{
                {10 * kNs, 3 * kLine}, {20 * kNs, 2 * kLine}, {30 * kNs, kLine}}));
  ASSERT_EQ(s.late_rec->fills.size(), 3u);
  EXPECT_EQ(s.late_rec->fills[0].line, 3 * kLine);
  EXPECT_EQ(s.late_rec->fills[0].when, 16 * kNs);  // 15 ns, at the next edge
  EXPECT_EQ(s.late_port->stats().refused, 0u);
}

}  // namespace
}  // namespace rtsim::model
