// Runs a function once when the simulation starts, after elaboration (so every port is bound):
// for a test that hands a block its work the way a block bound to it would.
#pragma once

#include <systemc>

#include <functional>
#include <utility>

namespace rtsim::test {

class AtStart : public sc_core::sc_module {
 public:
  AtStart(sc_core::sc_module_name name, std::function<void()> fn)
      : sc_core::sc_module(name), fn_(std::move(fn)) {
    SC_METHOD(run);  // no sensitivity: runs at initialisation only
  }
  SC_HAS_PROCESS(AtStart);

 private:
  void run() { fn_(); }
  std::function<void()> fn_;
};

}  // namespace rtsim::test
