// What a trace records: a file and a window of accelerator cycles [start_cycle, end_cycle). Used
// by the VCD of FIFOs and busy signals (model/sim/vcd_trace.h) and the memory transaction CSV
// (model/memory/memory_port.h).
#pragma once

#include <cstdint>
#include <string>

namespace rtsim::model {

struct TraceRequest {
  std::string file;  // empty = no trace
  uint64_t start_cycle = 0;
  uint64_t end_cycle = 0;
};

}  // namespace rtsim::model
