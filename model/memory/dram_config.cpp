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
  for (const auto& [rail, currents] :
       {std::pair{"core", &power.core}, {"aux", &power.aux}, {"io", &power.io}}) {
    try {
      currents->validate_pair(tRAS, tRC);
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string("DramConfig.power.") + rail + "." + e.what());
    }
  }
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
