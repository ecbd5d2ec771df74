#include "model/memory/memory_interconnect.h"

namespace rtsim::model {

MemoryInterconnect::MemoryInterconnect(sc_core::sc_module_name name, const LinkConfig& link,
                                       const DramConfig& dram, const Clock& clock,
                                       Calendar& calendar, uint32_t l2_banks, uint32_t writers)
    : sc_core::sc_module(name),
      port_("port", dram.request_bytes, dram, clock, calendar),
      icnt_("icnt", link, clock, l2_banks + writers + 1, port_.port_count()),
      first_writer_(l2_banks),
      line_bytes_(dram.request_bytes) {
  record_reader_ =
      std::make_unique<CrossbarPort>(&icnt_, l2_banks + writers, nullptr, &port_, line_bytes_);
  port_.name_requester(record_reader_.get(), "culling");
}

std::unique_ptr<CrossbarPort> MemoryInterconnect::l2_port(uint32_t first_source,
                                                          const std::string& initiator) {
  auto p = std::make_unique<CrossbarPort>(&icnt_, first_source, nullptr, &port_, line_bytes_);
  port_.name_requester(p.get(), initiator);
  return p;
}

void MemoryInterconnect::write_line(uint32_t writer, uint64_t line, const uint8_t* data, Tick now,
                                    const std::string& initiator) {
  const Tick arrived = icnt_.request(first_writer_ + writer, port_.port_of(line), line_bytes_, now);
  port_.write_line(line, data, arrived, initiator);
}

}  // namespace rtsim::model
