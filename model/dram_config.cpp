#include "model/dram_config.h"

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

void require_at_least(const std::string& field, uint64_t value, uint64_t min) {
  if (value < min) fail(field, "must be >= " + std::to_string(min) + " (got " + std::to_string(value) + ")");
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

// GT200 as configured in GPGPU-Sim's configs/QuadroFX5800/gpgpusim.config. Its timing line is
// "-gpgpu_dram_timing_opt 8:2:8:12:25:10:35:10:7:6", commented "GDDR3 timing from Samsung
// K4J52324QH-HC12 @ 800MHz", fields {nbk:tCCD:tRRD:tRCD:tRAS:tRP:tRC:CL:WL:tWTR}.
DramConfig gddr3_gt200() {
  DramConfig c;
  c.preset = "gddr3-gt200";
  c.channels = 8;         // -gpgpu_n_mem 8
  c.banks = 8;            // timing field 1, nbk = 8
  c.tCK_ps = 1250;        // -gpgpu_clock_domains 325.0:650.0:650.0:800.0, DRAM clock 800 MHz
  c.tCCD = 2;             // timing field 2
  c.tRRD = 8;             // timing field 3
  c.tRCD = 12;            // timing field 4
  c.tRAS = 25;            // timing field 5
  c.tRP = 10;             // timing field 6
  c.tRC = 35;             // timing field 7
  c.CL = 10;              // timing field 8
  c.WL = 7;               // timing field 9 (unused: no writes)
  c.tWTR = 6;             // timing field 10 (GPGPU-Sim parses it as tCDLR; unused: no writes)
  c.tWR = 13;             // not in the GT200 line (10 fields): GPGPU-Sim's default for the 11th
                          // field, "4:2:8:12:21:13:34:9:4:5:13:1:0:0" (unused: no writes)
  c.burst_length = 4;     // -gpgpu_dram_burst_length 4 (DDR: 2 command cycles of data bus)
  c.bus_bytes = 8;        // -gpgpu_n_mem_per_ctrlr 2 x -gpgpu_dram_buswidth 4
  c.queue_size = 16;      // -gpgpu_dram_sched_queue_size 16 (with -gpgpu_dram_scheduler 1, FR-FCFS)
  c.request_bytes = 32;   // -gpgpu_cache:dl2 64:32:8, 32-byte L2 lines (= one burst); the
                          // accelerator sets its own L2 line size here
  c.row_policy = RowPolicy::kOpenPage;  // GPGPU-Sim's DRAM model keeps rows open
  c.address_mapping = kGt200AddressMapping;  // -gpgpu_mem_addr_mapping, verbatim
  return c;
}

// The same chip's timings in nanoseconds on a 1 GHz command clock (each rounded up to whole
// cycles): a faster GDDR3 part of the same family (K4J52324QH-HC10 is the 1 GHz grade). The
// HC10 datasheet values are not in GPGPU-Sim; this rescaling is our assumption.
DramConfig gddr3_gt200_1ghz() {
  DramConfig c = gddr3_gt200();
  c.preset = "gddr3-gt200-1ghz";
  auto rescale = [&c](uint32_t cycles_at_800) { return uint32_t((uint64_t(cycles_at_800) * c.tCK_ps + 999) / 1000); };
  c.tRRD = rescale(c.tRRD);  // 10 ns
  c.tRCD = rescale(c.tRCD);  // 15 ns
  c.tRAS = rescale(c.tRAS);  // 31.25 -> 32
  c.tRP = rescale(c.tRP);    // 12.5 -> 13
  c.tRC = rescale(c.tRC);    // 43.75 -> 44
  c.CL = rescale(c.CL);      // 12.5 -> 13
  c.WL = rescale(c.WL);
  c.tWTR = rescale(c.tWTR);
  c.tWR = rescale(c.tWR);
  c.tCK_ps = 1000;           // tCCD stays 2: a burst of 4 on a DDR bus
  return c;
}

}  // namespace

