// DRAM configuration: geometry, timings (in DRAM command-clock cycles), controller queue, request
// size and address mapping, plus the named presets (configs/dram/<name>.yaml, compiled in). The
// timing engine (dram_controller.h) and the SystemC wrapper (dram.h) take a validated DramConfig.
//
// Address mapping syntax (GPGPU-Sim's -gpgpu_mem_addr_mapping, a documented subset):
//   [dramid@N;]<bits>
// <bits> names every address bit from the most to the least significant:
//   R row, B bank, C column (index of a burst within the row), S byte within a burst,
//   D channel, 0 unused; '.', '|' and ' ' are separators and take no bit.
// "dramid@N;" inserts log2(channels) channel bits at bit N and shifts every <bits> bit at or
// above N up by as many (GPGPU-Sim's addrdec.cc does the same); D is then not allowed.
// '0' may only pad the top (above every named bit): address bits above the highest named bit
// extend the row number, so every address of any size maps to a distinct (channel, bank, row,
// column, byte) and nothing aliases. Row, bank and column numbers are the named bits packed in
// order, least significant first.
//
// Consequence for the GT200 string "dramid@8;...0000RRRR.RRRRRRRR.RRBBBCCC.CCCSSSSS", 8 channels:
//   bits 0-4 byte in a 32-byte burst, 5-7 column (low 3), 8-10 channel, 11-13 column (high 3),
//   14-16 bank, 17-30 row, 31+ more row. So 256 consecutive bytes stay in one channel, a row
//   holds 64 bursts = 2 KB per channel, and 16 KB of addresses cover one row in every channel.
#pragma once

#include "model/memory/dram_energy.h"
#include "model/memory/line_source.h"
#include "model/sim/config_description.h"

#include <array>
#include <cstdint>
#include <string>
#include <vector>

namespace rtsim::model {

// A simple alternative, row:bank:channel:column:offset: each channel gets whole 2 KB rows in turn
// (coarse interleaving, for studying channel imbalance).
inline constexpr const char* kRowBankChannelColumnMapping = "RRRRRRRRRRRRRR.BBB.DDD.CCCCCC.SSSSS";

// The controller's policies (docs/dram.md, "Policies"), each a class registered by name in its
// own file (dram_policies.h): a DramConfig names them. The defaults are GT200's: FR-FCFS, open
// page, no refresh. Their names and meanings, for the readers and `rtsim params`:
const std::vector<RegisteredName>& dram_scheduler_names();
const std::vector<RegisteredName>& dram_row_policy_names();
const std::vector<RegisteredName>& dram_refresh_names();

// A default-constructed DramConfig is empty (and fails validate()): start from dram_preset(),
// whose files (configs/dram/) are the one place the numbers and their sources are written down.
struct DramConfig {
  std::string preset;  // name of the preset this came from ("" = hand-made)

  uint32_t channels = 0;  // independent controllers, each with its own command and data bus
  uint32_t banks = 0;     // per channel
  Tick tCK_ps = 0;        // DRAM command-clock period

  // Timings in command-clock cycles.
  uint32_t tRCD = 0;  // ACT -> RD, same bank
  uint32_t CL = 0;    // RD -> first data beat
  uint32_t tRP = 0;   // PRE -> ACT, same bank
  uint32_t tRAS = 0;  // ACT -> PRE, same bank
  uint32_t tRC = 0;   // ACT -> ACT, same bank
  uint32_t tCCD = 0;  // column -> column (RD or WR), same channel (tCCD_S with bank groups)
  uint32_t tRRD = 0;  // ACT -> ACT, different banks of the channel (tRRD_S with bank groups)
  // Bank groups: bank b belongs to group b mod bank_groups (the low bank bits select the group).
  // 1 = none: tCCD and tRRD apply between any two banks and the _L values are unused.
  uint32_t bank_groups = 1;
  uint32_t tCCD_L = 0;  // column -> column, same bank group (0: tCCD)
  uint32_t tRRD_L = 0;  // ACT -> ACT, other banks of the same bank group (0: tRRD)
  uint32_t tRTP = 0;    // RD -> PRE, same bank, beyond the burst (0: BL/2 only, GDDR3's)
  // Write timings, GPGPU-Sim's three base values (the 9th to 11th fields of
  // -gpgpu_dram_timing_opt; names and meanings from gpu-sim.h, memory_config):
  uint32_t WL = 0;     // write latency: WR -> first data beat in
  uint32_t tCDLR = 0;  // last data-in -> RD ("switching from write to read")
  uint32_t tWR = 0;    // last data-in -> PRE, same bank (write recovery)

