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
  bool has(const std::string& name) const { return entries_.count(name) > 0; }

 private:
  struct Entry {
    const uint64_t* counter = nullptr;
    std::function<double()> formula;
    std::string unit, description;
  };
  void add(const std::string& name, Entry e);
  std::map<std::string, Entry> entries_;  // sorted: dumps are deterministic
};

}  // namespace rtsim::model
