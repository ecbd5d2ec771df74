// One description per statistic. Each stats struct has a describe_stats() function template next
// to it that names every field once: its name, unit and meaning, and the figures derived from the
// fields. Visitors walk it: the registry (StatsRegistrar: each one under a block's prefix, from
// which report.json and glossary.csv are dumped), the per-type totals (register_totals: a field
// summed over several blocks) and the VCD trace (VcdCounters, model/sim/vcd_trace.h: counters as
// signals). A visitor provides:
//
//   counter(name, field, unit, meaning)   a uint64_t count, `field` a const reference into the
//   struct formula(name, value, unit, meaning)   a figure computed when it is read: value() ->
//   double
//
// A block whose statistics depend on its configuration (a cache's banks) passes what it modelled
// to describe_stats; names are relative ("hits", "bank.stall_cycles").
#pragma once

#include "model/sim/stats_registry.h"

#include <algorithm>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace rtsim::model {

// Registers each statistic under `<prefix>.<name>`.
class StatsRegistrar {
 public:
  StatsRegistrar(StatsRegistry& r, std::string prefix) : r_(r), prefix_(std::move(prefix)) {}
  void counter(const std::string& name, const uint64_t& field, const std::string& unit,
               const std::string& meaning) {
    r_.counter(prefix_ + "." + name, &field, unit, meaning);
  }
  void formula(const std::string& name, std::function<double()> value, const std::string& unit,
               const std::string& meaning) {
    r_.formula(prefix_ + "." + name, std::move(value), unit, meaning);
  }

 private:
  StatsRegistry& r_;
  std::string prefix_;
};

// Collects the counters' addresses by name (formulas are left out): what a total sums.
class CounterAddresses {
 public:
  void counter(const std::string& name, const uint64_t& field, const std::string& unit,
               const std::string& meaning) {
    found.push_back({name, &field, unit, meaning});
  }
  void formula(const std::string&, std::function<double()>, const std::string&,
               const std::string&) {}
  struct Found {
    std::string name;
    const uint64_t* field;
    std::string unit, meaning;
  };
  std::vector<Found> found;
};

// <prefix>.<name> for each of `names`: the counter summed over `parts`, each described by
// describe(visitor, part); the meaning is `meaning` followed by the name.
template <class S, class Describe>
void register_totals(StatsRegistry& r, const std::string& prefix, const std::string& meaning,
                     const std::vector<const S*>& parts, const std::vector<std::string>& names,
                     Describe describe) {
  std::vector<CounterAddresses> each(parts.size());
  for (size_t i = 0; i < parts.size(); ++i) describe(each[i], *parts[i]);
  for (const std::string& name : names) {
    std::vector<const uint64_t*> fields;
    std::string unit;
    for (const CounterAddresses& c : each)
      for (const CounterAddresses::Found& f : c.found)
        if (f.name == name) {
          fields.push_back(f.field);
          unit = f.unit;
        }
    r.formula(
        prefix + "." + name,
        [fields] {
          uint64_t n = 0;
          for (const uint64_t* f : fields) n += *f;
          return double(n);
        },
        unit, meaning + name);
  }
}

}  // namespace rtsim::model
