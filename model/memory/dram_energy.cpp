#include "model/memory/dram_energy.h"

#include <fmt/format.h>

namespace rtsim::model {

void DramCurrents::validate() const {
  if (vdd == 0) return;
  const auto at_least = [](const char* key, double current, const char* base, double background) {
    if (current < background)
      throw std::invalid_argument(std::string(key) + ": expected at least " + base + " (" +
                                  fmt::format("{:g}", background) + " mA), got " +
                                  fmt::format("{:g}", current) +
                                  ": its energy over the background " + "would be negative");
  };
  at_least("idd4r", idd4r, "idd3n", idd3n);
  at_least("idd4w", idd4w, "idd3n", idd3n);
  at_least("idd5", idd5, "idd3n", idd3n);
}

void DramCurrents::validate_pair(uint32_t tRAS, uint32_t tRC) const {
  // TN-41-01's ACT+PRE pair, IDD0 x tRC - IDD3N x tRAS - IDD2N x (tRC - tRAS): DRAMPower's two
  // terms may each be negative (GDDR3's IDD0 is below its IDD3N), their sum may not.
  const double pair = idd0 * tRC - idd3n * tRAS - idd2n * (double(tRC) - double(tRAS));
  if (vdd != 0 && pair < 0)
    throw std::invalid_argument(
        "idd0: expected idd0 x tRC >= idd3n x tRAS + idd2n x (tRC - tRAS), got " +
        fmt::format("{:g}", idd0) +
        " mA: an activation's energy over the background would be "
        "negative");
}

DramEnergy dram_energy(const DramCurrents& idd, const DramEnergyTiming& t, const DramActivity& a) {
  // mA x V = mW, and mW x ns = pJ: each term is a power over the background for a time.
  const double devices = double(t.devices), ns = t.tck_ns;
  const auto over = [&](double current, double background, double cycles) {
    return idd.vdd * (current - background) * cycles * ns * devices;
  };
  DramEnergy e;
  e.activate = double(a.activates) * over(idd.idd0, idd.idd3n, t.tRAS);
  e.precharge = double(a.precharges) * over(idd.idd0, idd.idd2n, double(t.tRC) - double(t.tRAS));
  e.read = double(a.read_bursts) * over(idd.idd4r, idd.idd3n, t.burst_cycles);
  e.write = double(a.write_bursts) * over(idd.idd4w, idd.idd3n, t.burst_cycles);
  e.refresh = double(a.refreshes) * over(idd.idd5, idd.idd3n, t.tRFC);
  e.background =
      over(idd.idd3n, 0, double(a.active_cycles)) + over(idd.idd2n, 0, double(a.precharged_cycles));
  return e;
}

}  // namespace rtsim::model

namespace rtsim::model {

DramEnergy dram_energy(const DramPower& power, const DramEnergyTiming& timing,
                       const DramActivity& activity) {
  DramEnergyTiming t = timing;
  t.devices = power.devices;
  DramEnergy sum;
  for (const DramCurrents* rail : {&power.core, &power.aux, &power.io})
    sum += dram_energy(*rail, t, activity);
  return sum;
}

}  // namespace rtsim::model
