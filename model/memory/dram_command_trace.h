// The DRAM commands as a CSV (rtsim run --dram-commands): every ACT, PRE, RD, WR and REF the
// controllers issue, one row each, so that an outside DRAM power tool (DRAMPower, or
// scripts/price-dram-trace.py by the same Micron method) can price the very stream our energy
// model prices. Columns: time_ps (the command's clock edge), channel, bank, command (ACT, PRE, RD,
// WR, REF), row (empty for REF), column (RD and WR only), request (the id the controller served;
// empty for a refresh's PRE and REF). Plain CSV with its header row, nothing else: pandas and
// numpy read it as it is.
//
// Rows come in issue order, each channel's in time order, as a power tool reads them: a PRE waits
// for a later command of its channel (not a PRE) at or after its time, or the end (a closed-page
// auto-precharge takes no command cycle: the controller records it with its request's last burst,
// at the later cycle it takes effect). The controller appends to a buffer (set_command_trace) that
// Dram drains here after its activations: a frame of millions of commands holds a few thousand in
// memory. The file is written as FILE.part and named at close(): never a half-written file.
// restart() empties it when the statistics start again (Netlist::reset_stats): its rows are the
// commands the report's dram.* counters count. A window [start_cycle, end_cycle) of accelerator
// cycles keeps the commands whose edge lies in it.
#pragma once

#include "model/memory/dram_controller.h"
#include "model/sim/time.h"
#include "model/sim/trace_request.h"

#include <fstream>
#include <string>
#include <vector>

namespace rtsim::model {

class DramCommandTrace {
 public:
  using Record = DramController::CommandRecord;

  // Opens request.file + ".part" and writes the header (rtsim/trace if it cannot); `clock` is
  // the accelerator's, whose cycles the window counts.
  DramCommandTrace(const TraceRequest& request, const Clock& clock);
  DramCommandTrace(const DramCommandTrace&) = delete;
  DramCommandTrace& operator=(const DramCommandTrace&) = delete;
  ~DramCommandTrace();  // a trace never closed leaves no .part file behind

  // Where the controller appends its commands (DramController::set_command_trace).
  std::vector<Record>* buffer() { return &buffer_; }
  // Writes out the buffer once it holds enough commands to be worth a write.
  void drain_if_full() {
    if (buffer_.size() >= kDrainAt) drain();
  }
  void drain();    // writes out the buffer (a PRE once its channel's time reaches it), empty
  void restart();  // forgets every command so far: the file holds its header only (if open)
  // Writes out the rest and gives the file its name (rtsim/trace if either fails). Once.
  void close();

 private:
  static constexpr size_t kDrainAt = 4096;
  void open();                  // (again) FILE.part, with the header
  void write(const Record& r);  // its row into text_, if inside the window
  // Writes the PREs of `held` (a channel's, in time order) up to `until`.
  void release(std::vector<Record>& held, Tick until);

  TraceRequest request_;
  Clock clock_;
  std::string part_;
  std::ofstream out_;
  bool closed_ = false;
  std::vector<Record> buffer_;
  std::vector<std::vector<Record>> held_;  // by channel: PREs not written yet, in time order
  std::string text_;                       // scratch: the rows of one drain
};

}  // namespace rtsim::model