void DramConfig::validate() const {
  require_at_least("channels", channels, 1);
  require_pow2("channels", channels);
  require_at_least("banks", banks, 1);
  require_pow2("banks", banks);
  require_at_least("tCK_ps", tCK_ps, 1);
  require_at_least("tRCD", tRCD, 1);
  require_at_least("CL", CL, 1);
  require_at_least("tRP", tRP, 1);
  require_at_least("tRAS", tRAS, 1);
  require_at_least("tRC", tRC, 1);
  require_at_least("tCCD", tCCD, 1);
  require_at_least("tRRD", tRRD, 1);
  if (tRC < tRAS) fail("tRC", "must be >= tRAS (" + std::to_string(tRAS) + "), got " + std::to_string(tRC));
  require_at_least("burst_length", burst_length, 2);
  require_pow2("burst_length", burst_length);
  require_at_least("bus_bytes", bus_bytes, 1);
  require_pow2("bus_bytes", bus_bytes);
  require_at_least("queue_size", queue_size, 1);
  require_pow2("request_bytes", request_bytes);
  if (request_bytes < burst_bytes())
    fail("request_bytes", "must be at least one burst (" + std::to_string(burst_bytes()) + " bytes), got " +
                              std::to_string(request_bytes));
  if (row_policy != RowPolicy::kOpenPage) fail("row_policy", "only the open-page policy is modelled");

  const AddressMapping map(address_mapping, channels);
  auto require_bits = [&](AddressMapping::Field f, char letter, uint64_t count, const std::string& why) {
    if (map.bits(f) != log2u(count))
      fail("address_mapping", std::to_string(map.bits(f)) + " " + field_name(f) + " bits (" + letter + "), but " + why +
                                  " needs " + std::to_string(log2u(count)));
  };
  require_bits(AddressMapping::kByte, 'S', burst_bytes(), "a " + std::to_string(burst_bytes()) + "-byte burst");
  require_bits(AddressMapping::kBank, 'B', banks, std::to_string(banks) + " banks");
  require_bits(AddressMapping::kChannel, 'D', channels, std::to_string(channels) + " channels");
  // A request must stay within one row of one bank of one channel: its offset bits may only be
  // byte or column bits.
  for (uint32_t b = 0; b < log2u(request_bytes); ++b) {
    const AddressMapping::Field f = map.field_of(b);
    if (f != AddressMapping::kByte && f != AddressMapping::kColumn)
      fail("address_mapping", "bit " + std::to_string(b) + " is a " + field_name(f) + " bit, so a " +
                                  std::to_string(request_bytes) +
                                  "-byte request (request_bytes) would not stay in one row");
  }
}

std::vector<std::string> dram_preset_names() { return {"gddr3-gt200", "gddr3-gt200-1ghz"}; }

DramConfig dram_preset(const std::string& name) {
  if (name == "gddr3-gt200") return gddr3_gt200();
  if (name == "gddr3-gt200-1ghz") return gddr3_gt200_1ghz();
  std::string known;
  for (const std::string& n : dram_preset_names()) known += (known.empty() ? "" : ", ") + n;
  throw std::invalid_argument("unknown DRAM preset '" + name + "' (known: " + known + ")");
}

AddressMapping::AddressMapping(const std::string& spec, uint32_t channels) {
  auto bad = [&](const std::string& what) {
    throw std::invalid_argument("DramConfig.address_mapping: " + what + " in '" + spec + "'");
  };
  std::string body = spec;
  int64_t dramid = -1;
  if (spec.rfind("dramid@", 0) == 0) {
    const size_t semi = spec.find(';');
    const std::string num = spec.substr(7, semi == std::string::npos ? std::string::npos : semi - 7);
    if (semi == std::string::npos || num.empty() || num.size() > 2 ||
        !std::all_of(num.begin(), num.end(), [](char c) { return std::isdigit(static_cast<unsigned char>(c)); }))
      bad("expected 'dramid@<bit>;' before the bits");
    dramid = std::stoi(num);
    body = spec.substr(semi + 1);
  }

  std::string seq;  // one letter per bit, most significant first
  for (char c : body) {
    if (c == '.' || c == '|' || c == ' ') continue;
    const char u = char(std::toupper(static_cast<unsigned char>(c)));
    if (std::string("RBCSD0").find(u) == std::string::npos) bad(std::string("unknown character '") + c + "'");
    seq += u;
  }
  if (seq.empty()) bad("no bits");

  uint32_t chan_bits = 0;
  if (dramid >= 0) {
    if (!is_pow2(channels)) bad("dramid@ needs a power-of-two channel count");
    chan_bits = log2u(channels);
    if (seq.find('D') != std::string::npos) bad("'D' bits together with dramid@");
    if (dramid > int64_t(seq.size())) bad("dramid@" + std::to_string(dramid) + " lies above the bits");
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
    const Field f = c == 'R' ? kRow : c == 'B' ? kBank : c == 'C' ? kColumn : c == 'D' ? kChannel : kByte;
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
    if (std::binary_search(positions_[f].begin(), positions_[f].end(), uint8_t(bit))) return Field(f);
  return kRow;  // at or above top_: the row extends upwards
}

DramAddress AddressMapping::decode(uint64_t addr) const {
  auto gather = [&](Field f) {
    uint64_t v = 0;
    const std::vector<uint8_t>& p = positions_[f];
    for (size_t k = 0; k < p.size(); ++k) v |= ((addr >> p[k]) & 1u) << k;
    return v;
  };
  DramAddress a;
  a.channel = uint32_t(gather(kChannel));
  a.bank = uint32_t(gather(kBank));
  a.column = gather(kColumn);
  a.byte = uint32_t(gather(kByte));
  a.row = gather(kRow);
  if (top_ < 64) a.row |= (addr >> top_) << bits(kRow);
  return a;
}

}  // namespace rtsim::model
