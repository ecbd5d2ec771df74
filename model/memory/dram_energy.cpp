#include "model/memory/dram_energy.h"

namespace rtsim::model {

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
