// The interconnect in front of memory (the sc_module `memory`): one crossbar (`memory.icnt`) from
// every L2 bank, every frame-buffer writer and the record reader to the memory channels
// (GPGPU-Sim's GT200 layout: the L2 banks sit by the memory partitions, so L2 misses cross it to
// reach a channel), and at its far end the TLM-2.0 boundary (`memory.port`,
// model/memory/memory_port.h) whose initiator socket the accelerator binds to its GDDR3 model, or a
// platform to its own memory. A line's channel is the DRAM configuration's address mapping (the
// interconnect routes by it whatever memory model answers). Its clients are named by the caller
// (the initiators of the memory trace).
#pragma once

#include "model/memory/crossbar.h"
#include "model/memory/dram_config.h"
#include "model/memory/line_source.h"
#include "model/memory/memory_port.h"
#include "model/sim/stats_registry.h"
#include "model/sim/time.h"

#include <systemc>

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

namespace rtsim::model {

class MemoryInterconnect : public sc_core::sc_module {
 public:
  // `l2_banks` crossbar sources for the L2s (numbered as the caller assigns them), then one per
  // writer, then the reader. Every transaction is one `dram.request_bytes` line. Writer `s` is
  // `writers[s]` in the memory trace, with `write_buffer` writes in flight at most (0:
  // unbounded); the reader is `reader`. `target`: what the memory port is bound to.
  MemoryInterconnect(sc_core::sc_module_name name, const LinkConfig& link, const DramConfig& dram,
                     const Clock& clock, Calendar& calendar, uint32_t l2_banks,
                     const std::vector<std::string>& writers, const std::string& reader,
                     uint32_t write_buffer = 0, PortTarget target = PortTarget::kPlatform);
  ~MemoryInterconnect() override;

  // The way to memory of an L2 of `banks` banks (its bank b on crossbar source first_source + b);
  // `initiator` names it in the memory trace.
  std::unique_ptr<CrossbarPort> l2_port(uint32_t first_source, uint32_t banks,
                                        const std::string& initiator);
  // Writer `s`'s way to memory (the sc_object `writer<s>`): a posted write of a whole line
  // crosses the crossbar from the writer's port, then goes to memory.
  LineWriter& writer(uint32_t s);
  // The way to read the frame buffer without a cache (records are streamed).
  CrossbarPort& record_reader() { return *record_reader_; }
  MemoryPort& port() { return port_; }
  // <prefix>.icnt.*, <prefix>.port.*, and with a bounded write buffer <prefix>.writer<s>.*.
  void register_stats(StatsRegistry& r, const std::string& prefix, const Tick* span) const;

 private:
  class Writer;

  MemoryPort port_;
  Crossbar icnt_;
  uint32_t line_bytes_;
  std::unique_ptr<CrossbarPort> record_reader_;
  std::vector<std::unique_ptr<Writer>> writers_;
};

}  // namespace rtsim::model
