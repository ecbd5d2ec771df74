// One description per configuration parameter. Each config struct has a describe() function
// template (next to the struct) that names every field once: its key, range, unit and meaning.
// Visitors walk it: the hardware-file reader and the config.json writer
// (config_loader/hw_config.cpp), the range check of validate() (RangeCheck, below) and the
// documentation table (`rtsim params`, the table in configs/README.md). A visitor provides:
//
//   number(key, field, lo, hi, unit, meaning)     an integer or floating-point field in [lo, hi]
//   kib(key, bytes, lo, hi, meaning)              a byte count given in KB (cache sizes)
//   flag(key, field, meaning)                     a bool
//   text(key, field, meaning)                     a string
//   choice(key, field, {{"name", value}, ...}, meaning)    an enum by name
//   registered(key, field, names, meaning)        a string naming one registered implementation
//                                                 (common/registry.h); `names` lists them with
//                                                 their meanings
//   section(key, meaning, body[, check])          a nested map; body() describes its fields, and
//                                                 check() (optional) throws std::invalid_argument
//                                                 when they do not fit together
//   preset(key, config, meaning)                  the DRAM preset a dram section starts from
//
// `field` is a reference, const when the visitor only reads.
#pragma once

#include "common/registry.h"

#include <cstdint>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

namespace rtsim::model {

template <class E>
using Choices = std::initializer_list<std::pair<const char*, E>>;

// describe(V&, C&) is written once for C = S and C = const S: its return type, void only for S.
template <class C, class S>
using DescribeOf = std::enable_if_t<std::is_same_v<std::remove_const_t<C>, S>>;

// Throws std::invalid_argument("<root>.<path>.<key>: expected lo..hi") for the first field out of
// range. A byte count given in KB is checked against the upper bound only: a struct built in code
// (a test's tiny cache) may hold less than the files' smallest unit.
class RangeCheck {
 public:
  explicit RangeCheck(std::string root = "") : prefix_(std::move(root)) {}
  template <class T>
  void number(const char* key, const T& v, double lo, double hi, const char*, const char*) {
    if (!(double(v) >= lo && double(v) <= hi))
      throw std::invalid_argument(path(key) + ": expected " + range(lo, hi));
  }
  void kib(const char* key, uint32_t bytes, double lo, double hi, const char*) {
    if (!(bytes / 1024.0 <= hi))
      throw std::invalid_argument(path(key) + ": expected " + range(lo, hi) + " KB");
  }
  void flag(const char*, bool, const char*) {}
  void text(const char*, const std::string&, const char*) {}
  template <class E>
  void choice(const char*, const E&, Choices<E>, const char*) {}
  void registered(const char* key, const std::string& v, const std::vector<RegisteredName>& names,
                  const char*) {
    for (const RegisteredName& n : names)
      if (n.name == v) return;
    throw std::invalid_argument(path(key) + ": expected " + quoted_names(names) + ", got '" + v +
                                "'");
  }
  template <class E>
  void preset(const char*, const E&, const char*) {}
  template <class F, class G>
  void section(const char* key, const char* meaning, F&& body, G&& check) {
    section(key, meaning, body);
    try {
      check();
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(path(key) + ": " + e.what());
    }
  }
  template <class F>
  void section(const char* key, const char*, F&& body) {
    const std::string saved = prefix_;
    prefix_ = path(key);
    body();
    prefix_ = saved;
  }

 private:
  std::string path(const char* key) const { return prefix_.empty() ? key : prefix_ + "." + key; }
  static std::string range(double lo, double hi) {
    auto n = [](double x) {
      std::string s = std::to_string(x);
      s.erase(s.find_last_not_of('0') + 1);
      if (s.back() == '.') s.pop_back();
      return s;
    };
    return n(lo) + ".." + n(hi);
  }
  std::string prefix_;
};

}  // namespace rtsim::model
