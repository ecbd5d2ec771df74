#include "model/memory/dram_config.h"

#include "model/memory/dram_policies.h"

#include <algorithm>
#include <cctype>
#include <stdexcept>

namespace rtsim::model {

namespace {

bool is_pow2(uint64_t v) { return v != 0 && (v & (v - 1)) == 0; }

uint32_t log2u(uint64_t v) {
  uint32_t r = 0;
  while (v > 1) {
    v >>= 1;
    ++r;
  }
  return r;
}

[[noreturn]] void fail(const std::string& field, const std::string& what) {
  throw std::invalid_argument("DramConfig." + field + ": " + what);
}

void require_pow2(const std::string& field, uint64_t value) {
  if (!is_pow2(value)) fail(field, "must be a power of two (got " + std::to_string(value) + ")");
}

const char* field_name(AddressMapping::Field f) {
  switch (f) {
    case AddressMapping::kRow: return "row";
    case AddressMapping::kBank: return "bank";
    case AddressMapping::kColumn: return "column";
    case AddressMapping::kChannel: return "channel";
    default: return "byte";
  }
}

// GT200 as configured in GPGPU-Sim's QuadroFX5800 file, configs/deprecated-cfgs/QuadroFX5800/
// gpgpusim.config (configs/QuadroFX5800/ before 2018; "cfg:N" = its line N at master 90ec3399
// and at 5e8e8497). Its timing line (cfg:71), commented "GDDR3 timing from Samsung
// K4J52324QH-HC12 @ 800MHz", reads at 5e8e8497
//   -gpgpu_dram_timing_opt nbk=8:CCD=2:RRD=8:RCD=12:RAS=25:RP=10:RC=35:CL=10:WL=7:CDLR=6:WR=11
// (until 2011-07 it had ten positional fields, the 10th (6) then read as tWTR; since 2011-08 the
// 10th is tCDLR and an 11th, tWR = 11, follows: GPGPU-Sim derives tWTR = WL + BL/2 + tCDLR = 15).
DramConfig gddr3_gt200() {
  DramConfig c;
  c.preset = "gddr3-gt200";
  c.channels = 8;  // -gpgpu_n_mem 8 (cfg:12)
  c.banks = 8;     // nbk = 8
  // -gpgpu_clock_domains 325.0:650.0:650.0:800.0, DRAM clock 800 MHz (cfg:13)
  c.tCK_ps = 1250;
  c.tCCD = 2;   // CCD
  c.tRRD = 8;   // RRD
  c.tRCD = 12;  // RCD
  c.tRAS = 25;  // RAS
  c.tRP = 10;   // RP
  c.tRC = 35;   // RC (= tRAS + tRP exactly)
  c.CL = 10;    // CL
  c.WL = 7;     // WL
  c.tCDLR = 6;  // CDLR
  c.tWR = 11;   // WR
  // -gpgpu_dram_burst_length 4, -dram_data_command_freq_ratio 2 (cfg:66-67): DDR, 2 command
  // cycles of data bus
  c.burst_length = 4;
  c.bus_bytes = 8;        // -gpgpu_n_mem_per_ctrlr 2 x -gpgpu_dram_buswidth 4 (cfg:64-65)
  c.queue_size = 16;      // -gpgpu_frfcfs_dram_sched_queue_size 16 with -gpgpu_dram_scheduler 1,
                          // FR-FCFS (cfg:54, 60)
  c.input_queue = 8;      // the L2-to-DRAM queue of -gpgpu_dram_partition_queues 8:8:8:8
  c.request_bytes = 32;   // one burst (2 x 4 bytes x BL 4, GPGPU-Sim's dram_atom_size); the
                          // accelerator sets its own L2 line size here
  c.row_policy = "open";  // GPGPU-Sim's DRAM model keeps rows open
  c.address_mapping = kGt200AddressMapping;  // -gpgpu_mem_addr_mapping, verbatim (cfg:69)
  return c;
}

// The same chip's timings in nanoseconds on a 1 GHz command clock (each rounded up to whole
// cycles): a faster GDDR3 part of the same family (K4J52324QH-HC10 is the 1 GHz grade). The
// HC10 datasheet values are not in GPGPU-Sim; this rescaling is our assumption. The derived
// write turnarounds follow from the rescaled WL, tCDLR and tWR with GPGPU-Sim's formulas (BL/2
// and the 2-cycle bus turnaround stay cycles of the data bus).
DramConfig gddr3_gt200_1ghz() {
  DramConfig c = gddr3_gt200();
  c.preset = "gddr3-gt200-1ghz";
  auto rescale = [&c](uint32_t cycles_at_800) {
    return uint32_t((uint64_t(cycles_at_800) * c.tCK_ps + 999) / 1000);
  };
  c.tRRD = rescale(c.tRRD);    // 10 ns
  c.tRCD = rescale(c.tRCD);    // 15 ns
  c.tRAS = rescale(c.tRAS);    // 31.25 -> 32
  c.tRP = rescale(c.tRP);      // 12.5 -> 13
  c.CL = rescale(c.CL);        // 12.5 -> 13
  c.WL = rescale(c.WL);        // 8.75 -> 9
  c.tCDLR = rescale(c.tCDLR);  // 7.5 -> 8
  c.tWR = rescale(c.tWR);      // 13.75 -> 14
  // 43.75 ns rounds up to 44, but tRAS and tRP, rounded up separately, sum to 45: GT200's values
  // satisfy tRC = tRAS + tRP exactly (35 = 25 + 10), so keep that. This changes no timing: a bank
  // cannot ACT again before ACT + tRAS (to PRE) + tRP (to ACT) anyway.
  c.tRC = std::max(rescale(c.tRC), c.tRAS + c.tRP);  // 45
  c.tCK_ps = 1000;                                   // tCCD stays 2: a burst of 4 on a DDR bus
  return c;
}

// GPGPU-Sim's other reading of "GDDR3 at 1 GHz": its timings are counted in DRAM command
// cycles, so setting its DRAM clock domain to 1000 MHz keeps GT200's cycle counts, each now 1 ns
// (tRCD 12 ns, CL 10 ns, ...: a faster part than any K4J52324QH grade).
DramConfig gddr3_gt200_1ghz_cycles() {
  DramConfig c = gddr3_gt200();
  c.preset = "gddr3-gt200-1ghz-cycles";
  c.tCK_ps = 1000;
  return c;
}

// GDDR5 at 4 Gb/s per pin: SK hynix H5GQ1H24AFR (1 Gb, x32) at its 4 Gbps grade, a 1 GHz command
// clock. Its cycle counts as GPGPU-Sim's GTX480 file quotes them ("GDDR5 timing from hynix
// H5GQ1H24AFR", configs/tested-cfgs/SM2_GTX480/gpgpusim.config; run there at 924 MHz) and as
// Ramulator's GDDR5_4000 speed bin lists them at tCK 1 ns (src/GDDR5.h); both agree wherever both
// give a value (docs/dram.md, "Presets", has the table). One x32 chip per channel, as in
// GPGPU-Sim's TITAN files: BL 8 on 4 bytes = 32-byte bursts; 8 channels = a 256-bit bus, 128 GB/s
// (the default preset's peak). The controller (queues, request size) is GT200's, so that the
// presets differ only in the device. Neither source refreshes GDDR5 (GPGPU-Sim models no refresh,
// Ramulator's nREFI is 0).
DramConfig gddr5_4gbps() {
  DramConfig c = gddr3_gt200();
  c.preset = "gddr5-4gbps";
  c.banks = 16;           // nbk=16
  c.bank_groups = 4;      // nbkgrp=4
  c.tCK_ps = 1000;        // Ramulator tCK 1.0 ns (4 Gbps / 4 beats per clock)
  c.tCCD = 2;             // CCD=2, nCCDS 2
  c.tCCD_L = 3;           // CCDL=3, nCCDL 3
  c.tRRD = 6;             // RRD=6, nRRD 6 (no separate same-group value in either source)
  c.tRCD = 12;            // RCD=12, nRCDR 12
  c.tRAS = 28;            // RAS=28, nRAS 28
  c.tRP = 12;             // RP=12, nRP 12
  c.tRC = 40;             // RC=40, nRC 40
  c.CL = 12;              // CL=12, nCL 12
  c.WL = 4;               // WL=4 (Ramulator: nCWL 3)
  c.tCDLR = 5;            // CDLR=5, nWTR 5
  c.tWR = 12;             // WR=12, nWR 12
  c.tRTP = 2;             // RTPL=2, nRTP 2
  c.burst_length = 8;     // -gpgpu_dram_burst_length 8
  c.beats_per_clock = 4;  // -dram_data_command_freq_ratio 4 ("GDDR5 is QDR")
  c.bus_bytes = 4;        // -gpgpu_dram_buswidth 4, one chip per channel (SM6_TITANX)
  c.address_mapping = kGddr16BankAddressMapping;
  return c;
}

// GDDR6 at 14 Gb/s per pin (8 Gb, two x16 channels per chip). Timings: Ramulator 2.0's GDDR6
// table (src/dram/impl/GDDR6.cpp, row GDDR6_2000_1350mV_double) in its cycles of tCK 570 ps
// (CK 1.75 GHz: Micron's MT61K256M32 brief, "Clocking": data rate = 8 x CK). Organisation:
// Micron's brief, "Addressing": 16 banks (BA[3:0]) in 4 groups, 2 KB page = 64 bursts of 32
// bytes (x16, BL 16), refresh 16k per 32 ms. 16 channels = 8 chips = a 256-bit bus, 449 GB/s.
DramConfig gddr6_14gbps() {
  DramConfig c = gddr5_4gbps();
  c.preset = "gddr6-14gbps";
  c.channels = 16;
  c.tCK_ps = 570;         // tCK_ps 570
  c.tCCD = 4;             // nCCDS 4
  c.tCCD_L = 6;           // nCCDL 6
  c.tRRD = 7;             // nRRDS 7
  c.tRRD_L = 7;           // nRRDL 7
  c.tRCD = 26;            // nRCDRD 26
  c.tRAS = 53;            // nRAS 53
  c.tRP = 26;             // nRP 26
  c.tRC = 79;             // nRC 79
  c.CL = 24;              // nCL 24
  c.WL = 6;               // nCWL 6
  c.tCDLR = 9;            // nWTRS 9: WR -> RD = nCWL + nBL + nWTRS, GPGPU-Sim's form
  c.tWR = 26;             // nWR 26
  c.tRTP = 4;             // nRTP 4
  c.burst_length = 16;    // BL 16 (256-bit prefetch per x16 channel)
  c.beats_per_clock = 8;  // data rate = 8 x CK
  c.bus_bytes = 2;        // x16 channel
  c.refresh = "all-bank";
  c.tREFI = 3333;  // nREFI 3333 = 1.9 us (16k refreshes per 32 ms: 1.95 us)
  c.tRFC = 210;    // nRFC 210 = 120 ns
  return c;
}

// Bank groups and the policies: what their fields must satisfy together.
void validate_policies(const DramConfig& c) {
  require_pow2("bank_groups", c.bank_groups);
  if (c.bank_groups > c.banks)
    fail("bank_groups", "must be at most banks (" + std::to_string(c.banks) + "), got " +
                            std::to_string(c.bank_groups));
  // The same bank group is never faster than another one.
  if (c.bank_groups > 1 && c.tCCD_L != 0 && c.tCCD_L < c.tCCD)
    fail("tCCD_L",
         "must be 0 or >= tCCD (" + std::to_string(c.tCCD) + "), got " + std::to_string(c.tCCD_L));
  if (c.bank_groups > 1 && c.tRRD_L != 0 && c.tRRD_L < c.tRRD)
    fail("tRRD_L",
         "must be 0 or >= tRRD (" + std::to_string(c.tRRD) + "), got " + std::to_string(c.tRRD_L));
  // A policy checks the fields it uses when it is built (the names are known by now).
  dram_schedulers().make(c.scheduler, c);
  dram_row_policies().make(c.row_policy, c);
  dram_refresh_policies().make(c.refresh, c);
}

}  // namespace

void DramConfig::validate() const {
  // The ranges of describe() (every count and timing at least 1, bursts at least 2); then what
  // the fields must satisfy together.
  RangeCheck check("DramConfig");
  describe(check, *this);
  require_pow2("channels", channels);
  require_pow2("banks", banks);
  if (tRC < tRAS)
    fail("tRC", "must be >= tRAS (" + std::to_string(tRAS) + "), got " + std::to_string(tRC));
  require_pow2("burst_length", burst_length);
  require_pow2("beats_per_clock", beats_per_clock);
  if (burst_length < beats_per_clock)
    fail("burst_length", "must be at least beats_per_clock (" + std::to_string(beats_per_clock) +
                             "), got " + std::to_string(burst_length));
  validate_policies(*this);
  // GPGPU-Sim's derived write turnarounds subtract WL (gpu-sim.h memory_config::init()); both
  // must stay >= 1 cycle.
  if (WL + 1 >= tRCD)
    fail("WL", "must be < tRCD - 1 (" + std::to_string(tRCD) +
                   " - 1) for an activate-to-write delay tRCD - (WL + 1) >= 1, got " +
                   std::to_string(WL));
  if (WL >= CL + burst_cycles() + kReadToWriteTurnaround)
    fail("WL", "must be < CL + BL/2 + 2 (" +
                   std::to_string(CL + burst_cycles() + kReadToWriteTurnaround) +
                   ") for a read-to-write delay >= 1, got " + std::to_string(WL));
  require_pow2("bus_bytes", bus_bytes);
  require_pow2("request_bytes", request_bytes);
  if (request_bytes < burst_bytes())
    fail("request_bytes", "must be at least one burst (" + std::to_string(burst_bytes()) +
                              " bytes), got " + std::to_string(request_bytes));

  const AddressMapping map(address_mapping, channels);
  auto require_bits = [&](AddressMapping::Field f, char letter, uint64_t count,
                          const std::string& why) {
    if (map.bits(f) != log2u(count))
      fail("address_mapping", std::to_string(map.bits(f)) + " " + field_name(f) + " bits (" +
                                  letter + "), but " + why + " needs " +
                                  std::to_string(log2u(count)));
  };
  require_bits(AddressMapping::kByte, 'S', burst_bytes(),
               "a " + std::to_string(burst_bytes()) + "-byte burst");
  require_bits(AddressMapping::kBank, 'B', banks, std::to_string(banks) + " banks");
  require_bits(AddressMapping::kChannel, 'D', channels, std::to_string(channels) + " channels");
  // A request must stay within one row of one bank of one channel: its offset bits may only be
  // byte or column bits.
  for (uint32_t b = 0; b < log2u(request_bytes); ++b) {
    const AddressMapping::Field f = map.field_of(b);
    if (f != AddressMapping::kByte && f != AddressMapping::kColumn)
      fail("address_mapping", "bit " + std::to_string(b) + " is a " + field_name(f) +
                                  " bit, so a " + std::to_string(request_bytes) +
                                  "-byte request (request_bytes) would not stay in one row");
  }
}

// TEMPORARY: the C++ presets, to compare with configs/dram/ before they go.
DramConfig legacy_dram_preset(const std::string& name) {
  if (name == "gddr3-gt200") return gddr3_gt200();
  if (name == "gddr3-gt200-1ghz") return gddr3_gt200_1ghz();
  if (name == "gddr3-gt200-1ghz-cycles") return gddr3_gt200_1ghz_cycles();
  if (name == "gddr5-4gbps") return gddr5_4gbps();
  if (name == "gddr6-14gbps") return gddr6_14gbps();
  throw std::invalid_argument(name);
}

AddressMapping::AddressMapping(const std::string& spec, uint32_t channels) {
  auto bad = [&](const std::string& what) {
    throw std::invalid_argument("DramConfig.address_mapping: " + what + " in '" + spec + "'");
  };
  std::string body = spec;
  int64_t dramid = -1;
  if (spec.rfind("dramid@", 0) == 0) {
    const size_t semi = spec.find(';');
    const std::string num =
        spec.substr(7, semi == std::string::npos ? std::string::npos : semi - 7);
    if (semi == std::string::npos || num.empty() || num.size() > 2 ||
        !std::all_of(num.begin(), num.end(),
                     [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }))
      bad("expected 'dramid@<bit>;' before the bits");
    dramid = std::stoi(num);
    body = spec.substr(semi + 1);
  }

  std::string seq;  // one letter per bit, most significant first
  for (char c : body) {
    if (c == '.' || c == '|' || c == ' ') continue;
    const char u = char(std::toupper(static_cast<unsigned char>(c)));
    if (std::string("RBCSD0").find(u) == std::string::npos)
      bad(std::string("unknown character '") + c + "'");
    seq += u;
  }
  if (seq.empty()) bad("no bits");

  uint32_t chan_bits = 0;
  if (dramid >= 0) {
    if (!is_pow2(channels)) bad("dramid@ needs a power-of-two channel count");
    chan_bits = log2u(channels);
    if (seq.find('D') != std::string::npos) bad("'D' bits together with dramid@");
    if (dramid > int64_t(seq.size()))
      bad("dramid@" + std::to_string(dramid) + " lies above the bits");
  }

  bool named_seen = false;
  const uint32_t n = uint32_t(seq.size());
  for (uint32_t i = 0; i < n; ++i) {
    const uint32_t bit = n - 1 - i;
    const char c = seq[i];
    if (c == '0') {
      if (named_seen) bad("'0' (unused bit) below a named bit: it would alias addresses");
      continue;
    }
    named_seen = true;
    const uint32_t pos = (dramid >= 0 && bit >= uint32_t(dramid)) ? bit + chan_bits : bit;
    const Field f = c == 'R'   ? kRow
                    : c == 'B' ? kBank
                    : c == 'C' ? kColumn
                    : c == 'D' ? kChannel
                               : kByte;
    positions_[f].push_back(uint8_t(pos));
  }
  for (uint32_t k = 0; k < chan_bits; ++k) positions_[kChannel].push_back(uint8_t(dramid + k));
  for (auto& p : positions_) std::sort(p.begin(), p.end());  // LSB first
  for (const auto& p : positions_)
    if (!p.empty()) top_ = std::max<uint32_t>(top_, p.back() + 1u);
  if (top_ > 64) bad("more than 64 address bits");
}

AddressMapping::Field AddressMapping::field_of(uint32_t bit) const {
  for (int f = 0; f < kFields; ++f)
    if (std::binary_search(positions_[f].begin(), positions_[f].end(), uint8_t(bit)))
      return Field(f);
  return kRow;  // at or above top_: the row extends upwards
}

DramAddress AddressMapping::decode(uint64_t addr) const {
  DramAddress a;
  a.channel = channel(addr);
  a.bank = uint32_t(gather(positions_[kBank], addr));
  a.column = gather(positions_[kColumn], addr);
  a.byte = uint32_t(gather(positions_[kByte], addr));
  a.row = gather(positions_[kRow], addr);
  if (top_ < 64) a.row |= (addr >> top_) << bits(kRow);
  return a;
}

}  // namespace rtsim::model
