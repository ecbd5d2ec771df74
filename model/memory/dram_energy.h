// A DRAM's energy from its command stream, by the Micron method (TN-41-01 "Calculating Memory
// System Power for DDR3", as DRAMPower v4.1 codes it in MemoryPowerModel.cc): the background is
// charged every cycle by the state the banks are in (IDD3N with a row open, IDD2N with all banks
// precharged), and each command adds its increment over the background:
//   ACT   VDD x (IDD0 - IDD3N) x tRAS          PRE   VDD x (IDD0 - IDD2N) x (tRC - tRAS)
//   RD    VDD x (IDD4R - IDD3N) x burst         WR    VDD x (IDD4W - IDD3N) x burst
//   REF   VDD x (IDD5 - IDD3N) x tRFC
// per device, times the devices that make up a channel. Currents in mA and times in ns give pJ.
// I/O and termination energy are not in these terms (DRAMPower prices them per pin; no GDDR or
// LPDDR4 pin figures are published: ../shared/docs/energy-params.md, section 4).
#pragma once

#include <cstdint>

namespace rtsim::model {

// A device's datasheet currents (mA) and supply (V), as a DRAM preset gives them.
struct DramCurrents {
  double vdd = 0;
  double idd0 = 0;   // one bank activated and precharged, tRC apart
  double idd2n = 0;  // precharge standby: every bank closed
  double idd3n = 0;  // active standby: a row open
  double idd4r = 0;  // burst reads
  double idd4w = 0;  // burst writes
  double idd5 = 0;   // refresh (all banks)
};

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
};

// The Micron method's terms for `activity` (one channel, or channels summed).
DramEnergy dram_energy(const DramCurrents& idd, const DramEnergyTiming& timing,
                       const DramActivity& activity);

}  // namespace rtsim::model
