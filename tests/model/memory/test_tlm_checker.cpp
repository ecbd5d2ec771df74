// The TLM-2.0 base protocol checker (model/memory/tlm_checker.h) catches each rule it claims to,
// and lets a legal exchange through: scripted initiators and targets on both sides of a checker,
// one checker per scenario, all played at the start of one simulation.
#include "model/memory/tlm_checker.h"

#include "model/sim/report.h"
#include "tests/model/at_start.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>
#include <tlm_utils/simple_initiator_socket.h>
#include <tlm_utils/simple_target_socket.h>

#include <functional>
#include <map>
#include <memory>
#include <string>

namespace rtsim::model {
namespace {

using Answer = std::function<tlm::tlm_sync_enum(tlm::tlm_generic_payload&, tlm::tlm_phase&,
                                                sc_core::sc_time&)>;

tlm::tlm_sync_enum accepted(tlm::tlm_generic_payload&, tlm::tlm_phase&, sc_core::sc_time&) {
  return tlm::TLM_ACCEPTED;
}

// Both ends of a checker: `fw` and `bw` answer the calls that reach them.
struct Ends : sc_core::sc_module {
  tlm_utils::simple_initiator_socket<Ends> initiator;
  tlm_utils::simple_target_socket<Ends> target;
  TlmChecker checker;
  Answer fw = accepted, bw = accepted;

