// The timing protocol between the units, the caches, the crossbars and the memory port.
//
// Only misses that reach memory are asynchronous: every other access knows its completion time
// when it is made (a hit, a merge into a fill whose time is known, an L2 hit), so it costs no
// SystemC event. A memory read completes whenever the memory target answers; the memory port
// (model/memory/memory_port.h) hands the response to the calendar at an accelerator clock edge,
// and from there the requester is told through FillListener::on_fill, at the delivery time, up
// the chain port -> L2 -> L1 -> unit.
#pragma once

#include "model/sim/time.h"

#include <systemc>

#include <cstdint>
#include <functional>

namespace rtsim::model {

// Who gets told when a line that was not yet known arrives. `cookie` is the requester's own
// token (a ray id for a unit, a line address for a cache).
class FillListener {
 public:
  virtual ~FillListener() = default;
  virtual void on_fill(uint64_t line_addr, uint64_t cookie, Tick when) = 0;
};

// A level of the memory hierarchy (a cache, a crossbar in front of one, the memory port), as the
// level above or a unit sees it; an sc_interface, so a block may reach one through an sc_port.
class LineSource : public virtual sc_core::sc_interface {
 public:
  // Asks for the line at `line_addr` at time `now`. Returns the time the line is delivered to
  // the requester when that is known now; otherwise kUnknown, and `listener->on_fill` is called
  // at the delivery time with `cookie`.
  virtual Tick fetch_line(uint64_t line_addr, Tick now, FillListener* listener,
                          uint64_t cookie) = 0;
  // The bytes of the line (the simulated memory's contents), valid once it is delivered.
  virtual const uint8_t* line_data(uint64_t line_addr) const = 0;
  virtual uint32_t line_bytes() const = 0;
  // Which of the level's ports serves the line (a cache bank, a DRAM channel): where a crossbar
  // in front of it delivers the request.
  virtual uint32_t port_of(uint64_t /*line_addr*/) const { return 0; }
  virtual uint32_t port_count() const { return 1; }
};

// Posted writes of whole lines to memory (the frame buffer's hit records), through a buffer that
// may bound the writes in flight (issued, not yet acknowledged by memory).
class LineWriter : public virtual sc_core::sc_interface {
 public:
  // Writes line_bytes from `data` (copied) at `line_addr`, leaving the writer at `when`. Only
  // while !full().
  virtual void write_line(uint64_t line_addr, const uint8_t* data, Tick when) = 0;
  // Whether the buffer is full: the writer waits for an acknowledgement before its next write.
  virtual bool full() const = 0;
  // `room(when)` is called when a full buffer gets a free entry at `when` (the writer's wake-up).
  virtual void on_room(std::function<void(Tick)> room) = 0;
};

}  // namespace rtsim::model