  // The turnarounds GPGPU-Sim derives from them (src/gpgpu-sim/gpu-sim.h, memory_config::init(),
  // lines 246-254 at commit 011891ab; 208-216 at 90ec3399), with its BL / data_command_freq_ratio
  // = our burst_cycles() (BL 4 on a DDR bus: 2). dram.cc applies them: WR needs RCDWRc and RTWc
  // at 0 and sets WTRc and the bank's WTPc; RD needs WTRc at 0 and sets RTWc; PRE needs WTPc at 0
  // (dram_t::issue_col_command and issue_row_command). Defined only for a config that passed
  // validate() (which keeps the two subtractions >= 1).
  uint32_t write_to_read() const { return WL + burst_cycles() + tCDLR; }  // tWTR: WR -> RD, channel
  // tWTP: WR -> PRE, bank
  uint32_t write_to_precharge() const { return WL + burst_cycles() + tWR; }
  // tRTW: RD -> WR, channel. The read's data end at CL + BL/2; the +2 is GPGPU-Sim's fixed bus
  // turnaround, so a write's data (from WR + WL) start 2 cycles after the read's data end.
  uint32_t read_to_write() const { return CL + burst_cycles() + kReadToWriteTurnaround - WL; }
  uint32_t activate_to_write() const { return tRCD - (WL + 1); }  // tRCDWR: ACT -> WR, bank
  static constexpr uint32_t kReadToWriteTurnaround = 2;

  uint32_t burst_length = 0;  // beats per burst
  // Data beats per command clock: 2 for GDDR3 (DDR), 4 for GDDR5 (QDR: WCK = 2 x CK), 8 for
  // GDDR6 (data rate = 8 x CK). A burst holds the data bus burst_length / beats_per_clock cycles.
  uint32_t beats_per_clock = 2;
  uint32_t bus_bytes = 0;  // data-bus width of one channel

  uint32_t queue_size = 0;  // scheduler queue per channel; excess requests wait in a FIFO
  // That FIFO's size (GPGPU-Sim's L2-to-DRAM queue); full, a request is held back (the memory's
  // END_REQ waits for room). 0: unbounded.
  uint32_t input_queue = 0;
  // The cache line above; one request = request_bytes / burst_bytes bursts
  uint32_t request_bytes = 0;
  // The built-in memory's size, where a platform puts the image and the frame buffer: GT200's
  // (GeForce GTX 280) 1 GiB of GDDR3. Untouched pages cost no host memory.
  uint32_t capacity_mib = 1024;
  std::string scheduler = "fr-fcfs";  // a registered DramScheduler
  std::string row_policy = "open";    // a registered DramRowPolicy
  std::string refresh = "none";       // a registered DramRefreshPolicy
  uint32_t tREFI = 0;                 // REF -> REF, channel (refresh interval)
  uint32_t tRFC = 0;                  // REF -> ACT, channel (refresh cycle time)
  std::string address_mapping;
  // The devices' supplies and currents, which price the command stream (dram_energy.h); each
  // preset's are sourced in its file. They change no timing.
  DramPower power;

  uint32_t burst_bytes() const { return bus_bytes * burst_length; }
  uint32_t burst_cycles() const { return burst_length / beats_per_clock; }
  uint32_t bursts_per_request() const { return request_bytes / burst_bytes(); }
  uint32_t bank_group(uint32_t bank) const { return bank % bank_groups; }
  // The same-group delays as the rules use them: never below the other-group ones.
  uint32_t ccd_same_group() const { return tCCD_L > tCCD ? tCCD_L : tCCD; }
  uint32_t rrd_same_group() const { return tRRD_L > tRRD ? tRRD_L : tRRD; }
  uint32_t read_to_precharge() const { return tRTP > burst_cycles() ? tRTP : burst_cycles(); }
  // channels * bus_bytes * beats_per_clock / tCK, in GB/s (bytes per ns).
  double peak_bandwidth_gbps() const {
    return double(channels) * bus_bytes * beats_per_clock * 1000.0 / double(tCK_ps);
  }
  // The timing the energy terms use (dram_energy.h).
  DramEnergyTiming energy_timing() const {
    return {double(tCK_ps) / 1000.0, tRAS, tRC, tRFC, burst_cycles(), power.devices};
  }

