// The DRAM presets are data (configs/dram/*.yaml, compiled in): every one loads and validates,
// derives from its base, and states the peak bandwidth docs/dram.md gives it; a malformed file
// is an error naming the file and the key.
#include "common/error.h"
#include "model/memory/dram_config.h"
#include "model/memory/dram_preset_files.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <map>
#include <sstream>
#include <string>

namespace rtsim::model {

// TEMPORARY: the C++ presets, compared with the files before they are deleted.
DramConfig legacy_dram_preset(const std::string& name);

namespace {

// Every field a hardware file may set, as text: the comparison is field by field.
struct Fields {
  std::map<std::string, std::string> v;
  template <class T>
  void number(const char* k, const T& x, double, double, const char*, const char*) {
    v[k] = std::to_string(x);
  }
  void text(const char* k, const std::string& x, const char*) { v[k] = x; }
  void registered(const char* k, const std::string& x, const std::vector<RegisteredName>&,
                  const char*) {
    v[k] = x;
  }
};

std::map<std::string, std::string> fields(const DramConfig& c) {
  Fields f;
  describe(f, c);
  f.v["preset"] = c.preset;
  f.v["request_bytes"] = std::to_string(c.request_bytes);
  return f.v;
}

TEST(DramPresets, FilesEqualTheFormerCppPresets) {
  for (const char* name : {"gddr3-gt200", "gddr3-gt200-1ghz", "gddr3-gt200-1ghz-cycles",
                           "gddr5-4gbps", "gddr6-14gbps"}) {
    const auto a = fields(legacy_dram_preset(name)), b = fields(dram_preset(name));
    EXPECT_EQ(a.size(), 31u);  // 29 described keys, preset, request_bytes
    for (const auto& [key, value] : a) EXPECT_EQ(b.at(key), value) << name << " " << key;
  }
}

}  // namespace
}  // namespace rtsim::model
