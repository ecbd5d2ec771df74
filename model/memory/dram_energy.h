// A DRAM's energy from its command stream, by the Micron method (TN-41-01 "Calculating Memory
// System Power for DDR3", as DRAMPower v4.1 codes it in MemoryPowerModel.cc): the background is
// charged every cycle by the state the banks are in (IDD3N with a row open, IDD2N with all banks
// precharged), and each command adds its increment over the background:
//   ACT   VDD x (IDD0 - IDD3N) x tRAS          PRE   VDD x (IDD0 - IDD2N) x (tRC - tRAS)
//   RD    VDD x (IDD4R - IDD3N) x burst         WR    VDD x (IDD4W - IDD3N) x burst
//   REF   VDD x (IDD5 - IDD3N) x tRFC
// per device, times the devices that make up a channel. Currents in mA and times in ns give pJ.
// A part with several supplies (LPDDR4's VDD1, VDD2 and VDDQ; GDDR6's VDD and VPP) repeats each
// term per rail and sums them (DRAMPower v4.1's twoVoltageDomains does the same).
// I/O and termination energy are not in these terms (DRAMPower prices them per pin; no GDDR or
// LPDDR4 pin figures are published: ../shared/docs/energy-params.md, section 4).
#pragma once

#include "model/sim/config_description.h"

#include <cstdint>
#include <stdexcept>
#include <string>

namespace rtsim::model {

// One supply rail of a device: its voltage (V) and datasheet currents (mA), as a DRAM preset
// gives them. A rail of 0 V is absent.
struct DramCurrents {
  double vdd = 0;
  double idd0 = 0;   // one bank activated and precharged, tRC apart
  double idd2n = 0;  // precharge standby: every bank closed
  double idd3n = 0;  // active standby: a row open
  double idd4r = 0;  // burst reads
  double idd4w = 0;  // burst writes
  double idd5 = 0;   // refresh (all banks)
  // Throw std::invalid_argument when a command's energy over the background would be negative:
  // a burst's or a refresh's current below IDD3N; an ACT and its PRE together (their timing's).
  void validate() const;
  void validate_pair(uint32_t tRAS, uint32_t tRC) const;
};

// A channel's devices and their rails: `core` (VDD; LPDDR4's VDD2), `aux` (LPDDR4's VDD1, GDDR6's
// VPP) and `io` (LPDDR4's VDDQ, when the datasheet gives it apart).
struct DramPower {
  uint32_t devices = 1;  // devices per channel (a 64-bit channel of x32 parts: 2)
  DramCurrents core, aux, io;
};

template <class V, class C>
DescribeOf<C, DramCurrents> describe(V& v, C& c) {
  v.number("vdd", c.vdd, 0, 5, "V", "supply voltage (0: no such rail)");
  v.number("idd0", c.idd0, 0, 100000, "mA", "one bank activated and precharged, tRC apart");
  v.number("idd2n", c.idd2n, 0, 100000, "mA", "precharge standby: every bank closed");
  v.number("idd3n", c.idd3n, 0, 100000, "mA", "active standby: a row open");
  v.number("idd4r", c.idd4r, 0, 100000, "mA", "burst reads");
  v.number("idd4w", c.idd4w, 0, 100000, "mA", "burst writes");
  v.number("idd5", c.idd5, 0, 100000, "mA", "refresh (all banks, during tRFC)");
}

template <class V, class C>
DescribeOf<C, DramPower> describe(V& v, C& c) {
  v.number("devices", c.devices, 1, 64, "devices", "devices that make up a channel");
  v.section(
      "core", "the core supply (VDD; LPDDR4's VDD2)", [&] { describe(v, c.core); },
      [&] { c.core.validate(); });
  v.section(
      "aux", "a second supply (LPDDR4's VDD1, GDDR6's VPP); vdd 0: none",
      [&] { describe(v, c.aux); }, [&] { c.aux.validate(); });
  v.section(
      "io", "the I/O supply when given apart (LPDDR4's VDDQ); vdd 0: none",
      [&] { describe(v, c.io); }, [&] { c.io.validate(); });
}

// The timing the terms use, in command-clock cycles of tck_ns.
struct DramEnergyTiming {
  double tck_ns = 0;
  uint32_t tRAS = 0, tRC = 0, tRFC = 0;
  uint32_t burst_cycles = 0;  // the data bus's cycles per burst
  uint32_t devices = 1;       // devices per channel (a 64-bit channel of x32 parts: 2)
};

// What a channel did over a span: commands by class, and its cycles with a row open or with
// every bank closed (the two add up to the span).
struct DramActivity {
  uint64_t activates = 0, precharges = 0, read_bursts = 0, write_bursts = 0, refreshes = 0;
  uint64_t active_cycles = 0, precharged_cycles = 0;
};

// Energy in pJ by command class and the background; they add up to total().
struct DramEnergy {
  double activate = 0, precharge = 0, read = 0, write = 0, refresh = 0, background = 0;
  double total() const { return activate + precharge + read + write + refresh + background; }
  DramEnergy& operator+=(const DramEnergy& o) {
    activate += o.activate;
    precharge += o.precharge;
    read += o.read;
    write += o.write;
    refresh += o.refresh;
    background += o.background;
    return *this;
  }
};

// The Micron method's terms for `activity` (one channel, or channels summed): one rail's, and
// a part's (its rails summed).
DramEnergy dram_energy(const DramCurrents& idd, const DramEnergyTiming& timing,
                       const DramActivity& activity);
DramEnergy dram_energy(const DramPower& power, const DramEnergyTiming& timing,
                       const DramActivity& activity);

}  // namespace rtsim::model
