// Named statistics (gem5 style). Components keep their counters in a plain stats struct, so
// counting costs one increment, and register each field here under a dotted name
// ("trv.l1.hits") with its unit ("cycles", "count", "bytes", "ps", "ns", "ratio", "rays", "GB/s")
// and meaning; one reporter dumps them all. Formulas are evaluated at dump time.
#pragma once

#include <nlohmann/json.hpp>

#include <cstdint>
#include <functional>
#include <map>
#include <string>
#include <vector>

namespace sc_core {
class sc_object;
}

namespace rtsim::model {

// A block's statistics prefix: its hierarchical name below `top` ("top.trv3.l1" -> "trv3.l1").
std::string stat_prefix(const sc_core::sc_object& block, const sc_core::sc_object& top);

class StatsRegistry {
 public:
  void counter(const std::string& name, const uint64_t* value, const std::string& unit,
               const std::string& description);
  void formula(const std::string& name, std::function<double()> value, const std::string& unit,
               const std::string& description);

  // Every statistic as a nested JSON object following the dotted names, values only.
  nlohmann::json values() const;
  // name -> unit and description, for the report's glossary (glossary.csv).
  struct Glossary {
    std::string unit, description;
    bool operator==(const Glossary& o) const {
      return unit == o.unit && description == o.description;
    }
  };
  std::map<std::string, Glossary> glossary() const;
  double value(const std::string& name) const;  // throws std::out_of_range for an unknown name
  // Every counter to 0, as gem5's statistics reset: what is counted from now on is a new window's
  // (formulas follow, being computed from the counters), and every reset hook called. Only while
  // the blocks hold no work.
  void reset();
  // For a formula that reads fields of its own (not counters): how they start again.
  void on_reset(std::function<void()> f) { resets_.push_back(std::move(f)); }
  bool has(const std::string& name) const { return entries_.count(name) > 0; }

 private:
  struct Entry {
    const uint64_t* counter = nullptr;
    std::function<double()> formula;
    std::string unit, description;
  };
  void add(const std::string& name, Entry e);
  std::map<std::string, Entry> entries_;  // sorted: dumps are deterministic
  std::vector<std::function<void()>> resets_;
};

}  // namespace rtsim::model
