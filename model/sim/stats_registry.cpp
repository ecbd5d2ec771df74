#include "model/sim/stats_registry.h"

#include <systemc>

#include <stdexcept>

namespace rtsim::model {

std::string stat_prefix(const sc_core::sc_object& block, const sc_core::sc_object& top) {
  const std::string full = block.name(), prefix = std::string(top.name()) + ".";
  return full.compare(0, prefix.size(), prefix) == 0 ? full.substr(prefix.size()) : full;
}

void StatsRegistry::add(const std::string& name, Entry e) {
  if (!entries_.emplace(name, std::move(e)).second)
    throw std::logic_error("statistic registered twice: " + name);
}

void StatsRegistry::counter(const std::string& name, const uint64_t* value, const std::string& unit,
                            const std::string& description) {
  add(name, Entry{value, {}, unit, description});
}

void StatsRegistry::formula(const std::string& name, std::function<double()> value,
                            const std::string& unit, const std::string& description) {
  add(name, Entry{nullptr, std::move(value), unit, description});
}

void StatsRegistry::reset() {
  // The counters are the blocks' own fields, registered read-only for the reporters; the blocks
  // are not const, and resetting them is the registry's one write.
  for (auto& [name, e] : entries_)
    if (e.counter) *const_cast<uint64_t*>(e.counter) = 0;
  for (const std::function<void()>& f : resets_) f();
}

double StatsRegistry::value(const std::string& name) const {
  const Entry& e = entries_.at(name);
  return e.counter ? double(*e.counter) : e.formula();
}

nlohmann::json StatsRegistry::values() const {
  nlohmann::json root = nlohmann::json::object();
  for (const auto& [name, e] : entries_) {
    nlohmann::json* node = &root;
    size_t start = 0;
    for (size_t dot = name.find('.'); dot != std::string::npos; dot = name.find('.', start)) {
      node = &(*node)[name.substr(start, dot - start)];
      start = dot + 1;
    }
    const std::string leaf = name.substr(start);
    if (e.counter)
      (*node)[leaf] = *e.counter;
    else
      (*node)[leaf] = e.formula();
  }
  return root;
}

std::map<std::string, StatsRegistry::Glossary> StatsRegistry::glossary() const {
  std::map<std::string, Glossary> out;
  for (const auto& [name, e] : entries_) out[name] = {e.unit, e.description};
  return out;
}

}  // namespace rtsim::model
