// The DRAM presets are data (configs/dram/*.yaml, compiled in): every one loads and validates,
// derives from its base, and has the peak bandwidth docs/dram.md gives it; a malformed file is
// an error naming the file and the key.
#include "common/error.h"
#include "model/memory/dram_config.h"
#include "model/memory/dram_preset_files.h"
#include "tests/test_util.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <map>
#include <sstream>
#include <string>

namespace rtsim::model {

namespace {

// Every field a hardware file may set, as text: the comparison is field by field.
struct Fields {
  std::map<std::string, std::string> v;
  std::string prefix;  // of a nested section's keys
  template <class T>
  void number(const char* k, const T& x, double, double, const char*, const char*) {
    v[prefix + k] = std::to_string(x);
  }
  void text(const char* k, const std::string& x, const char*) { v[prefix + k] = x; }
  void registered(const char* k, const std::string& x, const std::vector<RegisteredName>&,
                  const char*) {
    v[prefix + k] = x;
  }
  template <class F, class G = void (*)()>
  void section(const char* k, const char*, F&& body, G&& = {}) {
    const std::string saved = prefix;
    prefix += std::string(k) + ".";
    body();
    prefix = saved;
  }
};

std::map<std::string, std::string> fields(const DramConfig& c) {
  Fields f;
  describe(f, c);
  f.v["preset"] = c.preset;
  f.v["request_bytes"] = std::to_string(c.request_bytes);
  return f.v;
}

// Each file: its name is its preset's, it validates, and it is what the source tree holds.
TEST(DramPresets, EveryFileLoadsAndValidates) {
  ASSERT_GE(dram_preset_names().size(), 6u);
  for (const EmbeddedFile& f : dram_preset_files()) {
    const std::string name = std::filesystem::path(f.path).stem().string();
    const DramConfig c = dram_preset(name);
    EXPECT_EQ(c.preset, name);
    EXPECT_NO_THROW(c.validate()) << name;
    EXPECT_EQ(test::slurp(test::source_dir() / f.path), f.text) << f.path << " is not rebuilt";
  }
}

// A derived preset keeps every value of its base that it does not set.
TEST(DramPresets, ADerivedPresetKeepsItsBasesValues) {
  auto g3 = fields(dram_preset("gddr3-gt200")),
       cycles = fields(dram_preset("gddr3-gt200-1ghz-cycles"));
  EXPECT_EQ(cycles["tCK_ps"], "1000");
  for (const auto& [key, value] : g3)
    if (key != "tCK_ps" && key != "preset") {
      EXPECT_EQ(cycles[key], value) << key;
    }
  const DramConfig g5 = dram_preset("gddr5-4gbps"), g6 = dram_preset("gddr6-14gbps");
  EXPECT_EQ(g6.banks, g5.banks);
  EXPECT_EQ(g6.address_mapping, g5.address_mapping);
  EXPECT_EQ(g6.queue_size, 16u);  // from gddr3-gt200, two bases down
}

// docs/dram.md, "Presets", gives each preset's peak: channels x bus bytes x beats per clock / tCK.
TEST(DramPresets, PeakBandwidthIsTheDocumentedOne) {
  std::istringstream doc(test::slurp(test::source_dir() / "docs/dram.md"));
  std::string line;
  int rows = 0;
  while (std::getline(doc, line)) {
    if (line.rfind("| `", 0) != 0 || line.find(" GB/s |") == std::string::npos) continue;
    const std::string name = line.substr(3, line.find('`', 3) - 3);
    const size_t end = line.rfind(" GB/s |"), start = line.rfind(' ', end - 1) + 1;
    const std::string figure = line.substr(start, end - start);
    const size_t dot = figure.find('.');
    const double scale = std::pow(10.0, dot == std::string::npos ? 0 : figure.size() - dot - 1);
    const double peak = dram_preset(name).peak_bandwidth_gbps();
    EXPECT_EQ(std::round(peak * scale) / scale, std::stod(figure)) << name;
    ++rows;
  }
  EXPECT_GE(rows, 5);
}

// LPDDR4-3200 (configs/dram/lpddr4-3200.yaml): x16 channels of 32-byte bursts at 1600 MHz.
TEST(DramPresets, Lpddr4IsEightX16Channels) {
  const DramConfig c = dram_preset("lpddr4-3200");
  EXPECT_EQ(c.burst_bytes(), 32u);
  EXPECT_EQ(c.burst_cycles(), 8u);                  // BL 16 on a DDR bus
  EXPECT_DOUBLE_EQ(c.peak_bandwidth_gbps(), 51.2);  // 8 x 2 bytes x 2 beats / 0.625 ns
  EXPECT_EQ(c.refresh, "all-bank");
  EXPECT_EQ(c.write_to_read(), 42u);  // WL + BL/2 + tCDLR = 18 + 8 + 16
}

void expect_file_error(const std::string& text, const std::vector<std::string>& parts) {
  try {
    read_dram_preset({"configs/dram/broken.yaml", text.c_str()});
    ADD_FAILURE() << "accepted: " << text;
  } catch (const InputError& e) {
    for (const std::string& p : parts)
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
  }
}

// A malformed preset is one error naming the file, the key and what was expected.
TEST(DramPresets, AMalformedFileNamesTheFileAndTheKey) {
  expect_file_error("base: gddr3-gt200\ntRCD: -3\n",
                    {"configs/dram/broken.yaml:2", "tRCD", "expected a value in [1, 1000]"});
  expect_file_error("base: gddr3-gt200\ntRDC: 3\n", {"broken.yaml:2", "tRDC", "unknown key"});
  expect_file_error("base: ddr9\n", {"broken.yaml:1", "base", "unknown DRAM preset 'ddr9'"});
  expect_file_error("base: gddr3-gt200\nrefresh: sometimes\n",
                    {"broken.yaml:2", "refresh", "'none' or 'all-bank'"});
  expect_file_error("base: gddr3-gt200\ntRC: 20\n", {"broken.yaml", "tRC", ">= tRAS"});
  expect_file_error("tRCD: [1\n", {"broken.yaml"});
}

}  // namespace
}  // namespace rtsim::model