  // Throws std::invalid_argument naming the offending field.
  void validate() const;
};

// The DramConfig fields a hardware file may set, once (model/sim/config_description.h); a file's
// `preset` is applied first, then these override its values. request_bytes is the L2 line size.
template <class V, class C>
DescribeOf<C, DramConfig> describe(V& v, C& c) {
  v.number("channels", c.channels, 1, 64, "channels",
           "independent controllers, each with its own command and data bus");
  v.number("banks", c.banks, 1, 64, "banks", "banks per channel");
  v.number("tCK_ps", c.tCK_ps, 1, 100000, "ps", "command-clock period");
  v.number("tRCD", c.tRCD, 1, 1000, "tCK", "ACT -> RD, same bank");
  v.number("CL", c.CL, 1, 1000, "tCK", "RD -> first data beat");
  v.number("tRP", c.tRP, 1, 1000, "tCK", "PRE -> ACT, same bank");
  v.number("tRAS", c.tRAS, 1, 1000, "tCK", "ACT -> PRE, same bank");
  v.number("tRC", c.tRC, 1, 1000, "tCK", "ACT -> ACT, same bank");
  v.number("tCCD", c.tCCD, 1, 1000, "tCK",
           "column command -> column command, same channel (tCCD_S with bank groups)");
  v.number("tRRD", c.tRRD, 1, 1000, "tCK",
           "ACT -> ACT, other banks of the channel (tRRD_S with bank groups)");
  v.number("bank_groups", c.bank_groups, 1, 64, "groups",
           "bank groups per channel (bank b in group b mod bank_groups); 1: none");
  v.number("tCCD_L", c.tCCD_L, 0, 1000, "tCK",
           "column command -> column command, same bank group (0: tCCD)");
  v.number("tRRD_L", c.tRRD_L, 0, 1000, "tCK", "ACT -> ACT, same bank group (0: tRRD)");
  v.number("tRTP", c.tRTP, 0, 1000, "tCK", "RD -> PRE, same bank (0: BL/2 only)");
  v.number("WL", c.WL, 1, 1000, "tCK", "WR -> first data beat in");
  v.number("tCDLR", c.tCDLR, 1, 1000, "tCK", "last data in -> RD");
  v.number("tWR", c.tWR, 1, 1000, "tCK", "last data in -> PRE, same bank (write recovery)");
  v.number("burst_length", c.burst_length, 2, 64, "beats", "beats per burst");
  v.number("beats_per_clock", c.beats_per_clock, 1, 16, "beats",
           "data beats per command clock (2: DDR, GDDR3; 4: GDDR5; 8: GDDR6)");
  v.number("bus_bytes", c.bus_bytes, 1, 256, "bytes", "data-bus width of one channel");
  v.number("queue_size", c.queue_size, 1, 4096, "requests", "scheduler queue per channel");
  v.number("input_queue", c.input_queue, 0, 1 << 20, "requests",
           "per channel, waiting for the scheduler queue; full, a request is held back "
           "(END_REQ waits); 0: unbounded (ideal)");
  v.text("address_mapping", c.address_mapping, "GPGPU-Sim's address-mapping syntax (above)");
  v.number("capacity_mib", c.capacity_mib, 1, 1 << 20, "MiB",
           "the built-in memory's size (the device's address space for image and frame buffer)");
  v.registered("scheduler", c.scheduler, dram_scheduler_names(),
               "which queued request's next command issues");
  v.registered("row_policy", c.row_policy, dram_row_policy_names(),
               "whether a request's last burst closes its row");
  v.registered("refresh", c.refresh, dram_refresh_names(),
               "when a refresh's PRE and REF go before the scheduler's pick");
  v.number("tREFI", c.tREFI, 0, 1000000, "tCK", "refresh interval (refresh: all-bank)");
  v.number("tRFC", c.tRFC, 0, 100000, "tCK", "REF -> ACT, channel (refresh: all-bank)");
  v.section("power", "the devices' supplies and datasheet currents (energy only)",
            [&] { describe(v, c.power); });
}

// The preset called `name` (configs/dram/NAME.yaml, dram_presets.cpp); unknown names throw
// std::invalid_argument listing the known ones. A malformed file is an InputError naming it.
DramConfig dram_preset(const std::string& name);
std::vector<std::string> dram_preset_names();  // sorted

// Where an address lands.
struct DramAddress {
  uint32_t channel = 0;
  uint32_t bank = 0;
  uint64_t row = 0;
  uint64_t column = 0;  // burst index within the row
  uint32_t byte = 0;    // byte within the burst
};

// A parsed address-mapping string (syntax above).
class AddressMapping {
 public:
  enum Field { kRow, kBank, kColumn, kChannel, kByte, kFields };

  // Throws std::invalid_argument("address_mapping: ...") for a malformed string.
  AddressMapping(const std::string& spec, uint32_t channels);

  DramAddress decode(uint64_t addr) const;
  // decode(addr).channel alone (a crossbar asks it of every request).
  uint32_t channel(uint64_t addr) const { return uint32_t(gather(positions_[kChannel], addr)); }
  uint32_t bits(Field f) const { return uint32_t(positions_[f].size()); }
  // The field that address bit `bit` belongs to (bits at or above top_bit() are row bits).
  Field field_of(uint32_t bit) const;
  uint32_t top_bit() const { return top_; }

 private:
  static uint64_t gather(const std::vector<uint8_t>& positions, uint64_t addr) {
    uint64_t v = 0;
    for (size_t k = 0; k < positions.size(); ++k) v |= ((addr >> positions[k]) & 1u) << k;
    return v;
  }
  std::array<std::vector<uint8_t>, kFields> positions_;  // address bits of each field, LSB first
  uint32_t top_ = 0;                                     // first bit above every named bit
};

}  // namespace rtsim::model
