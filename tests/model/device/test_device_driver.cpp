// DeviceDriver (model/device/device_driver.h) on its own: its load pieces, and the ways onto a
// bus it takes (an initiator socket, or the forward path of any initiator: a multi-socket's).
#include "model/device/device_driver.h"
#include "model/sim/report.h"
#include "tests/model/memory/tlm_target_styles.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>
#include <tlm_utils/multi_passthrough_initiator_socket.h>
#include <tlm_utils/simple_initiator_socket.h>

#include <functional>

namespace rtsim::model {
namespace {

constexpr uint64_t kBytes = 10000;

std::vector<uint8_t> pattern() {
  std::vector<uint8_t> v(kBytes);
  for (uint64_t i = 0; i < kBytes; ++i) v[i] = uint8_t(i * 7 + 3);
  return v;
}

uint64_t pieces(uint64_t bytes, uint64_t piece) { return (bytes + piece - 1) / piece; }

// A thread with a simple socket and a multi-socket onto memories, running `script`.
class Loader : public sc_core::sc_module {
 public:
  tlm_utils::simple_initiator_socket<Loader> simple{"simple"};
  tlm_utils::multi_passthrough_initiator_socket<Loader> multi{"multi"};
  std::function<void(Loader&)> script;

  explicit Loader(sc_core::sc_module_name name) : sc_core::sc_module(name) {
    multi.register_nb_transport_bw(this, &Loader::nb_transport_bw);
    multi.register_invalidate_direct_mem_ptr(this, &Loader::invalidate);
    SC_THREAD(run);
  }

 private:
  SC_HAS_PROCESS(Loader);
  void run() { script(*this); }
  tlm::tlm_sync_enum nb_transport_bw(int, tlm::tlm_generic_payload&, tlm::tlm_phase&,
                                     sc_core::sc_time&) {
    return tlm::TLM_COMPLETED;
  }
  void invalidate(int, sc_dt::uint64, sc_dt::uint64) {}
};

TEST(DeviceDriver, LoadsInPiecesOfTheSizeItIsGivenOnAnyInitiator) {
  const sc_core::sc_time latency(10, sc_core::SC_NS);
  test::StyledMemory a("a", test::TargetStyle::kLooselyTimed, std::vector<uint8_t>(kBytes), latency,
                       sc_core::SC_ZERO_TIME);
  test::StyledMemory b("b", test::TargetStyle::kLooselyTimed, std::vector<uint8_t>(kBytes), latency,
                       sc_core::SC_ZERO_TIME);
  Loader loader("loader");
  loader.simple.bind(a.socket);
  loader.multi.bind(b.socket);
  const std::vector<uint8_t> data = pattern();
  std::vector<uint8_t> back_a, back_b;
  uint64_t calls_default = 0, calls_1000 = 0, calls_3000 = 0;
  loader.script = [&](Loader& l) {
    DeviceDriver on_socket(l.simple, 0);  // the socket, resolved at each access
    EXPECT_EQ(on_socket.piece_bytes(), DeviceDriver::kDefaultPieceBytes);
    on_socket.write(0, data.data(), kBytes);
    calls_default = a.counts().b_transports;
    on_socket.set_piece_bytes(1000);
    on_socket.write(0, data.data(), kBytes);
    calls_1000 = a.counts().b_transports - calls_default;
    back_a = on_socket.read(0, kBytes);
    {
      test::ExpectReports expected({kReportConfig});
      EXPECT_THROW(on_socket.set_piece_bytes(0), sc_core::sc_report);
    }
    EXPECT_EQ(on_socket.piece_bytes(), 1000u);    // a refused size leaves the last one
    DeviceDriver on_multi(*l.multi[0], 0, 3000);  // a multi-socket's forward path
    on_multi.write(0, data.data(), kBytes);
    calls_3000 = b.counts().b_transports;
    back_b = on_multi.read(0, kBytes);
  };
  test::simulate();
  EXPECT_EQ(calls_default, pieces(kBytes, DeviceDriver::kDefaultPieceBytes));
  EXPECT_EQ(calls_1000, pieces(kBytes, 1000));
  EXPECT_EQ(calls_3000, pieces(kBytes, 3000));
  EXPECT_EQ(b.counts().b_transports, 2 * pieces(kBytes, 3000));
  EXPECT_EQ(back_a, data);
  EXPECT_EQ(back_b, data);
}

}  // namespace
}  // namespace rtsim::model
