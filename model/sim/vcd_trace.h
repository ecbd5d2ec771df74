// Not a hardware block: a VCD recording (sc_trace, viewable in GTKWave) of FIFO occupancies, unit
// busy signals and counters (any block's statistics, by their description) over a window of
// cycles. Signals are named after their block's
// hierarchical name (`<top>.trv3.in.occupancy`, `<top>.trv3.busy`), so the VCD's scopes are the
// module tree. Each traced value is an sc_signal that a
// probe writes once per cycle inside the window, half a cycle after the edge (after every unit
// has acted), so outside the window the file holds no changes and the run pays little.
#pragma once

#include "model/sim/periodic_probe.h"
#include "model/sim/ray_fifo.h"
#include "model/sim/time.h"
#include "model/sim/trace_request.h"
#include "model/sim/unit.h"

#include <systemc>

#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace rtsim::model {

class VcdTrace {
 public:
  // Sampling stops at the window's end, or once `pending` says nothing is left to do.
  VcdTrace(const TraceRequest& request, const Clock& clock, std::function<bool()> pending);
  ~VcdTrace();
  void add_fifo(const RayFifo* fifo);
  void add_unit(const Unit* unit);  // 1 in cycles where an operation issued
  void add_counter(const std::string& name, std::function<uint64_t()> value);
  // Every counter a stats struct describes (model/sim/stats_description.h), as <prefix>.<name>;
  // `args` are what its describe_stats takes besides the struct.
  template <class S, class... Args>
  void add_counters(const std::string& prefix, const S& stats, Args&&... args) {
    Counters v{*this, prefix};
    describe_stats(v, stats, std::forward<Args>(args)...);
  }
  // Sets the file's time unit from the resolution (its owner calls it at the end of elaboration).
  void end_of_elaboration();
  // Arms the sampling probe, at the start of the simulation.
  void start();
  void close();  // after the run: completes the file and moves it to its name

 private:
  // The VCD's visitor of a statistics description: counters become signals; formulas, computed
  // from them, are left to the reader.
  struct Counters {
    VcdTrace& trace;
    std::string prefix;
    void counter(const std::string& name, const uint64_t& field, const std::string&,
                 const std::string&) {
      trace.add_counter(prefix + "." + name, [&field] { return field; });
    }
    void formula(const std::string&, std::function<double()>, const std::string&,
                 const std::string&) {}
  };
  bool sample(Tick now);

  TraceRequest request_;
  const Clock& clock_;
  std::function<bool()> pending_;
  std::string temp_base_;
  sc_core::sc_trace_file* file_ = nullptr;
  struct Counter {
    std::unique_ptr<sc_core::sc_signal<uint64_t>> signal;
    std::function<uint64_t()> value;
  };
  struct Busy {
    std::unique_ptr<sc_core::sc_signal<bool>> signal;
    const Unit* unit;
  };
  std::vector<Counter> counters_;
  std::vector<Busy> busy_;
  std::unique_ptr<PeriodicProbe> probe_;
};

}  // namespace rtsim::model
