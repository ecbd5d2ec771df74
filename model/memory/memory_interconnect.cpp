#include "model/memory/memory_interconnect.h"

#include "model/sim/report.h"

#include <algorithm>

namespace rtsim::model {

struct WriterStats {
  uint64_t max_in_flight = 0, full_events = 0;
};

// Every WriterStats field, once (model/sim/stats_description.h).
template <class V>
void describe_stats(V& v, const WriterStats& s) {
  v.counter("max_in_flight", s.max_in_flight, "lines",
            "most writes in flight at once (bounded: write_buffer)");
  v.counter("full_events", s.full_events, "count",
            "times a full buffer freed an entry (the writer had to wait)");
}

// A writer's way to the frame buffer: its own source port on the crossbar, and a
// posted-write buffer of `entries` writes in flight (0: unbounded), each freed by its
// acknowledgement from memory.
class MemoryInterconnect::Writer : public sc_core::sc_object,
                                   public LineWriter,
                                   public FillListener {
 public:
  Writer(const char* name, MemoryInterconnect& m, uint32_t source, std::string initiator,
         uint32_t entries)
      : sc_core::sc_object(name),
        m_(m),
        source_(source),
        initiator_(std::move(initiator)),
        entries_(entries) {}
  const char* kind() const override { return "rtsim_line_writer"; }
  void write_line(uint64_t line, const uint8_t* data, Tick when) override {
    if (full()) report_error(kReportInternal, std::string(name()) + ": write to a full buffer");
    const Tick arrived = m_.icnt_.request(source_, m_.port_.port_of(line), m_.line_bytes_, when);
    if (entries_ == 0) return m_.port_.write_line(line, data, arrived, initiator_);
    ++in_flight_;
    stats_.max_in_flight = std::max(stats_.max_in_flight, uint64_t(in_flight_));
    m_.port_.write_line(line, data, arrived, initiator_, this, 0);
  }
  bool full() const override { return entries_ > 0 && in_flight_ >= entries_; }
  void on_room(std::function<void(Tick)> room) override { room_ = std::move(room); }
  void on_fill(uint64_t, uint64_t, Tick when) override {
    const bool was_full = full();
    --in_flight_;
    if (was_full) {
      ++stats_.full_events;
      if (room_) room_(when);
    }
  }
  void register_stats(StatsRegistry& r, const std::string& prefix) const {
    if (entries_ == 0) return;
    StatsRegistrar v(r, prefix);
    describe_stats(v, stats_);
  }

 private:
  MemoryInterconnect& m_;
  uint32_t source_;
  std::string initiator_;
  uint32_t entries_;
  uint32_t in_flight_ = 0;
  std::function<void(Tick)> room_;
  WriterStats stats_;
};

MemoryInterconnect::MemoryInterconnect(sc_core::sc_module_name name, const LinkConfig& link,
                                       const DramConfig& dram, const Clock& clock,
                                       Calendar& calendar, uint32_t l2_banks,
                                       const std::vector<std::string>& writers,
                                       const std::string& reader, uint32_t write_buffer,
                                       PortTarget target)
    : sc_core::sc_module(name),
      port_("port", dram.request_bytes, dram, clock, calendar, target),
      icnt_("icnt", link, clock, l2_banks + uint32_t(writers.size()) + 1, port_.port_count()),
      line_bytes_(dram.request_bytes) {
  const uint32_t reader_source = l2_banks + uint32_t(writers.size());
  record_reader_ = std::make_unique<CrossbarPort>(&icnt_, reader_source, 1, &port_, line_bytes_);
  port_.name_requester(record_reader_.get(), reader);
  for (uint32_t s = 0; s < writers.size(); ++s)
    writers_.push_back(std::make_unique<Writer>(("writer" + std::to_string(s)).c_str(), *this,
                                                l2_banks + s, writers[s], write_buffer));
}

MemoryInterconnect::~MemoryInterconnect() = default;

std::unique_ptr<CrossbarPort> MemoryInterconnect::l2_port(uint32_t first_source, uint32_t banks,
                                                          const std::string& initiator) {
  auto p = std::make_unique<CrossbarPort>(&icnt_, first_source, banks, &port_, line_bytes_);
  port_.name_requester(p.get(), initiator);
  return p;
}

LineWriter& MemoryInterconnect::writer(uint32_t s) { return *writers_.at(s); }

void MemoryInterconnect::register_stats(StatsRegistry& r, const std::string& prefix,
                                        const Tick* span) const {
  icnt_.register_stats(r, prefix + ".icnt", span);
  port_.register_stats(r, prefix + ".port");
  for (size_t s = 0; s < writers_.size(); ++s)
    writers_[s]->register_stats(r, prefix + ".writer" + std::to_string(s));
}

}  // namespace rtsim::model
