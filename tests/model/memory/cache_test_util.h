// What the cache's tests share: a memory that answers after a set latency (or never, until told),
// a listener that records fills, and small cache configurations.
#pragma once

#include "model/memory/cache.h"

#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cstring>
#include <functional>
#include <vector>

namespace rtsim::model::cache_test {

constexpr Tick kNs = 1000;  // ps

// Memory below the cache: a byte array answering after `latency`, or (kUnknown) later, when the
// test calls the cache's on_fill by hand.
class FakeMemory : public LineSource {
 public:
  struct Request {
    uint64_t line;
    Tick now;
    FillListener* listener;
    uint64_t cookie;
  };
  explicit FakeMemory(size_t size = 1 << 16) : bytes(size) {
    for (size_t i = 0; i < size; ++i) bytes[i] = uint8_t(i * 131 + (i >> 8) * 7 + 1);
  }
  Tick fetch_line(uint64_t line, Tick now, FillListener* listener, uint64_t cookie) override {
    requests.push_back({line, now, listener, cookie});
    return latency == kUnknown ? kUnknown : now + latency;
  }
  const uint8_t* line_data(uint64_t line) const override { return &bytes[line]; }
  uint32_t line_bytes() const override { return 64; }
  bool owns(const uint8_t* p) const { return p >= bytes.data() && p < bytes.data() + bytes.size(); }

  std::vector<uint8_t> bytes;
  Tick latency = 10 * kNs;
  std::vector<Request> requests;
};

struct Fill {
  uint64_t line;
  uint64_t cookie;
  Tick when;
  bool operator==(const Fill& o) const {
    return line == o.line && cookie == o.cookie && when == o.when;
  }
};

std::ostream& operator<<(std::ostream& os, const Fill& f) {
  return os << "{line " << f.line << ", cookie " << f.cookie << ", when " << f.when << "}";
}

class Recorder : public FillListener {
 public:
  void on_fill(uint64_t line, uint64_t cookie, Tick when) override {
    fills.push_back({line, cookie, when});
    if (hook) hook(line, cookie, when);
  }
  std::vector<Fill> fills;
  std::function<void(uint64_t, uint64_t, Tick)> hook;
};

inline CacheConfig tiny(uint32_t size, uint32_t ways, uint32_t hit = 1, uint32_t mshrs = 16) {
  CacheConfig c;
  c.size_bytes = size;
  c.ways = ways;
  c.line_bytes = 64;
  c.hit_latency = hit;
  c.mshrs = mshrs;
  return c;
}

inline void expect_invalid(const CacheConfig& c, const std::string& field) {
  try {
    c.validate();
    ADD_FAILURE() << "accepted a config with a bad " << field;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find(field), std::string::npos) << e.what();
  }
}

}  // namespace rtsim::model::cache_test
