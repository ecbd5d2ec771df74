#include "model/memory/memory_interconnect.h"

namespace rtsim::model {

// A shading unit's way to write the frame buffer: its own source port on the crossbar.
class MemoryInterconnect::Writer : public sc_core::sc_object, public LineWriter {
 public:
  Writer(const char* name, MemoryInterconnect& m, uint32_t source, std::string initiator)
      : sc_core::sc_object(name), m_(m), source_(source), initiator_(std::move(initiator)) {}
  const char* kind() const override { return "rtsim_line_writer"; }
  void write_line(uint64_t line, const uint8_t* data, Tick when) override {
    const Tick arrived = m_.icnt_.request(source_, m_.port_.port_of(line), m_.line_bytes_, when);
    m_.port_.write_line(line, data, arrived, initiator_);
  }

 private:
  MemoryInterconnect& m_;
  uint32_t source_;
  std::string initiator_;
};

MemoryInterconnect::MemoryInterconnect(sc_core::sc_module_name name, const LinkConfig& link,
                                       const DramConfig& dram, const Clock& clock,
                                       Calendar& calendar, uint32_t l2_banks, uint32_t writers,
                                       bool loosely_timed)
    : sc_core::sc_module(name),
      port_("port", dram.request_bytes, dram, clock, calendar, loosely_timed),
      icnt_("icnt", link, clock, l2_banks + writers + 1, port_.port_count()),
      line_bytes_(dram.request_bytes) {
  record_reader_ =
      std::make_unique<CrossbarPort>(&icnt_, l2_banks + writers, nullptr, &port_, line_bytes_);
  port_.name_requester(record_reader_.get(), "culling");
  for (uint32_t s = 0; s < writers; ++s)
    writers_.push_back(std::make_unique<Writer>(("writer" + std::to_string(s)).c_str(), *this,
                                                l2_banks + s, "shading" + std::to_string(s)));
}

MemoryInterconnect::~MemoryInterconnect() = default;

std::unique_ptr<CrossbarPort> MemoryInterconnect::l2_port(uint32_t first_source,
                                                          const std::string& initiator) {
  auto p = std::make_unique<CrossbarPort>(&icnt_, first_source, nullptr, &port_, line_bytes_);
  port_.name_requester(p.get(), initiator);
  return p;
}

LineWriter& MemoryInterconnect::writer(uint32_t s) { return *writers_.at(s); }

}  // namespace rtsim::model
