// The simulation's calendar. Every unit and the DRAM arm their activations here instead of on
// SystemC events of their own: one SC_METHOD, at each simulated time with work, runs every block
// due then in a fixed order (registration order). Blocks that act in the same cycle therefore
// always act in the same order, whatever observers (progress, traces) exist, and a cycle with N
// active blocks costs one SystemC activation instead of N. One scheduler per process (SystemC
// elaborates once per process); it is created by the first block.
#pragma once

#include "model/memory_interface.h"

#include <systemc>

#include <cstdint>
#include <queue>
#include <vector>

namespace rtsim::model {

class Scheduler : public sc_core::sc_module {
 public:
  class Client {
   public:
    virtual ~Client() = default;
    virtual void activate() = 0;
    Tick armed_at() const { return armed_at_; }

   private:
    friend class Scheduler;
    uint32_t id_ = 0;
    Tick armed_at_ = kUnknown;
  };

  static Scheduler& instance();
  void add(Client* c);
  // Arms `c` for time `at` (now if earlier). A pending activation at or before `at` (and not in
  // the past) stands; a later one is replaced.
  void schedule(Client* c, Tick at);

 private:
  SC_HAS_PROCESS(Scheduler);
  explicit Scheduler(sc_core::sc_module_name name);
  void run();

  struct Entry {
    Tick at;
    uint32_t id;
    bool operator>(const Entry& o) const { return at != o.at ? at > o.at : id > o.id; }
  };
  std::vector<Client*> clients_;
  std::priority_queue<Entry, std::vector<Entry>, std::greater<Entry>> calendar_;
  sc_core::sc_event event_;
  Tick event_at_ = kUnknown;  // time of the pending SystemC notification
  bool running_ = false;
};

}  // namespace rtsim::model
