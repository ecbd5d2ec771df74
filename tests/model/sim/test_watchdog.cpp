// The watchdog stops a run that makes no progress and names what is stuck; a moving run is left
// alone. (One SystemC simulation per executable.)
#include "model/sim/watchdog.h"

#include "tests/test_util.h"

#include <gtest/gtest.h>

namespace rtsim::model {
namespace {

TEST(Watchdog, FiresAfterAnIntervalWithoutProgressAndDescribesTheState) {
  sc_core::sc_set_time_resolution(1, sc_core::SC_PS);
  const Clock clock(1.0);
  Calendar calendar("calendar");
  uint64_t progress = 0;
  int looks = 0;
  // Progress moves for the first three looks, then stalls with work pending.
  Watchdog dog(
      "dog", calendar, clock, 1000,
      [&] {
        ++looks;
        return looks <= 3 ? ++progress : progress;
      },
      [] { return true; }, [] { return std::string("fifo trv0.in (3)"); });
  dog.start();
  // The watchdog reports an error of type rtsim/watchdog, which the default action throws.
  std::string type;
  test::ExpectReports expected({kReportWatchdog});
  try {
    sc_core::sc_start();
  } catch (const sc_core::sc_report& r) {
    type = r.get_msg_type();
  }
  EXPECT_EQ(type, kReportWatchdog);
  ASSERT_TRUE(dog.fired());
  EXPECT_NE(dog.report().find("no progress for 1000 cycles"), std::string::npos) << dog.report();
  EXPECT_NE(dog.report().find("trv0.in (3)"), std::string::npos);
  EXPECT_EQ(looks, 4);
  EXPECT_EQ(sc_core::sc_time_stamp().value(), 4 * clock.cycles(1000))
      << "it looked every 1000 cycles";
}

}  // namespace
}  // namespace rtsim::model