  explicit Ends(sc_core::sc_module_name n)
      : sc_module(n), initiator("initiator"), target("target"), checker("checker") {
    initiator.register_nb_transport_bw(this, &Ends::on_bw);
    target.register_nb_transport_fw(this, &Ends::on_fw);
    initiator.bind(checker.target_socket);
    checker.initiator_socket.bind(target);
  }
  tlm::tlm_sync_enum on_fw(tlm::tlm_generic_payload& p, tlm::tlm_phase& ph, sc_core::sc_time& t) {
    return fw(p, ph, t);
  }
  tlm::tlm_sync_enum on_bw(tlm::tlm_generic_payload& p, tlm::tlm_phase& ph, sc_core::sc_time& t) {
    return bw(p, ph, t);
  }
  // Initiator to target, and target to initiator, through the checker.
  tlm::tlm_sync_enum send(tlm::tlm_generic_payload& p, tlm::tlm_phase phase, double ns = 0) {
    sc_core::sc_time t(ns, sc_core::SC_NS);
    return initiator->nb_transport_fw(p, phase, t);
  }
  tlm::tlm_sync_enum answer(tlm::tlm_generic_payload& p, tlm::tlm_phase phase, double ns = 0) {
    sc_core::sc_time t(ns, sc_core::SC_NS);
    return target->nb_transport_bw(p, phase, t);
  }
};

struct Payload : tlm::tlm_generic_payload {
  explicit Payload(uint64_t addr) {
    set_read();
    set_address(addr);
    set_data_ptr(bytes);
    set_data_length(sizeof bytes);
    set_streaming_width(sizeof bytes);
    set_response_status(tlm::TLM_INCOMPLETE_RESPONSE);
  }
  unsigned char bytes[64] = {};
};

// Each scenario plays on its own checker; what it reported (empty: nothing).
struct Scenarios {
  using Play = std::function<void(Ends&)>;
  Scenarios() {
    add("legal", [](Ends& e) {
      Payload a(0), b(64);
      e.fw = [](tlm::tlm_generic_payload&, tlm::tlm_phase& ph, sc_core::sc_time& t) {
        ph = tlm::END_REQ;
        t += sc_core::sc_time(1, sc_core::SC_NS);
        return tlm::TLM_UPDATED;
      };
      e.send(a, tlm::BEGIN_REQ);
      e.send(b, tlm::BEGIN_REQ, 1);  // at the END_REQ's time: free again
      e.bw = [](tlm::tlm_generic_payload&, tlm::tlm_phase& ph, sc_core::sc_time&) {
        ph = tlm::END_RESP;
        return tlm::TLM_UPDATED;
      };
      a.set_response_status(tlm::TLM_OK_RESPONSE);
      b.set_response_status(tlm::TLM_OK_RESPONSE);
      e.answer(a, tlm::BEGIN_RESP, 5);
      e.answer(b, tlm::BEGIN_RESP, 6);
      open_after_legal = e.checker.open_transactions();
    });
    add("request_exclusion", [](Ends& e) {
      Payload a(0), b(64);
      e.send(a, tlm::BEGIN_REQ);
      e.send(b, tlm::BEGIN_REQ);
    });
    add("request_window", [](Ends& e) {
      Payload a(0), b(64);
      e.fw = [](tlm::tlm_generic_payload&, tlm::tlm_phase& ph, sc_core::sc_time& t) {
        ph = tlm::END_REQ;
        t += sc_core::sc_time(5, sc_core::SC_NS);
        return tlm::TLM_UPDATED;
      };
      e.send(a, tlm::BEGIN_REQ);
      e.send(b, tlm::BEGIN_REQ, 2);  // inside [0, 5 ns): the target is still taking `a`
    });
    add("payload_reused", [](Ends& e) {
      Payload a(0);
      e.fw = [](tlm::tlm_generic_payload&, tlm::tlm_phase& ph, sc_core::sc_time&) {
        ph = tlm::END_REQ;
        return tlm::TLM_UPDATED;
      };
      e.send(a, tlm::BEGIN_REQ);
      e.send(a, tlm::BEGIN_REQ);
    });
    add("incomplete_response", [](Ends& e) {
      Payload a(0);
      e.send(a, tlm::BEGIN_REQ);
      e.answer(a, tlm::BEGIN_RESP);
    });
    add("response_exclusion", [](Ends& e) {
      Payload a(0), b(64);
      e.fw = [](tlm::tlm_generic_payload&, tlm::tlm_phase& ph, sc_core::sc_time&) {
        ph = tlm::END_REQ;
        return tlm::TLM_UPDATED;
      };
      e.send(a, tlm::BEGIN_REQ);
      e.send(b, tlm::BEGIN_REQ);
      a.set_response_status(tlm::TLM_OK_RESPONSE);
      b.set_response_status(tlm::TLM_OK_RESPONSE);
      e.answer(a, tlm::BEGIN_RESP);  // TLM_ACCEPTED: END_RESP is still to come
      e.answer(b, tlm::BEGIN_RESP);
    });
    add("end_resp_first", [](Ends& e) {
      Payload a(0);
      e.send(a, tlm::BEGIN_REQ);
      e.send(a, tlm::END_RESP);
    });
    add("backwards_in_time", [](Ends& e) {
      Payload a(0);
      e.send(a, tlm::BEGIN_REQ, 10);
      e.answer(a, tlm::END_REQ, 3);
    });
  }
  void add(const std::string& name, Play play) {
    ends[name] = std::make_unique<Ends>(name.c_str());
    plays[name] = std::move(play);
  }
  void run() {
    test::ExpectReports expect({kReportTlm});
    for (auto& [name, play] : plays) {
      try {
        play(*ends[name]);
      } catch (const sc_core::sc_report& r) {
        reported[name] = r.get_msg();
      }
    }
  }
  std::map<std::string, std::unique_ptr<Ends>> ends;
  std::map<std::string, Play> plays;
  std::map<std::string, std::string> reported;
  static inline size_t open_after_legal = 99;
};

Scenarios& scenarios() {
  static Scenarios* s = [] {
    sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
    auto* made = new Scenarios;
    static test::AtStart start("start", [made] { made->run(); });
    test::simulate();
    return made;
  }();
  return *s;
}

void expect_reported(const std::string& scenario, const std::string& words) {
  const auto& r = scenarios().reported;
  ASSERT_TRUE(r.count(scenario)) << scenario << ": no violation reported";
  EXPECT_NE(r.at(scenario).find(words), std::string::npos) << r.at(scenario);
}

TEST(TlmChecker, LetsALegalExchangeThroughAndSeesItEnd) {
  EXPECT_EQ(scenarios().reported.count("legal"), 0u) << scenarios().reported["legal"];
  EXPECT_EQ(Scenarios::open_after_legal, 0u);
  EXPECT_EQ(scenarios().ends["legal"]->checker.stats().transactions, 2u);
}

TEST(TlmChecker, CatchesEachRule) {
  expect_reported("request_exclusion", "awaits its END_REQ");
  expect_reported("request_window", "previous request was being taken");
  expect_reported("payload_reused", "has not ended");
  expect_reported("incomplete_response", "TLM_INCOMPLETE_RESPONSE");
  expect_reported("response_exclusion", "awaits its END_RESP");
  expect_reported("end_resp_first", "END_RESP (the forward path) before BEGIN_RESP");
  expect_reported("backwards_in_time", "before the last phase");
}

}  // namespace
}  // namespace rtsim::model
